// The Python module's parts, one function per library area (python/src/*.cpp), called by
// PYBIND11_MODULE in module.cpp. Each binds thin wrappers: parse the Python arguments, call the
// library with the GIL released where the call is long, convert the result (convert.hpp).
#pragma once

#include "shprt/light/light.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/params.hpp"

#include <pybind11/pybind11.h>

#include <array>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace shprt::python {

namespace py = pybind11;

void bind_errors(py::module_& m);  // shprt.Error
void bind_scene(py::module_& m);   // shprt.Mesh, load_scene, builtin_scenes
void bind_io(py::module_& m);      // shprt.File, load, save
void bind_bake(py::module_& m);    // bake
void bind_sh(py::module_& m);      // sh_* (evaluation, projection, rotation, windowing)
void bind_light(py::module_& m);   // light, light_from_equirect, light_from_cube_cross
void bind_shade(py::module_& m);   // shade, save_image (shade/: no GL)
void bind_render(py::module_& m);  // render, when the build has render/ (GL)

// The shading keywords shade() and render() share, as shade/params.hpp's ShadingParams, checked
// (one line naming the keyword as Python spells it).
struct ShadingKeywords {
    double k;
    double gloss;
    int coeffs;
    std::optional<std::string> brdf;
    std::optional<std::array<float, 3>> albedo;
    bool direct;
    std::string glossy;
    std::string view = "radiance";
};
ShadingParams shading_params(const ShadingKeywords& keywords);
// K′ from shading_coeffs=, or from the deprecated coeffs= (a DeprecationWarning; both: an error).
int shading_coeffs_arg(std::optional<int> coeffs, int shading_coeffs);
// sun= as the command line's --sun: "X,Y,Z[,RADIUS_DEG[,R,G,B]]" or the same 3, 4 or 7 numbers
// (shade(), render()).
using SunArg = std::variant<std::string, std::vector<double>>;
Sun sun_arg(const SunArg& arg);

// The mesh a Python call gives: a shprt.Mesh as it is, or arrays (vertices (V, 3) float,
// faces (T, 3) int, normals (V, 3) or None = computed, albedo (V, 3) or None = kDefaultAlbedo)
// made into one, checked by validate_mesh (NaN and index ranges) under the name `name`.
// A light (3, K) float array as an ShLight (checked shape and K).
ShLight light_arg(py::handle light);

Mesh mesh_from_arrays(py::handle vertices, py::handle faces, py::handle normals, py::handle albedo,
                      const char* name);

}  // namespace shprt::python
