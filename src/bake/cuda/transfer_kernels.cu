// The GPU bake's kernels: the transfer matrix W of Sloan, Kautz & Snyder 2002 (visibility ×
// clamped cosine × Monte Carlo weight, Green 2003), one thread per (vertex, sample), traced over
// the flat BVH with the while-while traversal of Aila & Laine 2009 (trace/flat_bvh.hpp). The
// kernels are thin: every value comes from transfer_sample(), which the CPU tests run on the host.
#include "bake/cuda/transfer_kernels.hpp"

#include "shprt/bake/transfer_sample.hpp"

namespace shprt::cuda {
namespace {

// 128 threads: the traversal keeps a 64-entry stack per thread, so small blocks keep occupancy up
// when the register count is high.
constexpr int kBlock = 128;

__device__ __forceinline__ Vec3f load_direction(const float* dirs, std::uint32_t s) {
    return Vec3f{dirs[3 * s], dirs[3 * s + 1], dirs[3 * s + 2]};
}

// One atomic per warp: the number of lanes whose flag is set.
__device__ __forceinline__ void count_lanes(bool flag, unsigned long long* counter) {
    const unsigned mask = __ballot_sync(0xFFFFFFFFu, flag);
    if ((threadIdx.x & 31u) == 0 && mask != 0) atomicAdd(counter, (unsigned long long)__popc(mask));
}

__global__ void __launch_bounds__(kBlock) transfer_kernel(TransferLaunch p) {
    const std::uint32_t total = p.count * p.samples;
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    bool cast = false;
    if (i < total) {  // no early return: every lane takes part in the warp vote below
        const std::uint32_t s = i / p.count;
        const std::uint32_t vertex = p.first + (i - s * p.count);
        const Vec3f n = p.normals[vertex];
        p.w_t[i] =
            p.local
                ? local_transfer_sample(p.bvh, p.positions[vertex], n, local_axes(n),
                                        load_direction(p.dirs, s), p.weights[s], p.shadowed, cast)
                : transfer_sample(p.bvh, p.positions[vertex], n, load_direction(p.dirs, s),
                                  p.weights[s], p.shadowed, cast, p.hemisphere);
    }
    count_lanes(cast, p.rays);
}

__global__ void __launch_bounds__(kBlock) closest_hit_kernel(TransferLaunch p) {
    const std::uint32_t total = p.count * p.samples;
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    bool cast = false;
    if (i < total) {
        const std::uint32_t s = i / p.count;
        const std::uint32_t vertex = p.first + (i - s * p.count);
        SampleHit hit;
        p.w_t[i] = closest_hit_sample(p.bvh, p.positions[vertex], p.normals[vertex],
                                      load_direction(p.dirs, s), p.weights[s], cast, hit);
        p.hits[i] = hit;
    }
    count_lanes(cast, p.rays);
}

__global__ void __launch_bounds__(kBlock) trace_only_kernel(TransferLaunch p) {
    const std::uint32_t total = p.count * p.samples;
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    bool cast = false, hit = false;
    if (i < total) {
        const std::uint32_t s = i / p.count;
        const std::uint32_t vertex = p.first + (i - s * p.count);
        // Weight 1: the value is the cosine when the ray escapes, 0 when it hits.
        const float value = transfer_sample(p.bvh, p.positions[vertex], p.normals[vertex],
                                            load_direction(p.dirs, s), 1.0f, true, cast);
        hit = cast && value == 0.0f;
    }
    count_lanes(cast, p.rays);
    if (p.occluded) count_lanes(hit, p.occluded);
}

unsigned blocks_for(const TransferLaunch& p) {
    const unsigned long long total = (unsigned long long)p.count * p.samples;
    return (unsigned)((total + kBlock - 1) / kBlock);
}

}  // namespace

cudaError_t launch_transfer(const TransferLaunch& launch, cudaStream_t stream) {
    if (launch.count == 0 || launch.samples == 0) return cudaSuccess;
    transfer_kernel<<<blocks_for(launch), kBlock, 0, stream>>>(launch);
    return cudaGetLastError();
}

cudaError_t launch_closest_hits(const TransferLaunch& launch, cudaStream_t stream) {
    if (launch.count == 0 || launch.samples == 0) return cudaSuccess;
    closest_hit_kernel<<<blocks_for(launch), kBlock, 0, stream>>>(launch);
    return cudaGetLastError();
}

cudaError_t launch_trace_only(const TransferLaunch& launch, cudaStream_t stream) {
    if (launch.count == 0 || launch.samples == 0) return cudaSuccess;
    trace_only_kernel<<<blocks_for(launch), kBlock, 0, stream>>>(launch);
    return cudaGetLastError();
}

}  // namespace shprt::cuda
