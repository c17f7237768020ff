// The one owner of device memory (DeviceBuffer) and of page-locked host memory (PinnedBuffer),
// with an optional tally of the bytes a bake has allocated (for BakeStats::peak_bytes_device).
// Host code of the CUDA backend only.
#pragma once

#include "bake/cuda/cuda_check.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>

namespace shprt::cuda {

// Bytes currently allocated through the buffers that point at it, and the most ever at once.
struct MemoryTally {
    std::uint64_t current = 0;
    std::uint64_t peak = 0;
    void add(std::uint64_t bytes) {
        current += bytes;
        if (current > peak) peak = current;
    }
    void remove(std::uint64_t bytes) { current -= bytes; }
};

// Throws Error(out_of_memory) for cudaErrorMemoryAllocation, else as check(); `what` names the
// allocation ("device" or "pinned host") in the message.
void check_allocation(cudaError_t status, std::size_t bytes, const char* what, const char* file,
                      int line);

// `count` elements of T in device memory (uninitialised). Move-only; frees on destruction
// (cudaFree errors are ignored there: a destructor must not throw).
template <class T>
class DeviceBuffer {
public:
    DeviceBuffer() = default;
    explicit DeviceBuffer(std::size_t count, MemoryTally* tally = nullptr)
        : m_count(count), m_tally(tally) {
        if (count == 0) return;
        void* p = nullptr;
        check_allocation(cudaMalloc(&p, bytes()), bytes(), "device", __FILE__, __LINE__);
        m_data = static_cast<T*>(p);
        if (m_tally) m_tally->add(bytes());
    }
    ~DeviceBuffer() { release(); }
    DeviceBuffer(const DeviceBuffer&) = delete;
    DeviceBuffer& operator=(const DeviceBuffer&) = delete;
    DeviceBuffer(DeviceBuffer&& o) noexcept { swap(o); }
    DeviceBuffer& operator=(DeviceBuffer&& o) noexcept {
        if (this != &o) {
            release();
            swap(o);
        }
        return *this;
    }

    T* data() { return m_data; }
    const T* data() const { return m_data; }
    std::size_t size() const { return m_count; }
    std::size_t bytes() const { return m_count * sizeof(T); }

    // Synchronous copies of `count` ≤ size() elements: complete when they return. (A pageable
    // host-to-device cudaMemcpy may return before its DMA has finished, and the bake's
    // non-blocking streams do not wait for the default stream, hence the device synchronisation.)
    void upload(const T* host, std::size_t count) {
        if (count == 0) return;
        SHPRT_CUDA_CHECK(cudaMemcpy(m_data, host, count * sizeof(T), cudaMemcpyHostToDevice));
        SHPRT_CUDA_CHECK(cudaDeviceSynchronize());
    }
    void download(T* host, std::size_t count) const {
        if (count > 0)
            SHPRT_CUDA_CHECK(cudaMemcpy(host, m_data, count * sizeof(T), cudaMemcpyDeviceToHost));
    }

private:
    void release() noexcept {
        if (m_data) {
            cudaFree(m_data);
            if (m_tally) m_tally->remove(bytes());
        }
        m_data = nullptr;
        m_count = 0;
    }
    void swap(DeviceBuffer& o) noexcept {
        std::swap(m_data, o.m_data);
        std::swap(m_count, o.m_count);
        std::swap(m_tally, o.m_tally);
    }

    T* m_data = nullptr;
    std::size_t m_count = 0;
    MemoryTally* m_tally = nullptr;
};

// `count` elements of T in page-locked host memory, the source or target of asynchronous copies.
template <class T>
class PinnedBuffer {
public:
    PinnedBuffer() = default;
    explicit PinnedBuffer(std::size_t count) : m_count(count) {
        if (count == 0) return;
        void* p = nullptr;
        check_allocation(cudaMallocHost(&p, count * sizeof(T)), count * sizeof(T), "pinned host",
                         __FILE__, __LINE__);
        m_data = static_cast<T*>(p);
    }
    ~PinnedBuffer() {
        if (m_data) cudaFreeHost(m_data);
    }
    PinnedBuffer(const PinnedBuffer&) = delete;
    PinnedBuffer& operator=(const PinnedBuffer&) = delete;
    PinnedBuffer(PinnedBuffer&& o) noexcept
        : m_data(std::exchange(o.m_data, nullptr)), m_count(std::exchange(o.m_count, 0)) {}
    PinnedBuffer& operator=(PinnedBuffer&& o) noexcept {
        if (this != &o) {
            if (m_data) cudaFreeHost(m_data);
            m_data = std::exchange(o.m_data, nullptr);
            m_count = std::exchange(o.m_count, 0);
        }
        return *this;
    }

    T* data() { return m_data; }
    const T* data() const { return m_data; }
    std::size_t size() const { return m_count; }
    std::size_t bytes() const { return m_count * sizeof(T); }

private:
    T* m_data = nullptr;
    std::size_t m_count = 0;
};

// A CUDA event, created on construction (timing enabled) and destroyed with the object.
class Event {
public:
    Event() { SHPRT_CUDA_CHECK(cudaEventCreate(&m_event)); }
    ~Event() {
        if (m_event) cudaEventDestroy(m_event);
    }
    Event(const Event&) = delete;
    Event& operator=(const Event&) = delete;
    Event(Event&& o) noexcept : m_event(std::exchange(o.m_event, nullptr)) {}
    Event& operator=(Event&&) = delete;

    cudaEvent_t get() const { return m_event; }
    void record(cudaStream_t stream) { SHPRT_CUDA_CHECK(cudaEventRecord(m_event, stream)); }

private:
    cudaEvent_t m_event = nullptr;
};

// Milliseconds between two recorded, completed events, in seconds.
double elapsed_seconds(const Event& from, const Event& to);

}  // namespace shprt::cuda
