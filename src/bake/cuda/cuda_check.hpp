// Checks for CUDA runtime, cuBLAS and cuSPARSE calls: a failure becomes
// shprt::Error(ErrorCode::cuda) whose message names the call, the file and line, and CUDA's own
// error name and text. Allocation failures become Error(out_of_memory). Host code of the CUDA
// backend only (.cpp files compiled by the host compiler; nvcc cannot parse fmt, so .cu launchers
// return cudaError_t to be checked here).
#pragma once

#include <cublas_v2.h>
#include <cuda_runtime_api.h>
#include <cusparse.h>

namespace shprt::cuda {

// Throws when `status` is not success; `call` is the expression text. The CUDA runtime's
// last-error state is cleared first, so a failure does not resurface in an unrelated later check.
void check(cudaError_t status, const char* call, const char* file, int line);
void check(cublasStatus_t status, const char* call, const char* file, int line);
void check(cusparseStatus_t status, const char* call, const char* file, int line);

}  // namespace shprt::cuda

#define SHPRT_CUDA_CHECK(call) ::shprt::cuda::check((call), #call, __FILE__, __LINE__)
