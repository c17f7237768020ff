// SH evaluation, projection, rotation and windowing (sh/), and lights (light/) for Python.
// Coefficient arrays are (..., K): the last axis holds the first K coefficients in the library's
// order (index l(l+1)+m, Condon–Shortley phase, sh/basis.hpp); leading axes are channels.
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/sh/window.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <variant>

namespace shprt::python {

using namespace pybind11::literals;

namespace {

// Unit directions from an (N, 3) float array (normalised here; zero or non-finite rows refused).
std::vector<double> unit_directions(py::handle obj, const char* name) {
    const auto a = float64_array(obj, name);
    check_shape(a, name, {-1, 3}, "(N, 3)");
    std::vector<double> dirs(a.data(), a.data() + a.size());
    for (std::size_t d = 0; d < dirs.size() / 3; ++d) {
        double* v = dirs.data() + 3 * d;
        const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        SHPRT_CHECK(std::isfinite(len) && len > 0, invalid_argument,
                    "{}: direction {} is zero or not finite", name, d);
        for (int i = 0; i < 3; ++i) v[i] /= len;
    }
    return dirs;
}

void check_K(int K, int max_K) {
    SHPRT_CHECK(K >= 1 && K <= max_K, invalid_argument, "K={}: must be 1 to {}", K, max_K);
}

// A coefficient array (..., K) as float64 and its shape.
struct Coeffs {
    py::array_t<double, py::array::c_style> a;
    int K = 0;
    std::size_t rows = 0;  // product of the leading axes
};
Coeffs coeff_rows(py::handle obj, const char* name) {
    Coeffs c{float64_array(obj, name)};
    SHPRT_CHECK(c.a.ndim() >= 1 && c.a.shape(c.a.ndim() - 1) >= 1, invalid_argument,
                "{}: expected coefficients of shape (..., K), got {}", name, describe_shape(c.a));
    c.K = int(c.a.shape(c.a.ndim() - 1));
    check_K(c.K, sh_count(kMaxBands));
    c.rows = std::size_t(c.a.size()) / std::size_t(c.K);
    return c;
}

py::array_t<double> same_shape(const Coeffs& c, std::vector<double>&& out) {
    return take_vector(std::move(out),
                       std::vector<py::ssize_t>(c.a.shape(), c.a.shape() + c.a.ndim()));
}

py::array_t<float> light_array(ShLight&& light) {
    return take_vector(std::move(light.coeffs), {3, light.K});
}

ShLight light_from_array(py::handle obj) {
    const auto a = float32_array(obj, "light");
    check_shape(a, "light", {3, -1}, "(3, K)");
    ShLight light;
    light.K = int(a.shape(1));
    check_K(light.K, kMaxLightK);
    light.coeffs.assign(a.data(), a.data() + a.size());
    check_finite_light(light, "light");  // the command line's check of every light it makes
    return light;
}

Image image_from_array(py::handle obj) {
    const auto a = float32_array(obj, "image");
    check_shape(a, "image", {-1, -1, 3}, "(H, W, 3)");
    Image image = Image::make(int(a.shape(1)), int(a.shape(0)));
    std::memcpy(image.rgb.data(), a.data(), image.rgb.size() * sizeof(float));
    return image;
}

}  // namespace

ShLight light_arg(py::handle obj) { return light_from_array(obj); }

void bind_sh(py::module_& m) {
    m.def("sh_index", &sh_index, "l"_a, "m"_a, "Flat index l(l+1)+m.");
    m.def("sh_count", &sh_count, "bands"_a, "bands² coefficients.");
    m.def(
        "sh_eval",
        [](ArrayLike dirs, int K) {
            check_K(K, sh_count(kMaxBands));
            const std::vector<double> d = unit_directions(dirs, "dirs");
            const std::size_t n = d.size() / 3;
            std::vector<double> out(n * std::size_t(K));
            sh_eval_batch<double>(K, d.data(), long(n), out.data(), K);
            return take_vector(std::move(out), {py::ssize_t(n), K});
        },
        "dirs"_a, "K"_a,
        "The first K real SH basis functions at directions (N, 3) (normalised first): (N, K) "
        "float64.");
    m.def(
        "sh_directions",
        [](const std::string& sampler, std::uint32_t count, std::uint64_t seed) {
            DirectionSet set = make_direction_set(parse_sampler_kind(sampler), seed, count);
            const py::ssize_t n = py::ssize_t(set.size());
            return py::make_tuple(take_vector(std::move(set.dirs), {n, 3}),
                                  take_vector(std::move(set.weights), {n}));
        },
        "sampler"_a = "sobol", "count"_a = 1024, "seed"_a = 1,
        "The bake's direction set: (dirs (S, 3) float32, weights (S,) float32 = 4π/S).");
    m.def(
        "sh_project",
        [](ArrayLike dirs, ArrayLike values, int K, OptionalArrayLike weights) {
            check_K(K, sh_count(kMaxBands));
            const auto d = float32_array(dirs, "dirs");
            check_shape(d, "dirs", {-1, 3}, "(S, 3)");
            const std::size_t S = std::size_t(d.shape(0));
            const auto v = float32_array(values, "values");
            SHPRT_CHECK((v.ndim() == 1 || v.ndim() == 2) && std::size_t(v.shape(0)) == S,
                        invalid_argument, "values: expected shape ({},) or ({}, C), got {}", S, S,
                        describe_shape(v));
            DirectionSet set;
            set.dirs.assign(d.data(), d.data() + d.size());
            if (weights.is_none()) {
                set.weights.assign(S, float(4.0 * M_PI / double(S)));
            } else {
                const auto w = float32_array(weights, "weights");
                check_shape(w, "weights", {py::ssize_t(S)}, "(S,)");
                set.weights.assign(w.data(), w.data() + w.size());
            }
            const std::vector<float> table = basis_table(K, set);
            const std::size_t C = v.ndim() == 2 ? std::size_t(v.shape(1)) : 1;
            std::vector<double> out;
            std::vector<float> channel(S);
            for (std::size_t c = 0; c < C; ++c) {
                for (std::size_t s = 0; s < S; ++s) channel[s] = v.data()[s * C + c];
                const std::vector<double> coeffs = project_with_table(table, K, set, channel);
                out.insert(out.end(), coeffs.begin(), coeffs.end());
            }
            if (v.ndim() == 1) return take_vector(std::move(out), {K});
            return take_vector(std::move(out), {py::ssize_t(C), K});
        },
        "dirs"_a, "values"_a, "K"_a, "weights"_a = py::none(),
        "Projects samples f(dirs[s]) (values (S,) or (S, C)) onto the first K SH coefficients: "
        "c_i = Σ_s w_s f(d_s) y_i(d_s), weights 4π/S by default. Returns (K,) or (C, K) "
        "float64.");
    m.def(
        "sh_reconstruct",
        [](ArrayLike coeffs, ArrayLike dirs) {
            const Coeffs c = coeff_rows(coeffs, "coeffs");
            const std::vector<double> d = unit_directions(dirs, "dirs");
            const std::size_t n = d.size() / 3;
            std::vector<double> out(n * c.rows);
            for (std::size_t i = 0; i < n; ++i)
                for (std::size_t r = 0; r < c.rows; ++r)
                    out[i * c.rows + r] =
                        sh_reconstruct(c.a.data() + r * std::size_t(c.K), c.K,
                                       Vec3d{d[3 * i], d[3 * i + 1], d[3 * i + 2]});
            std::vector<py::ssize_t> shape{py::ssize_t(n)};
            shape.insert(shape.end(), c.a.shape(), c.a.shape() + c.a.ndim() - 1);
            return take_vector(std::move(out), std::move(shape));
        },
        "coeffs"_a, "dirs"_a,
        "Σ_i c_i y_i(d) at directions (N, 3) for coefficients (..., K): shape (N, ...).");
    m.def(
        "sh_rotate",
        [](ArrayLike coeffs, ArrayLike R, const std::string& method) {
            const Coeffs c = coeff_rows(coeffs, "coeffs");
            const ShRotation rotation = ShRotation::from_matrix(mat3(R, "R"), sh_bands_for(c.K),
                                                                parse_rotation_method(method));
            std::vector<double> out(c.rows * std::size_t(c.K));
            for (std::size_t r = 0; r < c.rows; ++r)
                rotation.apply(c.a.data() + r * std::size_t(c.K), out.data() + r * std::size_t(c.K),
                               c.K);
            return same_shape(c, std::move(out));
        },
        "coeffs"_a, "R"_a, "method"_a = "ivanic",
        "Rotates coefficients (..., K) by the 3×3 rotation R: g(d) = f(R⁻¹d), a lobe toward v "
        "ends toward R·v (sh/rotation.hpp). Exact for full bands; a partial last band is "
        "padded with zeros.");
    m.def(
        "sh_window",
        [](ArrayLike coeffs, const std::string& kind, double strength) {
            const Coeffs c = coeff_rows(coeffs, "coeffs");
            std::vector<double> out(c.a.data(), c.a.data() + c.a.size());
            const WindowKind w = parse_window_kind(kind);
            for (std::size_t r = 0; r < c.rows; ++r)
                apply_window(w, out.data() + r * std::size_t(c.K), c.K, strength);
            return same_shape(c, std::move(out));
        },
        "coeffs"_a, "kind"_a, "strength"_a = 0.0,
        "Multiplies coefficients (..., K) by the window 'hann', 'lanczos', 'sloan' or 'none' "
        "(sh/window.hpp) per band.");
    m.def(
        "sh_window_weights",
        [](const std::string& kind, int bands, double strength) {
            return window_weights(parse_window_kind(kind), bands, strength);
        },
        "kind"_a, "bands"_a, "strength"_a = 0.0, "The window's weight per band.");
}

void bind_light(py::module_& m) {
    m.def(
        "light",
        [](std::variant<std::string, std::vector<std::string>> specs, int K,
           std::optional<std::array<double, 3>> rotate, const std::string& window,
           double window_strength) {
            LightSetup setup;
            if (auto* one = std::get_if<std::string>(&specs))
                setup.specs = {*one};
            else
                setup.specs = std::get<std::vector<std::string>>(specs);
            if (rotate) setup.yaw_pitch_roll_deg = {(*rotate)[0], (*rotate)[1], (*rotate)[2]};
            setup.window = parse_window_kind(window);
            setup.window_strength = window_strength;
            ShLight light;
            {
                py::gil_scoped_release release;
                light = prepare_light(setup, K);
            }
            return light_array(std::move(light));
        },
        "specs"_a = "builtin", "K"_a = 16, "rotate"_a = py::none(),
        "window"_a = LightChoice{}.window, "window_strength"_a = LightChoice{}.window_strength,
        R"(A distant light as (3, K) float32 SH coefficients (RGB rows), through the one light
path (light/light_setup.hpp): the specs summed — 'FILE.hdr|.exr' (equirect or cube cross),
'constant[:R,G,B]', 'gradient', 'sun:X,Y,Z[,RADIUS_DEG[,R,G,B]]', 'builtin' — windowed, then
rotated by (yaw, pitch, roll) degrees.)");
    // A light projected from an image array by `project` (equirect or cube cross), GIL released.
    const auto projected = [](ShLight (*project)(const Image&, int)) {
        return [project](ArrayLike image, int K) {
            const Image map = image_from_array(image);
            ShLight light;
            {
                py::gil_scoped_release release;
                // What the command line refuses in a light file: NaN, infinite or negative
                // pixels, and a light so bright that it overflows float.
                check_radiance_map("array", map);
                light = project(map, K);
            }
            check_finite_light(light, "the image");
            return light_array(std::move(light));
        };
    };
    m.def("light_from_equirect", projected(&project_equirect), "image"_a, "K"_a = 16,
          "Projects an equirect radiance map (H, W, 3) (row 0 the zenith, the centre toward −Z) "
          "with exact pixel solid angles: (3, K) float32.");
    m.def("light_from_cube_cross", projected(&project_cube_cross), "image"_a, "K"_a = 16,
          "Projects a horizontal (4:3) or vertical (3:4) cube cross (H, W, 3): (3, K) float32.");
    m.def(
        "light_rotate",
        [](ArrayLike light, ArrayLike R) {
            const ShLight source = light_from_array(light);
            return light_array(rotated_light(source, mat3(R, "R"), source.K));
        },
        "light"_a, "R"_a,
        "The light (3, K) turned by the rotation R (a feature toward s moves toward R·s).");
}

}  // namespace shprt::python
