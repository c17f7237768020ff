// shade (render/shade.hpp) always; render and save_image (render/renderer.hpp, headless OpenGL
// through EGL) when the build has the renderer (SHPRT_HAS_RENDER). Without it the module has
// no `render` and shprt.HAS_RENDER is False.
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/config.hpp"
#include "shprt/io/shprt_file.hpp"

#if SHPRT_HAS_RENDER
#include "shprt/render/camera.hpp"
#include "shprt/render/glossy.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/render/save_image.hpp"
#include "shprt/render/shade.hpp"
#include "shprt/render/sun_shade.hpp"
#include "shprt/render/texel_shade.hpp"
#endif

#include <pybind11/stl.h>

#include <cstring>
#include <variant>

namespace shprt::python {

using namespace pybind11::literals;

#if SHPRT_HAS_RENDER
namespace {

py::array_t<float> vec3_array(std::vector<Vec3f>&& rows) {
    const py::ssize_t n = py::ssize_t(rows.size());
    std::vector<float> flat(rows.size() * 3);
    if (!rows.empty()) std::memcpy(flat.data(), rows.data(), flat.size() * sizeof(float));
    return take_vector(std::move(flat), {n, 3});
}

ShadeView parse_view(const std::string& name) {
    if (name == "radiance") return ShadeView::radiance;
    if (name == "irradiance") return ShadeView::irradiance;
    if (name == "transfer") return ShadeView::transfer;
    fail(ErrorCode::invalid_argument, "view='{}': expected radiance, irradiance or transfer", name);
}

// The glossy term of a file of transfer matrices (render/glossy.hpp): `brdf` (a spec, "ggx:0.3",
// "phong:40:1,0.7,0.3") everywhere, else the materials' BRDFs where the mesh has them and a Phong
// lobe of exponent `gloss` elsewhere; `albedo` replaces both colours. A vector file takes
// neither (one-line Error). The options' brdf, material_brdfs and albedo; the caller sets the rest.
std::optional<GlossyShadeOptions> glossy_args(const ShprtFile& file,
                                              const std::optional<std::string>& brdf,
                                              const std::optional<std::array<float, 3>>& albedo,
                                              double gloss) {
    if (file.transfer.layout.shape != TransferShape::symmetric_matrix) {
        SHPRT_CHECK(!brdf && !albedo, invalid_argument,
                    "brdf= and albedo= shade glossy transfer matrices; {} holds {} transfer "
                    "(bake with transfer='glossy')",
                    file.mesh.source, to_string(file.transfer.layout.shape));
        return std::nullopt;
    }
    GlossyShadeOptions g;
    g.material_brdfs = !brdf;
    g.brdf = brdf ? parse_brdf(*brdf) : Brdf{BrdfModel::phong, gloss};
    check_brdf(g.brdf);
    if (albedo) g.albedo = Vec3f{(*albedo)[0], (*albedo)[1], (*albedo)[2]};
    return g;
}

// The file as `shade` and `render` shade it: with `direct`, an interreflected bake's direct part
// only (as the command line's --direct).
const ShprtFile& shaded_file(const ShprtFile& file, bool direct, std::optional<ShprtFile>& own) {
    if (!direct) return file;
    SHPRT_CHECK(!file.transfer.direct.empty(), invalid_argument,
                "direct=True: {} has no direct part (only interreflected bakes keep one)",
                file.mesh.source);
    own.emplace();
    own->mesh = file.mesh;
    own->transfer = file.transfer.direct_only();
    return *own;
}

// sun= as the command line's --sun: "X,Y,Z[,RADIUS_DEG[,R,G,B]]" or the same 3, 4 or 7 numbers.
using SunArg = std::variant<std::string, std::vector<double>>;
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

}  // namespace
#endif

void bind_render(py::module_& m) {
#if SHPRT_HAS_RENDER
    m.def(
        "shade",
        [](const ShprtFile& given, ArrayLike light, double k, double gloss,
           std::array<float, 3> eye, int coeffs, std::optional<std::string> brdf,
           std::optional<std::array<float, 3>> albedo, bool direct, std::optional<SunArg> sun,
           int sun_samples) {
            const ShLight l = light_arg(light);
            std::optional<PreparedSun> prepared;
            if (sun) prepared = PreparedSun{sun_arg(*sun), {}};
            SHPRT_CHECK(prepared || sun_samples == kDefaultSunSamples, invalid_argument,
                        "sun_samples={} needs sun=", sun_samples);
            std::optional<ShprtFile> own;
            const ShprtFile& file = shaded_file(given, direct, own);
            std::optional<GlossyShadeOptions> glossy = glossy_args(file, brdf, albedo, gloss);
            ShadeOptions options;
            options.k = k;
            options.gloss = gloss;
            options.eye = {eye[0], eye[1], eye[2]};
            options.K_used = coeffs;
            if (glossy) {
                glossy->k = k;
                glossy->eye = options.eye;
                glossy->K_used = coeffs;
            }
            ShadeResult result;
            {
                py::gil_scoped_release release;
                if (prepared) {
                    SHPRT_CHECK(!glossy, unsupported,
                                "sun=: a traced sun lights diffuse transfer only; {} holds glossy "
                                "transfer matrices",
                                file.mesh.source);
                    prepared->sh = sun_light(prepared->sun, l.K);  // same K as the sky
                    SunShadeOptions sun_options;
                    sun_options.disc_samples = sun_samples;
                    result = shade_with_sun(file.mesh, file.transfer, l, *prepared, options,
                                            sun_options);
                } else {
                    result = shade_receivers(file.mesh, file.transfer, l, options,
                                             glossy ? &*glossy : nullptr);
                }
            }
            return py::make_tuple(vec3_array(std::move(result.irradiance)),
                                  vec3_array(std::move(result.radiance)));
        },
        "file"_a, "light"_a, py::kw_only(), "k"_a = 1.0, "gloss"_a = kDefaultGloss,
        "eye"_a = std::array<float, 3>{0, 0, 0}, "coeffs"_a = 0, "brdf"_a = py::none(),
        "albedo"_a = py::none(), "direct"_a = false, "sun"_a = py::none(),
        "sun_samples"_a = kDefaultSunSamples,
        R"(Per-vertex shading on the CPU (render/shade.hpp): returns (irradiance, radiance), each
(V, 3) float32, under light (3, K) — for a texel file (N, 3), one row per covered texel in the
atlas's order (render/texel_shade.hpp). k is the diffuse share (1 = diffuse only), gloss the Phong
exponent, eye the viewer for the glossy term, coeffs the K' used (0 = all).

A file of glossy transfer matrices (bake(transfer='glossy')) is shaded with its BRDF
(render/glossy.hpp, as `shprt shade --brdf`): brdf a spec such as 'ggx:0.3' or
'phong:40:1,0.7,0.3' (with a specular colour) for every vertex; without it the materials' BRDFs
where the scene has them and a Phong lobe of exponent gloss elsewhere. albedo (r, g, b) replaces
the diffuse and specular colours. brdf and albedo are refused for vector transfer.

direct=True shades an interreflected bake's direct part only (File.direct; `--direct`).

sun='X,Y,Z[,RADIUS_DEG[,R,G,B]]' (or those 3, 4 or 7 numbers) adds a sun kept out of the SH sum, as
`shprt shade --sun` (render/sun_shade.hpp): its direct light traced at each receiver through
sun_samples directions on its disc (a square; 1 = a point sun), its bounced light from an
interreflected file's T - T0; `light` is then the sky alone (the sun's own SH projection is made
here, at the light's K, neither windowed nor rotated). Diffuse transfer only.)");
    m.def(
        "render",
        [](const ShprtFile& given, ArrayLike light, int width, int height,
           std::optional<std::array<float, 6>> camera, std::optional<double> fov, double k,
           double gloss, int coeffs, const std::string& view, bool background, bool wireframe,
           int samples, std::optional<std::string> brdf, std::optional<std::array<float, 3>> albedo,
           bool direct) {
            const ShLight l = light_arg(light);
            std::optional<ShprtFile> own;
            const ShprtFile& file = shaded_file(given, direct, own);
            const std::optional<GlossyShadeOptions> glossy = glossy_args(file, brdf, albedo, gloss);
            SHPRT_CHECK(width >= 1 && width <= 16384 && height >= 1 && height <= 16384,
                        invalid_argument, "size {}x{}: width and height must be 1 to 16384", width,
                        height);
            SHPRT_CHECK(samples >= 1 && samples <= 64, invalid_argument,
                        "samples={}: MSAA samples must be 1 to 64", samples);
            DrawSettings settings;
            settings.view = parse_view(view);
            settings.k = k;
            settings.gloss = gloss;
            settings.K_used = coeffs;
            settings.background = background;
            settings.wireframe = wireframe;
            if (glossy) {
                settings.brdf = glossy->brdf;
                settings.material_brdfs = glossy->material_brdfs;
                settings.albedo = glossy->albedo;
            }
            const float aspect = float(width) / float(height);
            if (camera) {
                const auto& c = *camera;
                settings.camera = look_at_camera({c[0], c[1], c[2]}, {c[3], c[4], c[5]},
                                                 Camera{}.fov_y_deg, mesh_bounds(file.mesh));
            } else {
                settings.camera = default_camera(file.mesh, aspect);
            }
            if (fov) settings.camera.fov_y_deg = float(*fov);
            Image image;
            {
                py::gil_scoped_release release;
                image = render_image(file.mesh, file.transfer, l, settings, width, height, samples);
            }
            return take_vector(std::move(image.rgb), {image.height, image.width, 3});
        },
        "file"_a, "light"_a, py::kw_only(), "width"_a = 1280, "height"_a = 720,
        "camera"_a = py::none(), "fov"_a = py::none(), "k"_a = 1.0, "gloss"_a = kDefaultGloss,
        "coeffs"_a = 0, "view"_a = "radiance", "background"_a = false, "wireframe"_a = false,
        "samples"_a = 4, "brdf"_a = py::none(), "albedo"_a = py::none(), "direct"_a = false,
        R"(Renders the baked scene headless (OpenGL through EGL, the renderer of `shprt render`):
returns linear RGB (height, width, 3) float32, row 0 at the top. camera (ex, ey, ez, tx, ty, tz)
or None for the default view; view 'radiance', 'irradiance' or 'transfer'. brdf and albedo as
for shade(): the glossy term of transfer matrices, shaded on the GPU; direct as for shade().)");
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
#else
    (void)m;
#endif
}

}  // namespace shprt::python
