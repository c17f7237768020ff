// cuBLAS, loaded on first use with dlopen rather than linked. Linking libcublas (and with it the
// 540 MB libcublasLt) costs every program that links shprt ~0.3 s and ~200 MB of relocated pages
// at start-up, GPU or not, and makes the program fail to start where the toolkit's libraries are
// missing; loaded lazily, only a GPU bake pays, and a missing library is an ordinary
// shprt::Error. Host code of the CUDA backend only.
#pragma once

#include <cublas_v2.h>

namespace shprt::cuda {

// The cuBLAS entry points the bake uses (the _v2 API of cublas_v2.h).
struct CublasApi {
    decltype(&cublasCreate_v2) create;
    decltype(&cublasSetStream_v2) set_stream;
    decltype(&cublasSetMathMode) set_math_mode;
    decltype(&cublasSetWorkspace_v2) set_workspace;
    decltype(&cublasSgemm_v2) sgemm;
    decltype(&cublasGetStatusString) status_string;
};

// Opens libcublas.so.<CUBLAS_VER_MAJOR> (the dynamic linker's search path first, then the toolkit
// directory found at configure time) and resolves the entry points, once per process; thread-safe.
// Throws Error(unsupported) naming the library and dlerror()'s message when it cannot.
const CublasApi& cublas();

// cublasGetStatusString when cuBLAS is loaded, else a generic text (never throws).
const char* cublas_status_string(cublasStatus_t status);

}  // namespace shprt::cuda
