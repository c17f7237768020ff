// Device discovery (query_gpu), the shared GPU context, and the CUDA/cuBLAS error checks.
#include "bake/cuda/gpu_context.hpp"

#include "bake/cuda/cublas_loader.hpp"
#include "bake/cuda/cusparse_loader.hpp"
#include "bake/cuda/device_buffer.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"

#include <fmt/format.h>

#include <map>
#include <memory>
#include <mutex>

namespace shprt {
namespace cuda {

void check(cudaError_t status, const char* call, const char* file, int line) {
    if (status == cudaSuccess) return;
    cudaGetLastError();  // clear the (non-sticky) error state
    throw Error(ErrorCode::cuda,
                fmt::format("CUDA error {} ({}) in {} at {}:{}", cudaGetErrorName(status),
                            cudaGetErrorString(status), call, file, line));
}

void check(cublasStatus_t status, const char* call, const char* file, int line) {
    if (status == CUBLAS_STATUS_SUCCESS) return;
    const ErrorCode code =
        status == CUBLAS_STATUS_ALLOC_FAILED ? ErrorCode::out_of_memory : ErrorCode::cuda;
    throw Error(code, fmt::format("cuBLAS error {} ({}) in {} at {}:{}", int(status),
                                  cublas_status_string(status), call, file, line));
}

void check(cusparseStatus_t status, const char* call, const char* file, int line) {
    if (status == CUSPARSE_STATUS_SUCCESS) return;
    const ErrorCode code =
        status == CUSPARSE_STATUS_ALLOC_FAILED ? ErrorCode::out_of_memory : ErrorCode::cuda;
    throw Error(code, fmt::format("cuSPARSE error {} ({}) in {} at {}:{}", int(status),
                                  cusparse().error_string(status), call, file, line));
}

void check_allocation(cudaError_t status, std::size_t bytes, const char* what, const char* file,
                      int line) {
    if (status == cudaSuccess) return;
    if (status == cudaErrorMemoryAllocation) {
        cudaGetLastError();
        throw Error(ErrorCode::out_of_memory,
                    fmt::format("out of {} memory: allocating {:.1f} MiB failed ({}:{})", what,
                                double(bytes) / (1024.0 * 1024.0), file, line));
    }
    check(status, "cudaMalloc", file, line);
}

double elapsed_seconds(const Event& from, const Event& to) {
    float ms = 0;
    SHPRT_CUDA_CHECK(cudaEventElapsedTime(&ms, from.get(), to.get()));
    return double(ms) * 1e-3;
}

std::mutex& gpu_mutex() {
    static std::mutex mutex;
    return mutex;
}

GpuContext& gpu_context(int device) {
    // One per device, deliberately leaked (see gpu_context.hpp); guarded by gpu_mutex().
    static std::map<int, GpuContext*> contexts;
    if (auto it = contexts.find(device); it != contexts.end()) return *it->second;
    const GpuInfo info = query_gpu(device);
    SHPRT_CHECK(info.available, unsupported, "device 'cuda': {}", info.reason);
    auto c = std::make_unique<GpuContext>();
    c->device = device;
    c->name = info.name;
    const CublasApi& blas = cublas();
    SHPRT_CUDA_CHECK(cudaSetDevice(c->device));
    // cuBLAS recommends 32 MiB of workspace per handle on Hopper, 4 MiB before.
    c->workspace_bytes = (info.compute_capability >= 90 ? 32u : 4u) << 20;
    for (int i = 0; i < kStreams; ++i) {
        SHPRT_CUDA_CHECK(cudaStreamCreateWithFlags(&c->streams[i], cudaStreamNonBlocking));
        SHPRT_CUDA_CHECK(blas.create(&c->blas[i]));
        SHPRT_CUDA_CHECK(blas.set_stream(c->blas[i], c->streams[i]));
        // FP32 arithmetic (no TF32 tensor-core rounding of the inputs).
        SHPRT_CUDA_CHECK(blas.set_math_mode(c->blas[i], CUBLAS_DEFAULT_MATH));
        check_allocation(cudaMalloc(&c->workspace[i], c->workspace_bytes), c->workspace_bytes,
                         "device", __FILE__, __LINE__);
        SHPRT_CUDA_CHECK(blas.set_workspace(c->blas[i], c->workspace[i], c->workspace_bytes));
    }
    GpuContext* context = c.release();
    contexts[device] = context;
    return *context;
}

}  // namespace cuda

namespace {

GpuInfo discover_gpu(int device) {
    GpuInfo info;
    int count = 0;
    const cudaError_t status = cudaGetDeviceCount(&count);
    if (status != cudaSuccess) {
        cudaGetLastError();
        info.reason =
            fmt::format("no CUDA device (cudaGetDeviceCount: {})", cudaGetErrorString(status));
        return info;
    }
    info.device_count = count;
    if (count < 1) {
        info.reason = "no CUDA device (cudaGetDeviceCount: 0 devices)";
        return info;
    }
    if (device < 0 || device >= count) {
        info.reason = fmt::format("no CUDA device {} (the machine has {})", device, count);
        return info;
    }
    cudaDeviceProp prop{};
    const cudaError_t props = cudaGetDeviceProperties(&prop, device);
    if (props != cudaSuccess) {
        cudaGetLastError();
        info.reason = fmt::format("no usable CUDA device (cudaGetDeviceProperties: {})",
                                  cudaGetErrorString(props));
        return info;
    }
    info.available = true;
    info.name = prop.name;
    info.memory_bytes = prop.totalGlobalMem;
    info.compute_capability = prop.major * 10 + prop.minor;
    info.multiprocessors = prop.multiProcessorCount;
    return info;
}

}  // namespace

GpuInfo query_gpu(int device) {
    static std::mutex mutex;
    static std::map<int, GpuInfo> known;
    const std::lock_guard<std::mutex> lock(mutex);
    auto it = known.find(device);
    if (it == known.end()) it = known.emplace(device, discover_gpu(device)).first;
    return it->second;
}

}  // namespace shprt
