// Where a bake puts its results: a sink of rows. (It lives in transfer/, below bake/ and io/, so
// that io/ can offer a sink too: the streaming .shprt writer, io/shprt_stream.hpp.) A row is one
// receiver's transfer, layout.floats_per_receiver() floats (transfer/transfer.hpp); the bake hands
// a sink the rows of consecutive receivers, chunk by chunk, as they are final. Three sinks come
// with the library:
//
//   HostSink        rows in host memory, the range's rows contiguous (what bake() returns);
//   FileRegionSink  rows written with pwrite into a region of an open file, as float32 — the
//                   seam for streaming output, shards and MPI ranks: no V×K array in memory;
//   DeviceSink      a CUDA device buffer (e.g. an OpenGL buffer mapped through CUDA–GL interop,
//                   bake/gpu_gl_interop.hpp): the GPU bake writes the rows in place.
//
// (bake/background.hpp adds ChunkQueue, the sink of a bake shown while it refines.)
//
// Threads: write() may be called concurrently from several worker threads, for disjoint ranges,
// in any order; begin() and finish() are called by the thread that called bake().
#pragma once

#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace shprt {

// Receivers [first, first + count) of a domain's numbering: what a sink holds, or a checkpoint
// (io/checkpoint.hpp) or a resumed bake (bake/remaining.hpp) has done.
struct ReceiverSpan {
    std::size_t first = 0;
    std::size_t count = 0;
    bool operator==(const ReceiverSpan&) const = default;
};

// The spans of [first, first + count) not covered by `done` (in any order, possibly overlapping,
// possibly reaching outside), in increasing order.
std::vector<ReceiverSpan> remaining_spans(std::size_t first, std::size_t count,
                                          std::vector<ReceiverSpan> done);

// "Every receiver at most once": the indices of `spans` in increasing order of first receiver
// (ties by index), and the first two of that order that share a receiver, if any. Empty spans
// share nothing. merge_shprt_parts (parts of a sharded bake) and CheckpointFile::resume (a
// checkpoint's records) refuse what overlaps.
struct SpanOrder {
    std::vector<std::size_t> order;
    std::optional<std::pair<std::size_t, std::size_t>> overlap;  // (earlier, later) in spans
};
SpanOrder order_spans(const std::vector<ReceiverSpan>& spans);

class TransferSink {
public:
    virtual ~TransferSink() = default;

    // Called once before any row: the layout of every row and the receiver range to come,
    // [first, first + count). Throws to refuse (the bake then fails with that error).
    virtual void begin(const TransferLayout& layout, std::size_t first, std::size_t count) = 0;
    // Host memory where the bake may compute the rows of receivers [first, first + count) in
    // place (a sub-range of the begun range), saving a copy; nullptr (the default) means "hand
    // them to write()".
    virtual float* host_rows(std::size_t /*first*/, std::size_t /*count*/) { return nullptr; }
    // Device memory (CUDA, the bake's device) for all rows of the begun range, contiguous; the GPU
    // bake then writes there and calls write() with rows = nullptr. nullptr (the default): none.
    virtual float* device_rows() { return nullptr; }
    // The rows of receivers [first, first + count) are final: layout.floats(count) floats at
    // `rows`, valid only during the call (the pointer host_rows() gave, when it gave one), or
    // nullptr when they were written to device_rows().
    virtual void write(std::size_t first, std::size_t count, const float* rows) = 0;
    // An error-bounded bake (BakeOptions::target_error) calls begin_estimates() once after
    // begin(), then hands over with each write() each of the same receivers' sample count and
    // estimated error, valid only during the call (from any worker thread, as write()). The
    // default drops them.
    virtual void begin_estimates() {}
    virtual void write_estimates(std::size_t /*first*/, std::size_t /*count*/,
                                 const std::uint32_t* /*samples*/, const float* /*errors*/) {}
    // Called once after the last write() of a bake that succeeded (not after a failure or a
    // cancel).
    virtual void finish() {}
};

// Rows in host memory: after the bake, rows() holds layout.floats(count) floats for the begun
// range, receiver first at rows()[0].
class HostSink final : public TransferSink {
public:
    void begin(const TransferLayout& layout, std::size_t first, std::size_t count) override;
    float* host_rows(std::size_t first, std::size_t count) override;
    void write(std::size_t first, std::size_t count, const float* rows) override;
    void begin_estimates() override;
    void write_estimates(std::size_t first, std::size_t count, const std::uint32_t* samples,
                         const float* errors) override;

    const TransferLayout& layout() const { return m_layout; }
    std::size_t first() const { return m_first; }
    const std::vector<float>& rows() const { return m_rows; }
    std::vector<float> take_rows() { return std::move(m_rows); }
    // An error-bounded bake's estimates, one per receiver of the range, moved into `set`'s
    // receiver_samples and receiver_error (empty for other bakes).
    void take_estimates(TransferSet& set) {
        set.receiver_samples = std::move(m_samples);
        set.receiver_error = std::move(m_errors);
    }

private:
    TransferLayout m_layout;
    std::size_t m_first = 0, m_count = 0;
    std::vector<float> m_rows;
    std::vector<std::uint32_t> m_samples;
    std::vector<float> m_errors;
};

// Rows as float32 (little-endian, this host's floats) into the file `fd` (open for writing,
// owned by the caller) at byte `offset` + 4·layout.floats(receiver − first): the region of
// 4·layout.floats(count) bytes that begins at `offset`. begin() fails (Error(invalid_argument))
// when the layout's encoding is not f32; write() throws Error(io) when pwrite fails.
class FileRegionSink final : public TransferSink {
public:
    FileRegionSink(int fd, std::uint64_t offset) : m_fd(fd), m_offset(offset) {}
    void begin(const TransferLayout& layout, std::size_t first, std::size_t count) override;
    void write(std::size_t first, std::size_t count, const float* rows) override;
    // Bytes of the region (valid after begin()).
    std::uint64_t region_bytes() const { return m_bytes; }

private:
    int m_fd;
    std::uint64_t m_offset;
    std::uint64_t m_bytes = 0;
    TransferLayout m_layout;
    std::size_t m_first = 0, m_count = 0;
};

// A CUDA device buffer of at least layout.floats(count) floats (`capacity_floats`), on the
// device of the bake (BakeOptions::device_index). Only the GPU bake can fill it: a CPU bake into
// a DeviceSink fails with Error(unsupported). begin() checks the capacity.
class DeviceSink final : public TransferSink {
public:
    DeviceSink(float* device_pointer, std::size_t capacity_floats)
        : m_device(device_pointer), m_capacity(capacity_floats) {}
    void begin(const TransferLayout& layout, std::size_t first, std::size_t count) override;
    float* device_rows() override { return m_device; }
    void write(std::size_t first, std::size_t count, const float* rows) override;
    // Chunks written so far (the GPU bake reports each).
    std::size_t chunks_written() const { return m_chunks; }

private:
    float* m_device;
    std::size_t m_capacity;
    std::size_t m_first = 0, m_count = 0;
    std::size_t m_chunks = 0;  // written only by the GPU bake's calling thread
};

}  // namespace shprt
