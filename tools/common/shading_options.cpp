// Options shared by `shprt render` and `shprt view` (shading_options.hpp).
#include "common/shading_options.hpp"

#include "common/bake_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
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
    app.add_option("--sun", args.sun,
                   "X,Y,Z[,RADIUS_DEG[,R,G,B]]: a sun kept out of the SH sum, its direct light "
                   "traced (sharp shadows), its bounces from an interreflected file (shade only); "
                   "without --light, no sky");
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

void refuse_sun(const LightArgs& args, const std::string& command) {
    SHPRT_CHECK(args.sun.empty(), unsupported,
                "--sun: `shprt {}` does not draw a sun kept out of the SH sum yet (issue 36); "
                "`shprt shade --sun` traces it, --light sun:{} projects it into SH",
                command, args.sun);
}

std::vector<std::string> input_files(const std::string& file, const LightArgs& args) {
    std::vector<std::string> files{file};
    for (const std::string& spec : args.lights)
        for (std::string& f : light_spec_files(spec)) files.push_back(std::move(f));
    return files;
}

void add_camera_options(CLI::App& app, CameraArgs& args) {
    app.add_option("--camera", args.camera,
                   "EX,EY,EZ,TX,TY,TZ: eye and target (default: frames the scene)");
    app.add_option("--fov", args.fov, "Vertical field of view, degrees");
}

void check_camera_args(const CameraArgs& args) {
    SHPRT_CHECK(!args.fov || (*args.fov > 0 && *args.fov < 180), invalid_argument,
                "--fov {}: must be in (0, 180) degrees", args.fov.value_or(0));
    Camera parsed;
    if (!args.camera.empty()) parse_camera(args.camera, parsed);
}

Camera camera_from(const CameraArgs& args, const Mesh& mesh, float aspect,
                   const std::string& input) {
    check_camera_args(args);
    Camera camera;
    if (args.camera.empty()) {
        camera = default_camera(mesh, aspect);
    } else {
        Camera parsed;
        parse_camera(args.camera, parsed);
        camera = look_at_camera(parsed.eye, parsed.target, Camera{}.fov_y_deg, mesh_bounds(mesh));
    }
    if (args.fov) camera.fov_y_deg = static_cast<float>(*args.fov);
    // A camera without a frame (eye and target too far apart or too large for single precision,
    // or a scene whose positions are): say which option or file it came from.
    try {
        (void)view_matrix(camera);
    } catch (const Error& e) {
        if (!args.camera.empty())
            fail(ErrorCode::invalid_argument,
                 "--camera {}: {} (the coordinates are too large for single precision, or the "
                 "up axis +Y is the view direction)",
                 args.camera, e.what());
        fail(ErrorCode::format,
             "{}: cannot frame the scene with the default camera: {} (its positions are too large "
             "for single precision); give --camera EX,EY,EZ,TX,TY,TZ",
             input, e.what());
    }
    return camera;
}

ShadeView parse_view(const std::string& name) {
    if (name == "radiance") return ShadeView::radiance;
    if (name == "irradiance") return ShadeView::irradiance;
    if (name == "transfer") return ShadeView::transfer;
    fail(ErrorCode::invalid_argument, "--view '{}': expected radiance, irradiance or transfer",
         name);
}

void add_shading_options(CLI::App& app, ShadingArgs& args, const std::string& exposure_help,
                         const std::string& direct_help) {
    app.add_option("--k", args.k, "Diffuse share k in [0, 1] (default 1: pure diffuse)");
    app.add_option("--gloss", args.gloss, "Phong exponent of the glossy lobe (default 16)");
    app.add_option("--exposure", args.exposure, exposure_help);
    app.add_flag("--direct", args.direct, direct_help);
}

void check_shading_args(const ShadingArgs& a) {
    SHPRT_CHECK(a.k >= 0 && a.k <= 1, invalid_argument,
                "--k {}: the diffuse share must be in [0, 1]", a.k);
    SHPRT_CHECK(a.gloss >= 0 && std::isfinite(a.gloss), invalid_argument,
                "--gloss {}: the Phong exponent must be ≥ 0", a.gloss);
    SHPRT_CHECK(a.exposure > 0 && std::isfinite(a.exposure), invalid_argument,
                "--exposure {}: must be positive", a.exposure);
}

void check_texel_view(const std::string& path, const TransferSet& transfer, double k,
                      ShadeView view) {
    SHPRT_CHECK(transfer.layout.domain != ReceiverDomain::texel ||
                    transfer.layout.shape != TransferShape::vector || k >= 1 ||
                    view != ShadeView::radiance,
                unsupported,
                "{}: --k {}: diffuse texel transfer is drawn diffuse (k = 1); the paper's glossy "
                "term is not drawn per texel (a glossy bake's matrices are)",
                path, k);
}

void check_image_extension(const std::string& path) {
    const std::string ext = lower_extension(path);
    SHPRT_CHECK(ext == ".png" || ext == ".exr" || ext == ".hdr", invalid_argument,
                "output {}: unknown image format (expected .png, .exr or .hdr)", path);
}

ShprtFile read_for_shading(const std::string& path, bool direct) {
    ShprtFile file = read_shprt(path);
    if (direct) {
        SHPRT_CHECK(!file.transfer.direct.empty(), invalid_argument,
                    "--direct: {} has no direct part (only interreflected bakes keep one)", path);
        file.transfer = file.transfer.direct_only();
    }
    return file;
}

void add_glossy_options(CLI::App& app, GlossyArgs& args, bool with_albedo) {
    app.add_option("--brdf", args.brdf,
                   "Glossy bakes: the BRDF lobe phong:E (normalised Phong), blinn:E (Blinn-Phong) "
                   "or ggx:R (roughness), optionally :R,G,B, its specular colour (default white); "
                   "with --k the diffuse share");
    app.add_option("--glossy", args.glossy,
                   "matrix (default: transfer matrices, needs a glossy bake) or paper (the "
                   "paper's zonal term; a glossy bake is turned into diffuse transfer)");
    if (with_albedo)
        app.add_option("--albedo", args.albedo,
                       "Glossy shading: R,G,B (linear, 0 to 1) overriding the diffuse and "
                       "specular colours");
}

void check_glossy_args(const GlossyArgs& args) {
    SHPRT_CHECK(args.glossy == "matrix" || args.glossy == "paper", invalid_argument,
                "--glossy '{}': expected matrix or paper", args.glossy);
    if (!args.brdf.empty()) parse_brdf(args.brdf);
    if (!args.albedo.empty()) {
        SHPRT_CHECK(args.glossy == "matrix", invalid_argument,
                    "--albedo needs the matrix term (--glossy matrix)");
        parse_albedo(args.albedo);
    }
}

GlossyPlan plan_glossy(const GlossyArgs& args, const std::string& path, ShprtFile& file, double k,
                       double& gloss) {
    const bool matrices = file.transfer.layout.shape != TransferShape::vector;
    GlossyPlan plan;
    if (args.glossy == "paper") {
        std::optional<Brdf> brdf;
        if (!args.brdf.empty()) brdf = parse_brdf(args.brdf);
        SHPRT_CHECK(!brdf || brdf->model == BrdfModel::phong, invalid_argument,
                    "--glossy paper: the paper's term has a Phong lobe only (--brdf phong:E)");
        SHPRT_CHECK(!brdf || brdf->specular == (Vec3f{1, 1, 1}), invalid_argument,
                    "--glossy paper: the paper's term has no specular colour (--brdf phong:E)");
        if (brdf) gloss = brdf->parameter;
        if (matrices) file.transfer = glossy_to_diffuse(file.mesh, file.transfer);
        return plan;
    }
    // Without --brdf, a glossy file whose materials give BRDFs is shaded with them.
    const bool materials = matrices && args.brdf.empty() && !file.mesh.brdf_index.empty();
    SHPRT_CHECK(!matrices || !args.brdf.empty() || materials, invalid_argument,
                "{}: glossy transfer matrices need --brdf phong:E|blinn:E|ggx:R (or --glossy "
                "paper): the scene's materials give no BRDF",
                path);
    if (args.brdf.empty() && !materials) {
        SHPRT_CHECK(args.albedo.empty(), invalid_argument, "--albedo needs --brdf");
        return plan;
    }
    SHPRT_CHECK(matrices, invalid_argument,
                "{}: {} transfer is diffuse (a vector per vertex): --brdf needs a glossy bake "
                "(--transfer glossy), or use --gloss",
                path, to_string(file.transfer.kind));
    GlossyShadeOptions o;
    if (materials) {
        o.material_brdfs = true;  // o.brdf (--gloss's Phong lobe) where a material gives none
        o.brdf = Brdf{BrdfModel::phong, gloss};
        check_brdf(o.brdf);
    } else {
        o.brdf = parse_brdf(args.brdf);
    }
    o.k = k;
    if (!args.albedo.empty()) o.albedo = parse_albedo(args.albedo);
    plan.glossy = o;
    return plan;
}

std::string describe_brdf(const Brdf& brdf, int K) {
    const int bands = sh_bands_for(K);
    return fmt::format("brdf={}, zonal fit error {:.1f}% at {} bands", to_string(brdf),
                       100 * brdf_lobe(brdf, bands).fit_error, bands);
}

std::string describe_glossy(const Mesh& mesh, const GlossyShadeOptions& options, int K) {
    if (!options.material_brdfs || mesh.brdf_index.empty()) return describe_brdf(options.brdf, K);
    const int bands = sh_bands_for(K);
    double worst = 0;
    for (const Brdf& b : brdf_table(mesh, true, options.brdf))
        worst = std::max(worst, brdf_lobe(b, bands).fit_error);
    return fmt::format("brdf=materials: {}; none = {}; worst zonal fit error {:.1f}% at {} bands",
                       describe_brdfs(mesh), to_string(options.brdf), 100 * worst, bands);
}

}  // namespace shprt::tools
