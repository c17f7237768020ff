// `shprt render FILE.shprt --light L -o IMAGE.png|IMAGE.exr`: a picture of the shaded scene,
// headless (OpenGL 4.3 core through EGL; Mesa's llvmpipe where there is no GPU). Thin: checks
// the options, reads the file, prepares the light, calls render_image, saves (PNG: exposure +
// filmic tone map + sRGB; EXR/HDR: linear).
#include "common/command.hpp"
#include "common/shading_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/camera.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/render/save_image.hpp"

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
    LightArgs light;  // common/shading_options.hpp, shared with `shprt view`
    GlossyArgs glossy;
    CameraArgs camera;
    std::string size = "1280x720", view = "radiance";
    ShadingArgs shading;
    int coeffs = 0, samples = 4;
    bool background = false, wireframe = false;
};

void run(const RenderArgs& a) {
    refuse_sun(a.light, "render");
    const auto start = std::chrono::steady_clock::now();
    check_image_extension(a.output);
    check_shading_args(a.shading);
    SHPRT_CHECK(a.coeffs >= 0, invalid_argument, "--coeffs {}: must be ≥ 1 (0 = all)", a.coeffs);
    SHPRT_CHECK(a.samples >= 1 && a.samples <= 64, invalid_argument,
                "--samples {}: MSAA samples must be 1 to 64", a.samples);
    check_camera_args(a.camera);
    check_glossy_args(a.glossy);
    int width = 0, height = 0;
    parse_size(a.size, width, height);
    const LightSetup setup = light_setup_from(a.light);
    check_output_is_not_input(a.output, input_files(a.input, a.light));
    check_output_writable(a.output);  // a directory, a device: refused before the work
    DrawSettings settings;
    settings.view = parse_view(a.view);
    settings.k = a.shading.k;
    settings.gloss = a.shading.gloss;
    settings.K_used = a.coeffs;
    settings.background = a.background;
    settings.wireframe = a.wireframe;

    ShprtFile file = read_for_shading(a.input, a.shading.direct);
    check_texel_view(a.input, file.transfer, a.shading.k, settings.view);
    double gloss = a.shading.gloss;
    const GlossyPlan plan = plan_glossy(a.glossy, a.input, file, a.shading.k, gloss);
    settings.gloss = gloss;
    const ShLight light = prepare_light(setup, file.transfer.layout.K);
    const float aspect = float(width) / float(height);
    settings.camera = camera_from(a.camera, file.mesh, aspect, a.input);

    if (plan.glossy) {  // transfer matrices, shaded on the GPU (render/renderer.hpp)
        settings.brdf = plan.glossy->brdf;
        settings.material_brdfs = plan.glossy->material_brdfs;
        settings.albedo = plan.glossy->albedo;
    }
    const Image image =
        render_image(file.mesh, file.transfer, light, settings, width, height, a.samples);
    save_image(a.output, image, static_cast<float>(a.shading.exposure));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int K_used = effective_basis_size(file.transfer, light, a.coeffs);
    const std::string term =
        plan.glossy ? ", " + describe_glossy(file.mesh, *plan.glossy, K_used) : std::string();
    std::printf("rendered %dx%d (K'=%d, k=%g%s) in %.2f s -> %s\n", width, height, K_used,
                a.shading.k, term.c_str(), seconds, a.output.c_str());
}

const bool render_registered = register_command(
    {"render", "Render a picture of a baked scene (PNG, EXR), headless OpenGL", 60,
     [](CLI::App& app) {
         auto args = std::make_shared<RenderArgs>();
         app.add_option("file", args->input, "Baked .shprt file")->required();
         app.add_option("-o,--output", args->output,
                        "Output image: .png (tone mapped), .exr or .hdr (linear)")
             ->required();
         add_light_options(app, args->light);
         add_glossy_options(app, args->glossy);
         add_shading_options(app, args->shading, "Exposure multiplier for PNG (default 1)",
                             "Interreflected bakes: the direct light only (the file's T_0), "
                             "without the bounces");
         add_camera_options(app, args->camera);
         app.add_option("--size", args->size, "Image size WxH (default 1280x720)");
         app.add_option("--coeffs", args->coeffs, "Use the first K' coefficients (default: all)");
         app.add_option("--view", args->view,
                        "radiance (default), irradiance, or transfer (AO-like, light ignored)");
         app.add_flag("--background", args->background,
                      "Draw the light (its SH projection) behind the scene");
         app.add_flag("--wireframe", args->wireframe, "Draw triangle edges only");
         app.add_option("--samples", args->samples, "MSAA samples per pixel (default 4)");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
