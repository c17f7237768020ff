// render(): headless OpenGL through EGL (render/renderer.hpp), when the build has the renderer
// (SHPRT_HAS_RENDER). Without it the module has no `render` and shprt.HAS_RENDER is False.
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/config.hpp"

#if SHPRT_HAS_RENDER
#include "shprt/bake/object_bake.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/object_shade.hpp"
#include "shprt/shade/params.hpp"

#include "shprt/light/sun.hpp"

#include <pybind11/stl.h>

#include <cmath>
#endif

namespace shprt::python {

using namespace pybind11::literals;

void bind_render(py::module_& m) {
#if SHPRT_HAS_RENDER
    const ShadingParams d;      // the defaults: shading_option_table's, the command line's
    const ShadingChoice named;  // glossy's and view's: shading_choice_table's
    m.def(
        "render",
        [](const ShprtFile& given, ArrayLike light, int width, int height,
           std::optional<std::array<float, 6>> camera, std::optional<double> fov, double k,
           double gloss, int shading_coeffs, std::optional<int> coeffs, const std::string& view,
           bool background, bool wireframe, int samples, std::optional<std::string> brdf,
           std::optional<std::array<float, 3>> albedo, bool direct, const std::string& glossy,
           std::optional<SunArg> sun, std::optional<std::string> object,
           std::optional<std::array<double, 3>> at, double object_scale,
           std::optional<std::array<double, 3>> object_rotate) {
            const ShLight l = light_arg(light);
            ShadingParams params =
                shading_params({k, gloss, shading_coeffs_arg(coeffs, shading_coeffs), brdf, albedo,
                                direct, glossy, view});
            if (sun) params.sun = sun_arg(*sun);
            check(params, Spelling::python);
            SHPRT_CHECK(width >= 1 && width <= 16384 && height >= 1 && height <= 16384,
                        invalid_argument, "size {}x{}: width and height must be 1 to 16384", width,
                        height);
            SHPRT_CHECK(samples >= 1 && samples <= 64, invalid_argument,
                        "samples={}: MSAA samples must be 1 to 64", samples);
            // The object's pose, checked before anything is read or baked.
            std::optional<ObjectPose> pose;
            if (object) {
                SHPRT_CHECK(at.has_value(), invalid_argument,
                            "object={}: give its position with at=(x, y, z)", *object);
                pose = ObjectPose{{float((*at)[0]), float((*at)[1]), float((*at)[2])},
                                  float(object_scale),
                                  object_rotate ? Vec3d{(*object_rotate)[0], (*object_rotate)[1],
                                                        (*object_rotate)[2]}
                                                : Vec3d{0, 0, 0}};
                SHPRT_CHECK(object_scale > 0 && std::isfinite(object_scale), invalid_argument,
                            "object_scale={}: must be a finite number > 0", object_scale);
                check(*pose);
                check_probes(given.transfer.probes, given.mesh.source);
            } else {
                SHPRT_CHECK(!at && !object_rotate && object_scale == 1, invalid_argument,
                            "at=, object_scale= and object_rotate= place an object: give "
                            "object=MESH");
            }
            ShprtFile file = given;  // narrowed by resolve_shading (direct=, glossy='paper')
            const ShadingPlan plan =
                resolve_shading(params, file, file.mesh.source, Spelling::python);
            DrawSettings settings = draw_settings(plan, params.view);
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
            // The sun's own SH projection at the sky's K (its bounced light), as shade() makes it.
            std::optional<PreparedSun> prepared;
            if (plan.sun) prepared = PreparedSun{*plan.sun, sun_light(*plan.sun, l.K)};
            std::optional<DynamicObject> dynamic;
            ObjectShading object_shading;
            Image image;
            {
                py::gil_scoped_release release;
                if (pose) {
                    ObjectBakeOptions bake_options;
                    bake_options.K = file.transfer.probes.K;
                    dynamic = load_dynamic_object(*object, bake_options);
                    ObjectShadeOptions options = object_shade_options(plan, params.view);
                    options.eye = settings.camera.eye;
                    object_shading =
                        shade_object(*dynamic, *pose, file.transfer.probes, l, options);
                }
                const DrawnObject drawn{dynamic ? &dynamic->mesh : nullptr, &object_shading};
                image = render_image(file.mesh, file.transfer, l, settings, width, height, samples,
                                     prepared ? &*prepared : nullptr, dynamic ? &drawn : nullptr);
            }
            if (object_shading.clamped) {
                const std::string warning =
                    clamped_warning(file.transfer.probes, pose->position, "at=");
                if (PyErr_WarnEx(PyExc_UserWarning, warning.c_str(), 1) != 0)
                    throw py::error_already_set();
            }
            return take_vector(std::move(image.rgb), {image.height, image.width, 3});
        },
        "file"_a, "light"_a, py::kw_only(), "width"_a = 1280, "height"_a = 720,
        "camera"_a = py::none(), "fov"_a = py::none(), "k"_a = d.k, "gloss"_a = d.gloss,
        "shading_coeffs"_a = d.coeffs, "coeffs"_a = py::none(), "view"_a = named.view,
        "background"_a = false, "wireframe"_a = false, "samples"_a = 4, "brdf"_a = py::none(),
        "albedo"_a = py::none(), "direct"_a = d.direct, "glossy"_a = named.glossy,
        "sun"_a = py::none(), "object"_a = py::none(), "at"_a = py::none(),
        "object_scale"_a = ObjectChoice{}.object_scale, "object_rotate"_a = py::none(),
        R"(Renders the baked scene headless (OpenGL through EGL, the renderer of `shprt render`):
returns linear RGB (height, width, 3) float32, row 0 at the top. camera (ex, ey, ez, tx, ty, tz)
or None for the default view; view 'radiance', 'irradiance' or 'transfer'. brdf and albedo as
for shade(): the glossy term of transfer matrices, shaded on the GPU; direct and glossy as for
shade(). sun as for shade(): a sun kept out of the SH sum, drawn with a shadow map (its
bounced light from an interreflected file's T - T0); `light` is then the sky alone.
object (a mesh file) is drawn lit from the file's transfer probes (docs/probes.md) with its
centre at at=(x, y, z), scaled by object_scale and turned by object_rotate=(yaw, pitch, roll)
degrees; a position outside the probe grid is clamped with a UserWarning.)");
#else
    (void)m;
#endif
}

}  // namespace shprt::python
