// Lazy loading of cuBLAS (cublas_loader.hpp).
#include "cuda/cublas_loader.hpp"

#include "shprt/core/error.hpp"

#include <dlfcn.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#ifndef SHPRT_CUBLAS_DIR
#define SHPRT_CUBLAS_DIR ""
#endif

namespace shprt::cuda {
namespace {

#define SHPRT_STRINGIFY2(x) #x
#define SHPRT_STRINGIFY(x) SHPRT_STRINGIFY2(x)
constexpr const char* kLibrary = "libcublas.so." SHPRT_STRINGIFY(CUBLAS_VER_MAJOR);

std::atomic<const CublasApi*> g_loaded{nullptr};

template <class F>
void resolve(void* library, const char* name, F& out) {
    dlerror();  // clear
    void* symbol = dlsym(library, name);
    const char* error = dlerror();
    SHPRT_CHECK(symbol != nullptr, unsupported, "{} has no symbol {}: {}", kLibrary, name,
                error ? error : "null address");
    out = reinterpret_cast<F>(symbol);
}

const CublasApi* load() {
    void* library = dlopen(kLibrary, RTLD_NOW | RTLD_LOCAL);
    const char* error = library ? nullptr : dlerror();
    const std::string first_error = error ? error : "";
    const std::string dir = SHPRT_CUBLAS_DIR;
    if (!library && !dir.empty())
        library = dlopen((dir + "/" + kLibrary).c_str(), RTLD_NOW | RTLD_LOCAL);
    SHPRT_CHECK(library != nullptr, unsupported,
                "cannot load cuBLAS ({}): {} (install the CUDA toolkit's libraries or add their "
                "directory to LD_LIBRARY_PATH)",
                kLibrary, first_error);
    auto api = std::make_unique<CublasApi>();  // then lives as long as the process, as the library
    resolve(library, "cublasCreate_v2", api->create);
    resolve(library, "cublasSetStream_v2", api->set_stream);
    resolve(library, "cublasSetMathMode", api->set_math_mode);
    resolve(library, "cublasSetWorkspace_v2", api->set_workspace);
    resolve(library, "cublasSgemm_v2", api->sgemm);
    resolve(library, "cublasGetStatusString", api->status_string);
    return api.release();
}

}  // namespace

const CublasApi& cublas() {
    if (const CublasApi* api = g_loaded.load(std::memory_order_acquire)) return *api;
    static std::mutex mutex;
    const std::lock_guard<std::mutex> lock(mutex);
    if (const CublasApi* api = g_loaded.load(std::memory_order_acquire)) return *api;
    const CublasApi* api = load();  // throws; the next call tries again
    g_loaded.store(api, std::memory_order_release);
    return *api;
}

const char* cublas_status_string(cublasStatus_t status) {
    if (const CublasApi* api = g_loaded.load(std::memory_order_acquire))
        return api->status_string(status);
    return "cuBLAS status (library not loaded)";
}

}  // namespace shprt::cuda
