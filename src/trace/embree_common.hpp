// Private to src/trace: the Embree device wrapper shared by the Embree tracer and the flat-BVH
// builder, input validation of meshes for tracing, and the FTZ/DAZ scope.
#pragma once

#include "shprt/core/tsan.hpp"
#include "shprt/scene/mesh.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#if defined(__SSE__) || defined(__x86_64__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#define SHPRT_HAS_MXCSR 1
#else
#define SHPRT_HAS_MXCSR 0
#endif

namespace shprt::trace_detail {

// An RTCDevice configured not to fight the caller's threads (see tracer.hpp, "Embree threading"),
// whose error callback records the first error; check() turns it into shprt::Error. Errors are
// recorded rather than thrown from the callback because the callback runs inside Embree's C API,
// which must not be unwound through.
class EmbreeDevice {
public:
    EmbreeDevice();
    ~EmbreeDevice();
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;

    RTCDevice get() const { return m_device; }
    // Bytes Embree holds through this device now, and the most it held at once (its memory
    // monitor callback).
    std::size_t bytes_now() const {
        return static_cast<std::size_t>(std::max<long long>(m_bytes, 0));
    }
    std::size_t bytes_peak() const { return static_cast<std::size_t>(m_peak_bytes.load()); }
    // Throws shprt::Error with "<what>: Embree error (<code>): <message>" if Embree reported an
    // error since the last check (code out_of_memory / invalid_argument for Embree's, else
    // unsupported), and clears it.
    void check(const char* what);

    // Embree calls the memory monitor on its build threads, TBB workers whose hand-offs
    // ThreadSanitizer cannot see: each call is a task of this (tsan::TaskScope), and the calls
    // into Embree that may build (commits, rtcBuildBVH) fork and join it (tsan::ForkJoinScope).
    const tsan::ForkJoin& monitor() const { return m_monitor; }

private:
    static void on_error(void* user, RTCError code, const char* message);
    static bool on_memory(void* user, ssize_t bytes, bool post);

    RTCDevice m_device = nullptr;
    std::mutex m_mutex;
    RTCError m_code = RTC_ERROR_NONE;
    std::string m_message;
    std::atomic<long long> m_bytes{0}, m_peak_bytes{0};
    [[no_unique_address]] tsan::ForkJoin m_monitor;
};

// The device option string; exposed for the benchmark's record.
const char* embree_device_config();

// Checks a mesh for tracing: at least one triangle, every index < vertex_count, every position
// finite, at least one triangle of non-zero area. Throws shprt::Error(invalid_argument) naming
// mesh.source (or "<unnamed mesh>") and the offending triangle/vertex. Returns the number of
// non-degenerate triangles.
std::size_t validate_mesh(const Mesh& mesh);

// True for a triangle no ray can hit: repeated vertex indices or exactly collinear vertices (the
// cross product of its edges, evaluated in double, is zero).
bool is_degenerate(const Mesh& mesh, std::size_t triangle);

// Sets FTZ and DAZ on the calling thread for the scope's lifetime and restores the caller's
// MXCSR after: Embree needs them for speed; the caller's own float mode is left as it was.
class FtzDazScope {
public:
#if SHPRT_HAS_MXCSR
    FtzDazScope() : m_saved(_mm_getcsr()) {
        _mm_setcsr(m_saved | _MM_FLUSH_ZERO_ON | _MM_DENORMALS_ZERO_ON);
    }
    ~FtzDazScope() { _mm_setcsr(m_saved); }

private:
    unsigned m_saved;
#endif
};

}  // namespace shprt::trace_detail
