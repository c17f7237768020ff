// `shprt shade FILE.shprt --light L -o OUT.csv|OUT.ply|OUT.npy`: per-vertex irradiance and
// radiance (render/shade.hpp) under an SH light, in the input vertex order. Thin: checks the
// options, reads the file, prepares the light, shades on the CPU, writes atomically.
#include "common/command.hpp"
#include "common/shading_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/camera.hpp"
#include "shprt/render/shade.hpp"
#include "shprt/render/shade_export.hpp"
#include "shprt/render/sun_shade.hpp"
#include "shprt/render/texel_shade.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

namespace shprt::tools {
namespace {

struct ShadeArgs {
    std::string input, output;
    LightArgs light;  // common/shading_options.hpp, shared with `shprt render` and `shprt view`
    GlossyArgs glossy;
    std::string eye;
    ShadingArgs shading;
    int coeffs = 0;
    int sun_samples = kDefaultSunSamples;
    std::string quantity;  // texel files: irradiance (default) or radiance
};

void run(const ShadeArgs& a) {
    const auto start = Clock::now();
    // Every option is checked before any work (a texel file's image formats once it is read).
    const bool image_output =
        lower_extension(a.output) == ".exr" || lower_extension(a.output) == ".png";
    if (!image_output) shade_format_for_path(a.output);
    SHPRT_CHECK(a.quantity.empty() || a.quantity == "irradiance" || a.quantity == "radiance",
                invalid_argument, "--quantity '{}': expected irradiance or radiance", a.quantity);
    check_shading_args(a.shading);
    SHPRT_CHECK(a.coeffs >= 0, invalid_argument, "--coeffs {}: must be ≥ 1 (0 = all)", a.coeffs);
    check_glossy_args(a.glossy);
    const LightSetup setup = light_setup_from(a.light);
    SHPRT_CHECK(setup.sun || a.sun_samples == kDefaultSunSamples, invalid_argument,
                "--sun-samples {} needs --sun", a.sun_samples);
    if (setup.sun) {
        try {
            (void)sun_disc_directions(*setup.sun, a.sun_samples, 0);
        } catch (const Error& e) {
            fail(e.code(), "--sun-samples: {}", e.what());
        }
    }
    check_output_is_not_input(a.output, input_files(a.input, a.light));
    check_output_writable(a.output);  // a directory, a device: refused before the work
    Vec3f eye{};
    if (!a.eye.empty()) eye = parse_vec3(a.eye, "--eye");

    ShprtFile file = read_for_shading(a.input, a.shading.direct);
    double gloss = a.shading.gloss;
    const GlossyPlan plan = plan_glossy(a.glossy, a.input, file, a.shading.k, gloss);
    const ShLight light = prepare_light(setup, file.transfer.layout.K);
    // Without --eye, the eye of the default `shprt render` camera (16:9), so the glossy term
    // matches the default picture.
    const Vec3f eye_used = a.eye.empty() ? default_camera(file.mesh, 16.0f / 9.0f).eye : eye;
    const bool texel = file.transfer.layout.domain == ReceiverDomain::texel;
    SHPRT_CHECK(texel || a.quantity.empty(), invalid_argument,
                "--quantity is for texel files; {} holds vertex transfer", a.input);
    // The glossy matrix term (plan.glossy) or the diffuse/paper one.
    GlossyShadeOptions glossy_options = plan.glossy.value_or(GlossyShadeOptions{});
    glossy_options.eye = eye_used;
    glossy_options.K_used = a.coeffs;
    ShadeOptions options;
    options.k = a.shading.k;
    options.gloss = gloss;
    options.K_used = a.coeffs;
    options.eye = eye_used;
    // With --sun: the sun kept out of the SH sum, traced (render/sun_shade.hpp); said once.
    const auto shade = [&]() -> ShadeResult {
        if (!setup.sun)
            return shade_receivers(file.mesh, file.transfer, light, options,
                                   plan.glossy ? &glossy_options : nullptr);
        SunShadeOptions sun_options;
        sun_options.disc_samples = a.sun_samples;
        const PreparedSun sun = prepare_sun(setup, file.transfer.layout.K);
        SunShadeResult result =
            shade_with_sun(file.mesh, file.transfer, light, sun, options, sun_options);
        if (result.bounced)
            std::printf(
                "sun: direct light traced at every %s (%d disc direction%s), bounced light "
                "from the file's T - T0\n",
                texel ? "texel" : "vertex", a.sun_samples, a.sun_samples == 1 ? "" : "s");
        else
            std::printf(
                "sun: direct light only, traced at every %s (%d disc direction%s): %s has "
                "no bounced light (%s)\n",
                texel ? "texel" : "vertex", a.sun_samples, a.sun_samples == 1 ? "" : "s",
                a.input.c_str(), a.shading.direct ? "--direct" : "not an interreflected bake");
        return std::move(static_cast<ShadeResult&>(result));
    };
    if (texel) {
        // Per-texel values as an H x W x 3 image (NaN outside the charts).
        const ShadeResult result = shade();
        write_texel_image(a.output, file.transfer.texels,
                          a.quantity == "radiance" ? result.radiance : result.irradiance,
                          static_cast<float>(a.shading.exposure));
        const int K_used = effective_basis_size(file.transfer, light, a.coeffs);
        const std::string term =
            plan.glossy ? ", " + describe_glossy(file.mesh, *plan.glossy, K_used) : std::string();
        std::printf("shaded %zu texels of %dx%d (%s, K'=%d%s) in %.3f s -> %s\n",
                    file.transfer.texels.texel.size(), file.transfer.texels.width,
                    file.transfer.texels.height,
                    a.quantity.empty() ? "irradiance" : a.quantity.c_str(), K_used, term.c_str(),
                    seconds_since(start), a.output.c_str());
        return;
    }
    SHPRT_CHECK(
        !image_output, unsupported,
        "{}: .exr and .png output are for texel files; {} holds vertex transfer (use .csv, .ply or "
        ".npy)",
        a.output, a.input);
    const ShadeResult result = shade();
    write_shade(a.output, file.mesh, result, static_cast<float>(a.shading.exposure));
    const double seconds = seconds_since(start);
    const int K_used = effective_basis_size(file.transfer, light, a.coeffs);
    const std::string term = plan.glossy ? describe_glossy(file.mesh, *plan.glossy, K_used)
                                         : fmt::format("gloss={}", gloss);
    std::printf("shaded %zu vertices (K'=%d, k=%g, %s) in %.3f s -> %s\n", file.mesh.vertex_count(),
                K_used, a.shading.k, term.c_str(), seconds, a.output.c_str());
}

const bool shade_registered = register_command(
    {"shade", "Per-vertex irradiance and radiance under a light (CSV, PLY or NPY)", 50,
     [](CLI::App& app) {
         auto args = std::make_shared<ShadeArgs>();
         app.add_option("file", args->input, "Baked .shprt file")->required();
         app.add_option("-o,--output", args->output,
                        "Output .csv, .ply or .npy (texel files: .npy or .exr)")
             ->required();
         add_light_options(app, args->light);
         add_glossy_options(app, args->glossy);
         add_shading_options(app, args->shading, "Exposure of the PLY colours (default 1)",
                             "Interreflected bakes: the direct light only (the file's T_0), "
                             "without the bounces");
         app.add_option(
             "--eye", args->eye,
             "Eye position X,Y,Z for the glossy term (default: the default render camera)");
         app.add_option("--coeffs", args->coeffs, "Use the first K' coefficients (default: all)");
         app.add_option(
             "--sun-samples", args->sun_samples,
             "With --sun: directions traced on the sun's disc, a square (default 64; 1 = "
             "the centre only, a point sun's hard shadow)");
         app.add_option("--quantity", args->quantity,
                        "Texel files: irradiance (default) or radiance, written as an H x W x 3 "
                        ".npy or .exr (NaN outside the charts), or a .png picture");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
