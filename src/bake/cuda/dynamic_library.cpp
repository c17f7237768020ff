// Opening the toolkit's libraries (dynamic_library.hpp).
#include "bake/cuda/dynamic_library.hpp"

#include <string>

#ifndef SHPRT_CUDA_LIBRARY_DIR
#define SHPRT_CUDA_LIBRARY_DIR ""
#endif

namespace shprt::cuda {

void* open_toolkit_library(const char* soname, const char* what) {
    void* library = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
    const char* error = library ? nullptr : dlerror();
    const std::string first_error = error ? error : "";
    const std::string dir = SHPRT_CUDA_LIBRARY_DIR;
    if (!library && !dir.empty())
        library = dlopen((dir + "/" + soname).c_str(), RTLD_NOW | RTLD_LOCAL);
    SHPRT_CHECK(library != nullptr, unsupported,
                "cannot load {} ({}): {} (install the CUDA toolkit's libraries or add their "
                "directory to LD_LIBRARY_PATH)",
                what, soname, first_error);
    return library;
}

}  // namespace shprt::cuda
