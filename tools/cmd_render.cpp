// `shprt render FILE.shprt --light L -o IMAGE.png|IMAGE.exr`: a picture of the shaded scene,
// headless (OpenGL 4.3 core through EGL; Mesa's llvmpipe where there is no GPU). Thin: checks
// the options, reads the file, prepares the light, calls render_image, saves (PNG: exposure +
// filmic tone map + sRGB; EXR/HDR: linear).
#include "common/command.hpp"
#include "common/option_table.hpp"
#include "common/shading_options.hpp"

#include "shprt/bake/object_bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/log.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/object_shade.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/texel_shade.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

struct RenderArgs {
    std::string input, output;
    LightChoice light;  // light/light_setup.hpp, shared with `shade`, `view` and `export`
    ShadingChoice shading;
    CameraChoice camera;
    ObjectChoice object;  // shade/object_shade.hpp, shared with `view`
    std::string size = "1280x720";
    int samples = 4;
    bool background = false, wireframe = false;
};

void run(const RenderArgs& a) {
    const auto start = std::chrono::steady_clock::now();
    check_image_extension(a.output);
    SHPRT_CHECK(a.samples >= 1 && a.samples <= 64, invalid_argument,
                "--samples {}: MSAA samples must be 1 to 64", a.samples);
    check(a.camera);
    int width = 0, height = 0;
    parse_size(a.size, width, height);
    const LightSetup setup = light_setup_from(a.light);
    const ShadingParams params = shading_params(a.shading, setup.sun);
    const std::optional<ObjectPose> pose = object_pose_from(a.object);
    std::vector<std::string> inputs = input_files(a.input, a.light);
    if (pose) inputs.push_back(a.object.object);
    check_output_is_not_input(a.output, inputs);
    check_output_writable(a.output);  // a directory, a device: refused before the work

    ShprtFile file = read_shprt(a.input);
    if (pose) check_probes(file.transfer.probes, a.input);
    const ShadingPlan plan = resolve_shading(params, file, a.input, Spelling::command_line);
    check_texel_view(a.input, file.transfer, params.k, params.view);
    const ShLight light = prepare_light(setup, file.transfer.layout.K);
    std::optional<PreparedSun> sun;
    if (plan.sun) sun = prepare_sun(setup, file.transfer.layout.K);
    DrawSettings settings = draw_settings(plan, params.view);
    settings.camera = camera_from(a.camera, file.mesh, float(width) / float(height), a.input);
    settings.background = a.background;
    settings.wireframe = a.wireframe;
    // The object: baked for its self-shadowing once, lit by the probes under the light.
    std::optional<DynamicObject> object;
    ObjectShading object_shading;
    if (pose) {
        const ProbeGrid& probes = file.transfer.probes;
        ObjectBakeOptions bake_options;
        bake_options.K = probes.K;
        object = load_dynamic_object(a.object.object, bake_options);
        ObjectShadeOptions options = object_shade_options(plan, params.view);
        options.eye = settings.camera.eye;
        object_shading =
            shade_object(*object, *pose, probes, prepare_light(setup, probes.K), options);
        if (object_shading.clamped) log_warn("{}", clamped_warning(probes, pose->position, "--at"));
    }
    const DrawnObject drawn{object ? &object->mesh : nullptr, &object_shading};
    const Image image = render_image(file.mesh, file.transfer, light, settings, width, height,
                                     a.samples, sun ? &*sun : nullptr, object ? &drawn : nullptr);
    save_image(a.output, image, static_cast<float>(params.exposure));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int K_used = effective_basis_size(file.transfer, light, params.coeffs);
    const std::string term =
        plan.glossy ? ", " + describe_terms(plan, file.mesh, K_used) : std::string();
    if (sun)
        std::printf("sun: direct light from a %dx%d shadow map (soft: %g° radius), %s\n",
                    kShadowMapSize, kShadowMapSize, sun->sun.radius_deg,
                    !file.transfer.direct.empty()
                        ? "bounced light from the file's T - T_0"
                        : "no bounced light (the file has no direct part: not an interreflected "
                          "bake, or --direct)");
    if (object)
        std::printf("object: %s (%zu vertices, %s) at %g,%g,%g lit from %zu probes (K'=%d)\n",
                    a.object.object.c_str(), object->mesh.vertex_count(),
                    object->self.coeffs.empty() ? "no self-shadowing" : "self-shadowing baked",
                    pose->position.x, pose->position.y, pose->position.z,
                    file.transfer.probes.count(), object_shading.K_used);
    std::printf("rendered %dx%d (K'=%d, k=%g%s) in %.2f s -> %s\n", width, height, K_used, params.k,
                term.c_str(), seconds, a.output.c_str());
}

const bool render_registered = register_command(
    {"render", "Render a picture of a baked scene (PNG, EXR), headless OpenGL", 60,
     [](CLI::App& app) {
         auto args = std::make_shared<RenderArgs>();
         app.add_option("file", args->input, "Baked .shprt file")->required();
         app.add_option("-o,--output", args->output,
                        "Output image: .png (tone mapped), .exr or .hdr (linear)")
             ->required();
         add_table_options(app, light_option_table(), args->light);
         add_shading_options(app, args->shading,
                             kCoeffsOption | kDeprecatedCoeffsOption | kAlbedoOption | kViewOption,
                             "Exposure multiplier for PNG (default 1)",
                             "Interreflected bakes: the direct light only (the file's T_0), "
                             "without the bounces");
         add_table_options(app, camera_option_table(), args->camera);
         add_table_options(app, object_option_table(), args->object);
         app.add_option("--size", args->size, "Image size WxH (default 1280x720)");
         app.add_flag("--background", args->background,
                      "Draw the light (its SH projection) behind the scene");
         app.add_flag("--wireframe", args->wireframe, "Draw triangle edges only");
         app.add_option("--samples", args->samples, "MSAA samples per pixel (default 4)");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
