// shade() and save_image(): shading on the CPU (shade/), in every build, the baker-only one too.
// The shading keywords shade() and render() share become one ShadingParams (shade/params.hpp),
// checked and resolved as the command line's options are.
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/io/shprt_file.hpp"
#include "shprt/shade/params.hpp"
#include "shprt/shade/save_image.hpp"

#include <pybind11/stl.h>

#include <cstring>
#include <variant>

namespace shprt::python {

using namespace pybind11::literals;

namespace {

py::array_t<float> vec3_array(std::vector<Vec3f>&& rows) {
    const py::ssize_t n = py::ssize_t(rows.size());
    std::vector<float> flat(rows.size() * 3);
    if (!rows.empty()) std::memcpy(flat.data(), rows.data(), flat.size() * sizeof(float));
    return take_vector(std::move(flat), {n, 3});
}

}  // namespace

Sun sun_arg(const SunArg& arg) {
    std::string text;
    if (const auto* s = std::get_if<std::string>(&arg)) {
        text = *s;
    } else {
        for (double v : std::get<std::vector<double>>(arg))
            text += (text.empty() ? "" : ",") + fmt::format("{}", v);
    }
    return parse_sun(text, "sun='" + text + "'", "X,Y,Z[,RADIUS_DEG[,R,G,B]]");
}

int shading_coeffs_arg(std::optional<int> coeffs, int shading_coeffs) {
    if (!coeffs) return shading_coeffs;
    SHPRT_CHECK(shading_coeffs == 0, invalid_argument,
                "coeffs={} and shading_coeffs={}: give shading_coeffs alone (coeffs is its "
                "deprecated name here)",
                *coeffs, shading_coeffs);
    if (PyErr_WarnEx(PyExc_DeprecationWarning,
                     "coeffs= is deprecated in shade() and render(): it means K' here and K in "
                     "bake(); use shading_coeffs=",
                     1) != 0)
        throw py::error_already_set();
    return *coeffs;
}

ShadingParams shading_params(const ShadingKeywords& w) {
    ShadingParams p;
    p.view = parse_view(w.view, Spelling::python);
    p.glossy = parse_glossy_term(w.glossy, Spelling::python);
    p.k = w.k;
    p.gloss = w.gloss;
    p.coeffs = w.coeffs;
    p.direct = w.direct;
    if (w.brdf) set_brdf_choice(p, *w.brdf);  // as the command line's --brdf
    if (w.albedo) p.albedo = Vec3f{(*w.albedo)[0], (*w.albedo)[1], (*w.albedo)[2]};
    check(p, Spelling::python);
    return p;
}

void bind_shade(py::module_& m) {
    const ShadingParams d;      // the defaults: shading_option_table's, the command line's
    const ShadingChoice named;  // glossy's: shading_choice_table's
    m.def(
        "shade",
        [](const ShprtFile& given, ArrayLike light, double k, double gloss,
           std::optional<std::array<float, 3>> eye, int shading_coeffs, std::optional<int> coeffs,
           std::optional<std::string> brdf, std::optional<std::array<float, 3>> albedo, bool direct,
           const std::string& glossy, std::optional<SunArg> sun, int sun_samples) {
            const ShLight sky = light_arg(light);
            ShadingKeywords keywords{
                k, gloss, shading_coeffs_arg(coeffs, shading_coeffs), brdf, albedo, direct, glossy};
            ShadingParams params = shading_params(keywords);
            if (eye) params.eye = Vec3f{(*eye)[0], (*eye)[1], (*eye)[2]};
            if (sun) params.sun = sun_arg(*sun);
            params.sun_samples = sun_samples;
            check(params, Spelling::python);
            ShprtFile file = given;  // narrowed by resolve_shading (direct=, glossy='paper')
            const ShadingPlan plan =
                resolve_shading(params, file, file.mesh.source, Spelling::python);
            SunShadeResult result;
            {
                py::gil_scoped_release release;
                // The sun's own SH projection at the sky's K, neither windowed nor rotated.
                std::optional<PreparedSun> prepared;
                if (plan.sun) prepared = PreparedSun{*plan.sun, sun_light(*plan.sun, sky.K)};
                result = shade_file(file, sky, plan, prepared ? &*prepared : nullptr);
            }
            return py::make_tuple(vec3_array(std::move(result.irradiance)),
                                  vec3_array(std::move(result.radiance)));
        },
        "file"_a, "light"_a, py::kw_only(), "k"_a = d.k, "gloss"_a = d.gloss, "eye"_a = py::none(),
        "shading_coeffs"_a = d.coeffs, "coeffs"_a = py::none(), "brdf"_a = py::none(),
        "albedo"_a = py::none(), "direct"_a = d.direct, "glossy"_a = named.glossy,
        "sun"_a = py::none(), "sun_samples"_a = d.sun_samples,
        R"(Per-vertex shading on the CPU (shade/shade.hpp): returns (irradiance, radiance), each
(V, 3) float32, under light (3, K) — for a texel file (N, 3), one row per covered texel in the
atlas's order (shade/texel_shade.hpp). k is the diffuse share (1 = diffuse only), gloss the Phong
exponent, eye the viewer for the glossy term (None: the default camera's eye, as `shprt shade`),
shading_coeffs the K' used (0 = all; coeffs= is its deprecated name, a DeprecationWarning). The keywords are `shprt shade`'s options, with the same limits and
defaults (shade/params.hpp).

A file of glossy transfer matrices (bake(transfer='glossy')) is shaded with its BRDF
(shade/glossy.hpp, as `shprt shade --brdf`): brdf a spec such as 'ggx:0.3' or
'phong:40:1,0.7,0.3' (with a specular colour) for every vertex; without it the materials' BRDFs
where the scene has them (and gloss's Phong lobe elsewhere); 'materials+ggx:0.3' the materials'
BRDFs and that lobe elsewhere. albedo (r, g, b) replaces the diffuse and specular colours. brdf and
albedo are refused for vector transfer. glossy='paper' shades the paper's zonal term instead (the
matrices' diffuse part; brdf then a Phong lobe whose exponent replaces gloss).

direct=True shades an interreflected bake's direct part only (File.direct; `--direct`).

sun='X,Y,Z[,RADIUS_DEG[,R,G,B]]' (or those 3, 4 or 7 numbers) adds a sun kept out of the SH sum, as
`shprt shade --sun` (shade/sun_shade.hpp): its direct light traced at each receiver through
sun_samples directions on its disc (a square; 1 = a point sun), its bounced light from an
interreflected file's T - T0; `light` is then the sky alone (the sun's own SH projection is made
here, at the light's K, neither windowed nor rotated). Diffuse transfer only.)");
    m.def(
        "save_image",
        [](const std::string& path, ArrayLike image, float exposure) {
            const auto a = float32_array(image, "image");
            check_shape(a, "image", {-1, -1, 3}, "(H, W, 3)");
            Image img = Image::make(int(a.shape(1)), int(a.shape(0)));
            std::memcpy(img.rgb.data(), a.data(), img.rgb.size() * sizeof(float));
            py::gil_scoped_release release;
            save_image(path, img, exposure);
        },
        "path"_a, "image"_a, "exposure"_a = 1.0f,
        "Writes linear RGB (H, W, 3) as .png (tone mapped, sRGB) or .exr/.hdr (linear).");
}

}  // namespace shprt::python
