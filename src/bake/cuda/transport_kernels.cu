// The GPU's build of a block of the transport operator A (transport_kernels.hpp): one thread per
// (vertex, sample) for the entries, cub's radix sort (stable: entries of one row and column stay
// in ray order) and exclusive scan in between, one thread per sorted entry for the run sums and
// the compaction, one per row for the row starts. The arithmetic is transport_build.hpp's.
#include "bake/cuda/transport_kernels.hpp"

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>

namespace shprt::cuda {
namespace {

constexpr int kBlock = 256;

unsigned blocks_for(std::uint64_t threads) {
    return static_cast<unsigned>((threads + kBlock - 1) / kBlock);
}

__global__ void __launch_bounds__(kBlock)
    entries_kernel(TransportBuildView view, std::uint64_t* keys, std::uint32_t* order,
                   float* values) {
    const std::uint64_t i = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < std::uint64_t(view.count) * view.samples)
        transport_sample_entries(view, static_cast<std::uint32_t>(i), keys, order, values);
}

__global__ void __launch_bounds__(kBlock)
    run_sum_kernel(std::uint32_t n, const std::uint64_t* keys, const std::uint32_t* order,
                   const float* values, std::uint64_t no_entry, float* sums, std::uint32_t* kept) {
    const std::uint32_t p = blockIdx.x * blockDim.x + threadIdx.x;
    if (p < n) transport_run_sum(p, n, keys, order, values, no_entry, sums, kept);
}

__global__ void __launch_bounds__(kBlock)
    compact_kernel(TransportBuildLaunch l, std::uint32_t n, const std::uint64_t* keys) {
    const std::uint32_t p = blockIdx.x * blockDim.x + threadIdx.x;
    if (p < n)
        transport_compact(p, keys, l.kept, l.slot, l.sums, l.view.vertices, l.out_keys, l.column,
                          l.value[0], l.value[1], l.value[2]);
    if (p == 0) *l.nnz = n ? l.slot[n - 1] + l.kept[n - 1] : 0;
}

__global__ void __launch_bounds__(kBlock) row_start_kernel(TransportBuildLaunch l) {
    const std::uint32_t j = blockIdx.x * blockDim.x + threadIdx.x;
    if (j <= l.view.count)
        l.row_start[j] = transport_row_start(j, l.out_keys, *l.nnz, l.view.vertices);
}

}  // namespace

cudaError_t transport_build_temp_bytes(std::size_t entries, std::size_t& bytes) {
    const int n = static_cast<int>(entries);
    std::size_t sort_bytes = 0, scan_bytes = 0;
    cub::DoubleBuffer<std::uint64_t> keys(nullptr, nullptr);
    cub::DoubleBuffer<std::uint32_t> order(nullptr, nullptr);
    if (const cudaError_t e =
            cub::DeviceRadixSort::SortPairs(nullptr, sort_bytes, keys, order, n, 0, 64);
        e != cudaSuccess)
        return e;
    if (const cudaError_t e =
            cub::DeviceScan::ExclusiveSum(nullptr, scan_bytes, static_cast<std::uint32_t*>(nullptr),
                                          static_cast<std::uint32_t*>(nullptr), n);
        e != cudaSuccess)
        return e;
    bytes = std::max(sort_bytes, scan_bytes);
    return cudaSuccess;
}

cudaError_t launch_transport_build(const TransportBuildLaunch& l, cudaStream_t stream) {
    const std::uint64_t n64 = l.view.entries();
    const std::uint32_t n = static_cast<std::uint32_t>(n64);
    if (n64 != 0) {
        entries_kernel<<<blocks_for(n64 / 3), kBlock, 0, stream>>>(l.view, l.keys[0], l.order[0],
                                                                   l.values);
        if (const cudaError_t e = cudaGetLastError(); e != cudaSuccess) return e;
    }
    cub::DoubleBuffer<std::uint64_t> keys(l.keys[0], l.keys[1]);
    cub::DoubleBuffer<std::uint32_t> order(l.order[0], l.order[1]);
    std::size_t temp_bytes = l.temp_bytes;
    if (n != 0) {
        if (const cudaError_t e = cub::DeviceRadixSort::SortPairs(
                l.temp, temp_bytes, keys, order, static_cast<int>(n), 0, transport_key_bits(l.view),
                stream);
            e != cudaSuccess)
            return e;
        run_sum_kernel<<<blocks_for(n), kBlock, 0, stream>>>(
            n, keys.Current(), order.Current(), l.values, l.view.no_entry(), l.sums, l.kept);
        if (const cudaError_t e = cudaGetLastError(); e != cudaSuccess) return e;
        temp_bytes = l.temp_bytes;
        if (const cudaError_t e = cub::DeviceScan::ExclusiveSum(l.temp, temp_bytes, l.kept, l.slot,
                                                                static_cast<int>(n), stream);
            e != cudaSuccess)
            return e;
    }
    compact_kernel<<<std::max(1u, blocks_for(n)), kBlock, 0, stream>>>(l, n, keys.Current());
    if (const cudaError_t e = cudaGetLastError(); e != cudaSuccess) return e;
    row_start_kernel<<<blocks_for(std::uint64_t(l.view.count) + 1), kBlock, 0, stream>>>(l);
    return cudaGetLastError();
}

}  // namespace shprt::cuda
