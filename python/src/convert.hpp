// numpy ↔ library conversions for the Python module (a thin shell: parse, call, convert).
//
// Inputs are checked here for what only Python can get wrong — the dtype and the shape — and
// each bad one is a shprt::Error(invalid_argument) that names the argument, the expected shape
// and dtype, and what was given (the module maps shprt::Error to shprt.Error). Everything about
// the values themselves (NaN, index ranges, K, sizes) is checked by the library functions the
// module calls, with their own messages.
//
// Outputs own their memory without a copy: a std::vector the library filled is moved into a
// capsule that the array holds (take_vector), and arrays of an object that lives in Python
// (a Mesh, a File) are views whose base is that object (view_of).
#pragma once

#include "shprt/core/error.hpp"
#include "shprt/core/vec.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt::python {

namespace py = pybind11;

// An argument the binding converts and checks itself, so that a bad one is one shprt.Error naming
// it (not pybind11's "incompatible function arguments"): any Python object is taken as it is.
// Tag::name is the type its signature shows, the one the stubs give (python/shprt/_shprt.pyi,
// checked by python/tests/test_stubs.py); a bare py::handle would show as "handle".
template <class Tag>
struct Loose {
    py::object value;
    operator py::handle() const { return value; }  // NOLINT: used where a handle is
    bool is_none() const { return value.is_none(); }
};
struct ArrayLikeName {
    static constexpr auto name = py::detail::const_name("numpy.typing.ArrayLike");
};
struct OptionalArrayLikeName {
    static constexpr auto name = py::detail::const_name("Optional[numpy.typing.ArrayLike]");
};
using ArrayLike = Loose<ArrayLikeName>;                  // an array, or what numpy.asarray takes
using OptionalArrayLike = Loose<OptionalArrayLikeName>;  // the same, or None

// "(10, 3) float32": an array's shape and dtype, for messages.
std::string describe_shape(const py::array& a);

// The object as a numpy array (lists and other array-likes go through numpy.asarray);
// Error(invalid_argument) naming `name` if numpy cannot make one.
py::array as_array(py::handle obj, const char* name);

// Checks a.ndim() and every dimension of `shape` that is ≥ 0; `expect` is how the message shows
// the expected shape, e.g. "(V, 3)". Error(invalid_argument) otherwise.
void check_shape(const py::array& a, const char* name, std::initializer_list<py::ssize_t> shape,
                 const char* expect);

// The values of a floating-point array (float16/32/64; integers, booleans, complex and objects
// are refused) as a C-contiguous float32 / float64 array: the array itself when it already is
// one, else a converted copy.
py::array_t<float, py::array::c_style> float32_array(py::handle obj, const char* name);
py::array_t<double, py::array::c_style> float64_array(py::handle obj, const char* name);

// An (N, 3) floating-point array as N Vec3f (one copy into the vector the library owns).
std::vector<Vec3f> vec3_rows(py::handle obj, const char* name, const char* expect = "(N, 3)");

// An (T, 3) integer array (any signed or unsigned integer dtype) of triangle indices; negative
// indices or indices ≥ 2^32 are an Error(invalid_argument) naming the triangle.
std::vector<std::array<std::uint32_t, 3>> triangle_rows(py::handle obj, const char* name);

// A 3×3 floating-point matrix.
Mat3d mat3(py::handle obj, const char* name);

// The vector moved into a capsule and returned as an array of `shape` (C order), no copy.
template <class T>
py::array_t<T> take_vector(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* owner = new std::vector<T>(std::move(values));
    py::capsule capsule(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(std::move(shape), owner->data(), capsule);
}

// A C-order view of `data` with `shape`, kept alive by `base` (the Python object that owns it).
template <class T>
py::array_t<T> view_of(T* data, std::vector<py::ssize_t> shape, py::handle base) {
    return py::array_t<T>(std::move(shape), data, base);
}

}  // namespace shprt::python

namespace pybind11::detail {
template <class Tag>
struct type_caster<shprt::python::Loose<Tag>> {
    PYBIND11_TYPE_CASTER(shprt::python::Loose<Tag>, Tag::name);
    bool load(handle src, bool) {
        value.value = reinterpret_borrow<object>(src);
        return true;
    }
    static handle cast(const shprt::python::Loose<Tag>& v, return_value_policy, handle) {
        return v.value.inc_ref();
    }
};
}  // namespace pybind11::detail
