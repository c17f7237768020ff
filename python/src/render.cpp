// shade (render/shade.hpp) always; render and save_image (render/renderer.hpp, headless OpenGL
// through EGL) when the build has the renderer (SHPRT_HAS_RENDER). Without it the module has
// no `render` and shprt.HAS_RENDER is False.
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/config.hpp"
#include "shprt/io/shprt_file.hpp"

#if SHPRT_HAS_RENDER
#include "shprt/render/camera.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/render/save_image.hpp"
#include "shprt/render/shade.hpp"
#endif

#include <pybind11/stl.h>

#include <cstring>

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

}  // namespace
#endif

void bind_render(py::module_& m) {
#if SHPRT_HAS_RENDER
    m.def(
        "shade",
        [](const ShprtFile& file, py::handle light, double k, double gloss,
           std::array<float, 3> eye, int coeffs) {
            const ShLight l = light_arg(light);
            ShadeOptions options;
            options.k = k;
            options.gloss = gloss;
            options.eye = {eye[0], eye[1], eye[2]};
            options.K_used = coeffs;
            ShadeResult result;
            {
                py::gil_scoped_release release;
                result = shade_vertices(file.mesh, file.transfer, l, options);
            }
            return py::make_tuple(vec3_array(std::move(result.irradiance)),
                                  vec3_array(std::move(result.radiance)));
        },
        "file"_a, "light"_a, py::kw_only(), "k"_a = 1.0, "gloss"_a = kDefaultGloss,
        "eye"_a = std::array<float, 3>{0, 0, 0}, "coeffs"_a = 0,
        R"(Per-vertex shading on the CPU (render/shade.hpp): returns (irradiance, radiance), each
(V, 3) float32, under light (3, K). k is the diffuse share (1 = diffuse only), gloss the Phong
exponent, eye the viewer for the glossy term, coeffs the K' used (0 = all).)");
    m.def(
        "render",
        [](const ShprtFile& file, py::handle light, int width, int height,
           std::optional<std::array<float, 6>> camera, std::optional<double> fov, double k,
           double gloss, int coeffs, const std::string& view, bool background, bool wireframe,
           int samples) {
            const ShLight l = light_arg(light);
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
        "samples"_a = 4,
        R"(Renders the baked scene headless (OpenGL through EGL, the renderer of `shprt render`):
returns linear RGB (height, width, 3) float32, row 0 at the top. camera (ex, ey, ez, tx, ty, tz)
or None for the default view; view 'radiance', 'irradiance' or 'transfer'.)");
    m.def(
        "save_image",
        [](const std::string& path, py::handle image, float exposure) {
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
