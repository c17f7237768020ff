// Lazy loading of cuSPARSE (cusparse_loader.hpp).
#include "bake/cuda/cusparse_loader.hpp"

#include "bake/cuda/dynamic_library.hpp"

#include <memory>
#include <mutex>

namespace shprt::cuda {
namespace {

constexpr const char* kCusparseLibrary =
    "libcusparse.so." SHPRT_TOOLKIT_SONAME_VERSION(CUSPARSE_VER_MAJOR);

const CusparseApi* load_cusparse() {
    void* library = open_toolkit_library(kCusparseLibrary, "cuSPARSE");
    auto api = std::make_unique<CusparseApi>();  // lives as long as the process, as the library
    resolve_symbol(library, kCusparseLibrary, "cusparseCreate", api->create);
    resolve_symbol(library, kCusparseLibrary, "cusparseDestroy", api->destroy);
    resolve_symbol(library, kCusparseLibrary, "cusparseSetStream", api->set_stream);
    resolve_symbol(library, kCusparseLibrary, "cusparseCreateCsr", api->create_csr);
    resolve_symbol(library, kCusparseLibrary, "cusparseDestroySpMat", api->destroy_sp_mat);
    resolve_symbol(library, kCusparseLibrary, "cusparseCreateDnMat", api->create_dn_mat);
    resolve_symbol(library, kCusparseLibrary, "cusparseDestroyDnMat", api->destroy_dn_mat);
    resolve_symbol(library, kCusparseLibrary, "cusparseSpMM_bufferSize", api->spmm_buffer_size);
    resolve_symbol(library, kCusparseLibrary, "cusparseSpMM", api->spmm);
    resolve_symbol(library, kCusparseLibrary, "cusparseGetErrorString", api->error_string);
    return api.release();
}

}  // namespace

const CusparseApi& cusparse() {
    static std::mutex mutex;
    static const CusparseApi* loaded = nullptr;
    const std::lock_guard<std::mutex> lock(mutex);
    if (!loaded) loaded = load_cusparse();  // throws; the next call tries again
    return *loaded;
}

}  // namespace shprt::cuda
