// Options shared by `shprt render` and `shprt view` (shading_options.hpp).
#include "common/shading_options.hpp"

#include "common/option_table.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace shprt::tools {

void add_light_options(CLI::App& app, LightArgs& args) {
    app.add_option("--light", args.lights,
                   "Light spec, repeatable and summed: FILE.hdr|.exr, constant[:R,G,B], "
                   "gradient, sun:X,Y,Z[,RADIUS[,R,G,B]], builtin (default)");
    app.add_option(
        "--sun", args.sun,
        "X,Y,Z[,RADIUS_DEG[,R,G,B]]: a sun kept out of the SH sum, its direct light "
        "traced (shade) or shadow-mapped (render, view): sharp shadows; its bounces from "
        "an interreflected file; without --light, no sky; export writes it as a glTF "
        "KHR_lights_punctual light");
    app.add_option("--rotate", args.rotate, "Rotate the light: YAW,PITCH,ROLL in degrees");
    app.add_option("--window", args.window, "SH window of the light: none, hann, lanczos, sloan");
    app.add_option("--window-strength", args.window_strength,
                   "Window width (hann, lanczos) or lambda (sloan); 0 = default");
}

LightSetup light_setup_from(const LightArgs& args) {
    LightSetup setup;
    setup.specs = args.lights;
    if (!args.sun.empty())
        setup.sun = parse_sun(args.sun, "--sun '" + args.sun + "'", "X,Y,Z[,RADIUS_DEG[,R,G,B]]");
    setup.window = parse_window_kind(args.window);
    setup.window_strength = args.window_strength;
    if (!args.rotate.empty()) setup.yaw_pitch_roll_deg = parse_yaw_pitch_roll(args.rotate);
    return setup;
}

std::vector<std::string> input_files(const std::string& file, const LightArgs& args) {
    std::vector<std::string> files{file};
    for (const std::string& spec : args.lights)
        for (std::string& f : light_spec_files(spec)) files.push_back(std::move(f));
    return files;
}

void add_camera_options(CLI::App& app, CameraChoice& choice) {
    app.add_option("--camera", choice.camera,
                   "EX,EY,EZ,TX,TY,TZ: eye and target (default: frames the scene)");
    app.add_option("--fov", choice.fov, "Vertical field of view, degrees");
}

void add_shading_options(CLI::App& app, ShadingArgs& args, unsigned extra,
                         const std::string& exposure_help, const std::string& direct_help) {
    std::vector<std::string> leave_out;
    if (!(extra & kCoeffsOption)) leave_out.push_back("shading_coeffs");
    if (!(extra & kSunSamplesOption)) leave_out.push_back("sun_samples");
    add_table_options(app, shading_option_table(), args.params, leave_out);
    app.get_option("--exposure")->description(exposure_help);
    app.get_option("--direct")->description(direct_help);
    app.add_option("--brdf", args.brdf,
                   "Glossy bakes: the BRDF lobe phong:E (normalised Phong), blinn:E (Blinn-Phong) "
                   "or ggx:R (roughness), optionally :R,G,B, its specular colour (default white); "
                   "with --k the diffuse share");
    app.add_option("--glossy", args.glossy,
                   "matrix (default: transfer matrices, needs a glossy bake) or paper (the "
                   "paper's zonal term; a glossy bake is turned into diffuse transfer)");
    if (extra & kDeprecatedCoeffsOption)
        app.add_option("--coeffs", args.deprecated_coeffs,
                       "Deprecated here: --shading-coeffs (bake's --coeffs is the K baked)");
    if (extra & kAlbedoOption)
        app.add_option("--albedo", args.albedo,
                       "Glossy shading: R,G,B (linear, 0 to 1) overriding the diffuse and "
                       "specular colours");
    if (extra & kViewOption)
        app.add_option("--view", args.view,
                       "radiance (default), irradiance, or transfer (AO-like, light ignored)");
    if (extra & kEyeOption)
        app.add_option("--eye", args.eye,
                       "Eye position X,Y,Z for the glossy term (default: the default render "
                       "camera)");
}

ShadingParams shading_params(const ShadingArgs& args, const LightSetup& light) {
    constexpr Spelling cli = Spelling::command_line;
    ShadingParams p = args.params;
    SHPRT_CHECK(!(p.coeffs != 0 && args.deprecated_coeffs), invalid_argument,
                "--coeffs {} and --shading-coeffs {}: give --shading-coeffs alone (--coeffs is "
                "its deprecated name here)",
                args.deprecated_coeffs.value_or(0), p.coeffs);
    if (args.deprecated_coeffs)
        log_warn(
            "--coeffs {0} is deprecated in shading: it means K' here and K in bake; use "
            "--shading-coeffs {0}",
            *args.deprecated_coeffs);
    if (args.deprecated_coeffs) p.coeffs = *args.deprecated_coeffs;
    p.view = parse_view(args.view, cli);
    p.glossy = parse_glossy_term(args.glossy, cli);
    if (!args.brdf.empty()) p.brdf = parse_brdf(args.brdf);
    if (!args.albedo.empty()) {
        const std::vector<double> rgb = parse_numbers(args.albedo, 3, "--albedo R,G,B");
        p.albedo = Vec3f{float(rgb[0]), float(rgb[1]), float(rgb[2])};
    }
    if (!args.eye.empty()) p.eye = parse_vec3(args.eye, "--eye");
    p.sun = light.sun;
    check(p, cli);
    return p;
}

}  // namespace shprt::tools
