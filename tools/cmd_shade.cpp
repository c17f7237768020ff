// `shprt shade FILE.shprt --light L -o OUT.csv|OUT.ply|OUT.npy`: per-vertex irradiance and
// radiance (shade/shade.hpp) under an SH light, in the input vertex order. Thin: checks the
// options, reads the file, prepares the light, shades on the CPU, writes atomically.
#include "common/command.hpp"
#include "common/option_table.hpp"
#include "common/shading_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/shade/params.hpp"
#include "shprt/shade/shade_export.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

namespace shprt::tools {
namespace {

struct ShadeArgs {
    std::string input, output;
    LightChoice light;  // light/light_setup.hpp, shared with `render`, `view` and `export`
    ShadingChoice shading;
    std::string quantity;  // texel files: irradiance (default) or radiance
};

// "sun: direct light traced at every vertex (64 disc directions), bounced light from ...".
std::string describe_sun(const ShadeArgs& a, const SunShadeResult& result, bool texel) {
    const int n = a.shading.params.sun_samples;
    const std::string traced = fmt::format("traced at every {} ({} disc direction{})",
                                           texel ? "texel" : "vertex", n, n == 1 ? "" : "s");
    if (result.bounced)
        return fmt::format("sun: direct light {}, bounced light from the file's T - T0", traced);
    return fmt::format("sun: direct light only, {}: {} has no bounced light ({})", traced, a.input,
                       a.shading.params.direct ? "--direct" : "not an interreflected bake");
}

void run(const ShadeArgs& a) {
    const auto start = Clock::now();
    // Every option is checked before any work (a texel file's image formats once it is read).
    const bool image_output =
        lower_extension(a.output) == ".exr" || lower_extension(a.output) == ".png";
    if (!image_output) shade_format_for_path(a.output);
    SHPRT_CHECK(a.quantity.empty() || a.quantity == "irradiance" || a.quantity == "radiance",
                invalid_argument, "--quantity '{}': expected irradiance or radiance", a.quantity);
    const LightSetup setup = light_setup_from(a.light);
    const ShadingParams params = shading_params(a.shading, setup.sun);
    check_output_is_not_input(a.output, input_files(a.input, a.light));
    check_output_writable(a.output);  // a directory, a device: refused before the work

    ShprtFile file = read_shprt(a.input);
    const ShadingPlan plan = resolve_shading(params, file, a.input, Spelling::command_line);
    const ShLight light = prepare_light(setup, file.transfer.layout.K);
    const bool texel = is_texel(file.transfer.layout);
    SHPRT_CHECK(texel || a.quantity.empty(), invalid_argument,
                "--quantity is for texel files; {} holds vertex transfer", a.input);
    SHPRT_CHECK(
        texel || !image_output, unsupported,
        "{}: .exr and .png output are for texel files; {} holds vertex transfer (use .csv, .ply, "
        ".npy or .npz)",
        a.output, a.input);
    std::optional<PreparedSun> sun;
    if (plan.sun) sun = prepare_sun(setup, file.transfer.layout.K);
    const SunShadeResult result = shade_file(file, light, plan, sun ? &*sun : nullptr);
    if (sun) std::printf("%s\n", describe_sun(a, result, texel).c_str());
    const float exposure = static_cast<float>(params.exposure);
    const int K_used = effective_basis_size(file.transfer, light, params.coeffs);
    if (texel) {
        // Per-texel values as an H x W x 3 image (NaN outside the charts).
        write_texel_image(a.output, file.transfer.texels,
                          a.quantity == "radiance" ? result.radiance : result.irradiance, exposure);
        const std::string term =
            plan.glossy ? ", " + describe_terms(plan, file.mesh, K_used) : std::string();
        std::printf("shaded %zu texels of %dx%d (%s, K'=%d%s) in %.3f s -> %s\n",
                    file.transfer.texels.texel.size(), file.transfer.texels.width,
                    file.transfer.texels.height,
                    a.quantity.empty() ? "irradiance" : a.quantity.c_str(), K_used, term.c_str(),
                    seconds_since(start), a.output.c_str());
        return;
    }
    write_shade(a.output, file.mesh, result, exposure);
    std::printf("shaded %zu vertices (K'=%d, k=%g, %s) in %.3f s -> %s\n", file.mesh.vertex_count(),
                K_used, params.k, describe_terms(plan, file.mesh, K_used).c_str(),
                seconds_since(start), a.output.c_str());
}

const bool shade_registered = register_command(
    {"shade", "Per-vertex irradiance and radiance under a light (CSV, PLY or NPY)", 50,
     [](CLI::App& app) {
         auto args = std::make_shared<ShadeArgs>();
         app.add_option("file", args->input, "Baked .shprt file")->required();
         app.add_option("-o,--output", args->output,
                        "Output .csv, .ply, .npy or .npz (texel files: .npy, .exr or .png)")
             ->required();
         add_table_options(app, light_option_table(), args->light);
         add_shading_options(app, args->shading,
                             kCoeffsOption | kDeprecatedCoeffsOption | kAlbedoOption | kEyeOption |
                                 kSunSamplesOption,
                             "Exposure of the PLY colours (default 1)",
                             "Interreflected bakes: the direct light only (the file's T_0), "
                             "without the bounces");
         app.add_option("--quantity", args->quantity,
                        "Texel files: irradiance (default) or radiance, written as an H x W x 3 "
                        ".npy or .exr (NaN outside the charts), or a .png picture");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
