// cuSPARSE, loaded on first use with dlopen rather than linked, as cuBLAS is (cublas_loader.hpp
// says why). Host code of the CUDA backend only.
#pragma once

#include <cusparse.h>

namespace shprt::cuda {

// The cuSPARSE entry points the interreflected bake's bounces use (the generic SpMM API).
struct CusparseApi {
    decltype(&cusparseCreate) create;
    decltype(&cusparseDestroy) destroy;
    decltype(&cusparseSetStream) set_stream;
    decltype(&cusparseCreateCsr) create_csr;
    decltype(&cusparseDestroySpMat) destroy_sp_mat;
    decltype(&cusparseCreateDnMat) create_dn_mat;
    decltype(&cusparseDestroyDnMat) destroy_dn_mat;
    decltype(&cusparseSpMM_bufferSize) spmm_buffer_size;
    decltype(&cusparseSpMM) spmm;
    decltype(&cusparseGetErrorString) error_string;
};

// Opens libcusparse.so.<CUSPARSE_VER_MAJOR> once per process (thread-safe). Throws
// Error(unsupported) naming the library when it cannot.
const CusparseApi& cusparse();

}  // namespace shprt::cuda
