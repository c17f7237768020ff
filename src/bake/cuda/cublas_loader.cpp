// Lazy loading of cuBLAS (cublas_loader.hpp).
#include "bake/cuda/cublas_loader.hpp"

#include "bake/cuda/dynamic_library.hpp"

#include <atomic>
#include <memory>
#include <mutex>

namespace shprt::cuda {
namespace {

constexpr const char* kCublasLibrary =
    "libcublas.so." SHPRT_TOOLKIT_SONAME_VERSION(CUBLAS_VER_MAJOR);

std::atomic<const CublasApi*> g_loaded{nullptr};

const CublasApi* load_cublas() {
    void* library = open_toolkit_library(kCublasLibrary, "cuBLAS");
    auto api = std::make_unique<CublasApi>();  // then lives as long as the process, as the library
    resolve_symbol(library, kCublasLibrary, "cublasCreate_v2", api->create);
    resolve_symbol(library, kCublasLibrary, "cublasSetStream_v2", api->set_stream);
    resolve_symbol(library, kCublasLibrary, "cublasSetMathMode", api->set_math_mode);
    resolve_symbol(library, kCublasLibrary, "cublasSetWorkspace_v2", api->set_workspace);
    resolve_symbol(library, kCublasLibrary, "cublasSgemm_v2", api->sgemm);
    resolve_symbol(library, kCublasLibrary, "cublasGetStatusString", api->status_string);
    return api.release();
}

}  // namespace

const CublasApi& cublas() {
    if (const CublasApi* api = g_loaded.load(std::memory_order_acquire)) return *api;
    static std::mutex mutex;
    const std::lock_guard<std::mutex> lock(mutex);
    if (const CublasApi* api = g_loaded.load(std::memory_order_acquire)) return *api;
    const CublasApi* api = load_cublas();  // throws; the next call tries again
    g_loaded.store(api, std::memory_order_release);
    return *api;
}

const char* cublas_status_string(cublasStatus_t status) {
    if (const CublasApi* api = g_loaded.load(std::memory_order_acquire))
        return api->status_string(status);
    return "cuBLAS status (library not loaded)";
}

}  // namespace shprt::cuda
