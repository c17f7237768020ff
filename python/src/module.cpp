// `import shprt`: the Python module over the shprt library (pybind11). The package
// python/shprt/__init__.py re-exports this extension, shprt._shprt.
#include "bindings.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"

namespace shprt::python {

namespace {
// The enumerator's name: what Python code compares e.code with.
const char* code_name(ErrorCode code) {
    switch (code) {
        case ErrorCode::invalid_argument:
            return "invalid_argument";
        case ErrorCode::io:
            return "io";
        case ErrorCode::format:
            return "format";
        case ErrorCode::unsupported:
            return "unsupported";
        case ErrorCode::cuda:
            return "cuda";
        case ErrorCode::out_of_memory:
            return "out_of_memory";
        case ErrorCode::cancelled:
            return "cancelled";
    }
    return "unknown";
}
}  // namespace

void bind_errors(py::module_& m) {
    // shprt.Error(RuntimeError) with .code, the library's ErrorCode as a string
    // ("invalid_argument", "io", "format", "unsupported", "cuda", "out_of_memory", "cancelled").
    static py::exception<Error> error_type(m, "Error", PyExc_RuntimeError);
    error_type.attr("__module__") = "shprt";
    error_type.attr("code") = py::none();
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            py::object instance = py::reinterpret_borrow<py::object>(error_type.ptr())(e.what());
            instance.attr("code") = code_name(e.code());
            PyErr_SetObject(error_type.ptr(), instance.ptr());
        }
    });
}

}  // namespace shprt::python

PYBIND11_MODULE(_shprt, m) {
    using namespace shprt::python;
    m.doc() = "shprt: precomputed radiance transfer in real spherical harmonics (C++ library)";
    m.attr("__version__") = SHPRT_VERSION_STRING;
    m.attr("HAS_RENDER") = bool(SHPRT_HAS_RENDER);
    m.attr("HAS_CUDA") = bool(SHPRT_HAS_CUDA);
    bind_errors(m);
    bind_scene(m);
    bind_io(m);
    bind_bake(m);
    bind_sh(m);
    bind_light(m);
    bind_shade(m);
    bind_render(m);
}
