// numpy ↔ library conversions (convert.hpp).
#include "convert.hpp"

#include <fmt/format.h>

#include <cstring>
#include <limits>

namespace shprt::python {

std::string describe_shape(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i)
        s += fmt::format("{}{}", i > 0 ? ", " : "", a.shape(i));
    if (a.ndim() == 1) s += ",";
    s += ") ";
    s += py::str(a.dtype()).cast<std::string>();
    return s;
}

py::array as_array(py::handle obj, const char* name) {
    if (py::isinstance<py::array>(obj)) return py::reinterpret_borrow<py::array>(obj);
    try {
        return py::module_::import("numpy").attr("asarray")(obj).cast<py::array>();
    } catch (py::error_already_set& e) {
        fail(ErrorCode::invalid_argument, "{}: expected a numpy array, got {} ({})", name,
             py::str(py::type::of(obj).attr("__name__")).cast<std::string>(), e.what());
    }
}

void check_shape(const py::array& a, const char* name, std::initializer_list<py::ssize_t> shape,
                 const char* expect) {
    bool ok = a.ndim() == py::ssize_t(shape.size());
    py::ssize_t i = 0;
    for (const py::ssize_t want : shape) {
        if (ok && want >= 0 && a.shape(i) != want) ok = false;
        ++i;
    }
    SHPRT_CHECK(ok, invalid_argument, "{}: expected an array of shape {}, got {}", name, expect,
                describe_shape(a));
}

namespace {

void check_floating(const py::array& a, const char* name) {
    const char kind = a.dtype().kind();
    SHPRT_CHECK(kind == 'f', invalid_argument,
                "{}: expected a floating-point array (float32 or float64), got {}", name,
                describe_shape(a));
}

}  // namespace

py::array_t<float, py::array::c_style> float32_array(py::handle obj, const char* name) {
    const py::array a = as_array(obj, name);
    check_floating(a, name);
    return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
}

py::array_t<double, py::array::c_style> float64_array(py::handle obj, const char* name) {
    const py::array a = as_array(obj, name);
    check_floating(a, name);
    return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
}

std::vector<Vec3f> vec3_rows(py::handle obj, const char* name, const char* expect) {
    const py::array a = as_array(obj, name);
    check_floating(a, name);
    check_shape(a, name, {-1, 3}, expect);
    const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    std::vector<Vec3f> rows(std::size_t(f.shape(0)));
    static_assert(sizeof(Vec3f) == 3 * sizeof(float));
    if (!rows.empty()) std::memcpy(rows.data(), f.data(), rows.size() * sizeof(Vec3f));
    return rows;
}

std::vector<std::array<std::uint32_t, 3>> triangle_rows(py::handle obj, const char* name) {
    const py::array a = as_array(obj, name);
    const char kind = a.dtype().kind();
    SHPRT_CHECK(kind == 'i' || kind == 'u', invalid_argument,
                "{}: expected an integer array of shape (T, 3) (int32, int64 or uint32), got {}",
                name, describe_shape(a));
    check_shape(a, name, {-1, 3}, "(T, 3)");
    const auto idx =
        py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    const std::int64_t* p = idx.data();
    std::vector<std::array<std::uint32_t, 3>> rows(std::size_t(idx.shape(0)));
    for (std::size_t t = 0; t < rows.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::int64_t v = p[3 * t + std::size_t(c)];
            SHPRT_CHECK(v >= 0 && v <= std::int64_t(std::numeric_limits<std::uint32_t>::max()),
                        invalid_argument, "{}: triangle {} has the index {}", name, t, v);
            rows[t][std::size_t(c)] = std::uint32_t(v);
        }
    return rows;
}

Mat3d mat3(py::handle obj, const char* name) {
    const auto a = float64_array(obj, name);
    check_shape(a, name, {3, 3}, "(3, 3)");
    Mat3d R{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R.m[r][c] = a.at(r, c);
    return R;
}

}  // namespace shprt::python
