// Private to src/trace: the ray loop of the Embree tracer's blocker cones (tracer.hpp, "Blocker
// cones"), with its SIMD kernels, apart so that tests can hold the kernels to one another.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/trace/ray.hpp"

#include <cstdint>

namespace shprt::trace_detail {

// Every kConeStride-th ray of a call is a sample, traced first with its blocker recorded.
inline constexpr int kConeStride = 16;

// The kernels of test_cones: the same products in the same order as in_triangle_cone in each
// (no fused multiply-adds), so the same answers. automatic takes the widest this CPU has.
enum class ConeKernel { automatic, portable, sse, avx512 };

// Whether this CPU runs `kernel` (automatic and portable always).
bool cone_kernel_available(ConeKernel kernel);

// The rays between the samples (cone[j] is the cone of sample j's blocker, empty when it had
// none): ray i, between samples j = i / kConeStride and j + 1 (the last sample alone past it), is
// occluded (occluded[i] = 1) when it lies in either's cone; otherwise occluded[i] = 0 and i goes
// to `trace` (room for `count` entries), in increasing order. The samples' own entries are left
// alone. Returns how many went to `trace`. Error(unsupported) for a kernel this CPU lacks.
int test_cones(const TriangleCone* cone, int samples, const Vec3f* dirs, int count,
               std::uint8_t* occluded, std::uint32_t* trace,
               ConeKernel kernel = ConeKernel::automatic);

}  // namespace shprt::trace_detail
