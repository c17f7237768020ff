// The GPU's build of one block of the transport operator A (transport_build.hpp's four steps)
// from a chunk's closest-hit records, callable from host .cpp files. The kernels are thin: each
// calls one SHPRT_HD step of transport_build.hpp, which the CPU tests run on the host; between
// them, cub's stable radix sort of the keys and its exclusive scan of the kept flags.
#pragma once

#include "shprt/bake/transport_build.hpp"

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

namespace shprt::cuda {

// Device buffers of one build; `entries` ≥ view.entries() elements each (×3 for values and sums),
// row_start view.count + 1. All pointers are device pointers.
struct TransportBuildLaunch {
    TransportBuildView view;       // device arrays
    std::uint64_t* keys[2] = {};   // the sort's double buffer
    std::uint32_t* order[2] = {};  // the entries' indices, sorted with the keys
    float* values = nullptr;       // 3 per entry
    float* sums = nullptr;         // 3 per entry
    std::uint32_t* kept = nullptr;
    std::uint32_t* slot = nullptr;
    std::uint64_t* out_keys = nullptr;  // the block's keys, for the row starts
    std::int32_t* row_start = nullptr;  // the block's CSR arrays
    std::int32_t* column = nullptr;
    float* value[3] = {};
    std::uint32_t* nnz = nullptr;  // one: the block's non-zeros
    void* temp = nullptr;          // cub's temporary storage
    std::size_t temp_bytes = 0;    // ≥ transport_build_temp_bytes(entries)
};

// The temporary storage cub needs for a build of up to `entries` entries (< 2^31), into `bytes`.
cudaError_t transport_build_temp_bytes(std::size_t entries, std::size_t& bytes);

// Enqueues the whole build on `stream`: the block's CSR arrays and *nnz are written when it runs.
cudaError_t launch_transport_build(const TransportBuildLaunch& launch, cudaStream_t stream);

}  // namespace shprt::cuda
