// Launchers of the GPU bake's kernels (transfer_kernels.cu), callable from host .cpp files. Each
// kernel is thin: its body calls transfer_sample() (bake/transfer_sample.hpp), the SHPRT_HD code
// the CPU tests run on the host. Launchers return the launch's cudaError_t for the caller to check
// (nvcc cannot compile shprt::Error's fmt-based header).
#pragma once

#include "shprt/bake/transfer_sample.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/trace/flat_bvh.hpp"

#include <cuda_runtime_api.h>

#include <cstdint>

namespace shprt::cuda {

// One launch over the (vertex, sample) pairs of vertices [first, first + count) and all S samples:
// thread i handles vertex first + i % count and sample i / count, so a warp is 32 consecutive
// vertices and one direction (nearly parallel rays, agreeing horizons). All pointers are device
// pointers. Precondition: count·samples < 2^31.
struct TransferLaunch {
    FlatBvhView bvh;  // device arrays; may be empty when !shadowed
    const Vec3f* positions;
    const Vec3f* normals;
    const float* dirs;     // 3·S: xyz per direction
    const float* weights;  // S
    std::uint32_t first = 0, count = 0, samples = 0;
    bool shadowed = true;
    bool hemisphere = false;  // glossy transfer: no cosine (transfer_sample)
    bool local = false;       // a local set: dirs in each receiver's frame (local_transfer_sample)
    float* w_t = nullptr;     // S × count, sample-major: w_t[s·count + v]
    unsigned long long* rays = nullptr;      // += rays cast (must be non-null)
    unsigned long long* occluded = nullptr;  // trace-only: += rays that hit something
    SampleHit* hits = nullptr;  // closest hits: S × count, sample-major: hits[s·count + v]
};

// W[v][s] = transfer_sample(...) into w_t, and the rays cast into *rays. Asynchronous on `stream`.
cudaError_t launch_transfer(const TransferLaunch& launch, cudaStream_t stream);

// Interreflected transfer: W as launch_transfer with shadowed (from the closest hit:
// closest_hit_sample) and each sample's hit record into `hits`. Asynchronous on `stream`.
cudaError_t launch_closest_hits(const TransferLaunch& launch, cudaStream_t stream);

// The raw traversal rate kernel: traces the same rays (n·w > 0) and only counts them and their
// hits (*rays, *occluded); w_t and weights are not used.
cudaError_t launch_trace_only(const TransferLaunch& launch, cudaStream_t stream);

}  // namespace shprt::cuda
