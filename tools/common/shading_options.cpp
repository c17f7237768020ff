// Options shared by `shprt render` and `shprt view` (shading_options.hpp).
#include "common/shading_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace shprt::tools {

void add_light_options(CLI::App& app, LightArgs& args) {
    app.add_option("--light", args.lights,
                   "Light spec, repeatable and summed: FILE.hdr|.exr, constant[:R,G,B], "
                   "gradient, sun:X,Y,Z[,RADIUS[,R,G,B]], builtin (default)");
    app.add_option("--rotate", args.rotate, "Rotate the light: YAW,PITCH,ROLL in degrees");
    app.add_option("--window", args.window, "SH window of the light: none, hann, lanczos, sloan");
    app.add_option("--window-strength", args.window_strength,
                   "Window width (hann, lanczos) or lambda (sloan); 0 = default");
}

LightSetup light_setup_from(const LightArgs& args) {
    LightSetup setup;
    setup.specs = args.lights;
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

Camera camera_from(const CameraArgs& args, const Mesh& mesh, float aspect) {
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
    return camera;
}

ShadeView parse_view(const std::string& name) {
    if (name == "radiance") return ShadeView::radiance;
    if (name == "irradiance") return ShadeView::irradiance;
    if (name == "transfer") return ShadeView::transfer;
    fail(ErrorCode::invalid_argument, "--view '{}': expected radiance, irradiance or transfer",
         name);
}

void check_shading_args(double k, double gloss, double exposure) {
    SHPRT_CHECK(k >= 0 && k <= 1, invalid_argument, "--k {}: the diffuse share must be in [0, 1]",
                k);
    SHPRT_CHECK(gloss >= 0 && std::isfinite(gloss), invalid_argument,
                "--gloss {}: the Phong exponent must be ≥ 0", gloss);
    SHPRT_CHECK(exposure > 0 && std::isfinite(exposure), invalid_argument,
                "--exposure {}: must be positive", exposure);
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

}  // namespace shprt::tools
