// The CUDA toolkit's libraries that the backend opens on first use with dlopen rather than links
// (cuBLAS, cuSPARSE: cublas_loader.hpp says why). Host code of the CUDA backend only.
#pragma once

#include "shprt/core/error.hpp"

#include <dlfcn.h>

// A toolkit library's soname from its header's major version: "libcublas.so."
// SHPRT_TOOLKIT_SONAME_VERSION(CUBLAS_VER_MAJOR) is "libcublas.so.13".
#define SHPRT_TOOLKIT_SONAME_VERSION2(x) #x
#define SHPRT_TOOLKIT_SONAME_VERSION(x) SHPRT_TOOLKIT_SONAME_VERSION2(x)

namespace shprt::cuda {

// dlopen(soname) on the dynamic linker's search path, then in the toolkit directory found at
// configure time. Throws Error(unsupported) naming `what`, the library and dlerror()'s message.
void* open_toolkit_library(const char* soname, const char* what);

// The address of `name` in `library` (opened as `soname`), as F. Throws Error(unsupported).
template <class F>
void resolve_symbol(void* library, const char* soname, const char* name, F& out) {
    dlerror();  // clear
    void* symbol = dlsym(library, name);
    const char* error = dlerror();
    SHPRT_CHECK(symbol != nullptr, unsupported, "{} has no symbol {}: {}", soname, name,
                error ? error : "null address");
    out = reinterpret_cast<F>(symbol);
}

}  // namespace shprt::cuda
