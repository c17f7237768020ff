// Lazy loading of cuSPARSE (cusparse_loader.hpp).
#include "cuda/cusparse_loader.hpp"

#include "cuda/dynamic_library.hpp"

#include <memory>
#include <mutex>

namespace shprt::cuda {
namespace {

#define SHPRT_CUSPARSE_STRINGIFY2(x) #x
#define SHPRT_CUSPARSE_STRINGIFY(x) SHPRT_CUSPARSE_STRINGIFY2(x)
constexpr const char* kLibrary = "libcusparse.so." SHPRT_CUSPARSE_STRINGIFY(CUSPARSE_VER_MAJOR);

const CusparseApi* load() {
    void* library = open_toolkit_library(kLibrary, "cuSPARSE");
    auto api = std::make_unique<CusparseApi>();  // lives as long as the process, as the library
    resolve_symbol(library, kLibrary, "cusparseCreate", api->create);
    resolve_symbol(library, kLibrary, "cusparseDestroy", api->destroy);
    resolve_symbol(library, kLibrary, "cusparseSetStream", api->set_stream);
    resolve_symbol(library, kLibrary, "cusparseCreateCsr", api->create_csr);
    resolve_symbol(library, kLibrary, "cusparseDestroySpMat", api->destroy_sp_mat);
    resolve_symbol(library, kLibrary, "cusparseCreateDnMat", api->create_dn_mat);
    resolve_symbol(library, kLibrary, "cusparseDestroyDnMat", api->destroy_dn_mat);
    resolve_symbol(library, kLibrary, "cusparseSpMM_bufferSize", api->spmm_buffer_size);
    resolve_symbol(library, kLibrary, "cusparseSpMM", api->spmm);
    resolve_symbol(library, kLibrary, "cusparseGetErrorString", api->error_string);
    return api.release();
}

}  // namespace

const CusparseApi& cusparse() {
    static std::mutex mutex;
    static const CusparseApi* loaded = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!loaded) loaded = load();  // throws; the next call tries again
    return *loaded;
}

}  // namespace shprt::cuda
