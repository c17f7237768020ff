// The process's GPU context for bakes on one device: two non-blocking streams, one cuBLAS handle
// per stream with its own workspace (cuBLAS results are reproducible run to run only when streams
// do not share a workspace). Created on first use and never destroyed: CUDA may already be shut
// down when static destructors run, and the driver frees everything at process exit.
#pragma once

#include "bake/cuda/cuda_check.hpp"

#include <cstdint>
#include <mutex>
#include <string>

namespace shprt::cuda {

inline constexpr int kStreams = 2;

struct GpuContext {
    int device = 0;
    std::string name;
    cudaStream_t streams[kStreams] = {};
    cublasHandle_t blas[kStreams] = {};
    void* workspace[kStreams] = {};
    std::uint64_t workspace_bytes = 0;  // per handle
};

// The context of CUDA device `device`, created on the first call for it (cudaSetDevice, streams,
// handles, workspaces); the caller must hold gpu_mutex(). Throws Error(unsupported) when
// query_gpu(device) finds no device, Error(cuda) when a CUDA or cuBLAS call fails (the next call
// tries again).
GpuContext& gpu_context(int device);

// Serialises GPU bakes within the process: the context's streams and handles are shared.
std::mutex& gpu_mutex();

}  // namespace shprt::cuda
