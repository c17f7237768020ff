// `shprt view FILE.shprt [options]`: the interactive viewer (GLFW window, OpenGL 4.3 core, ImGui
// panel), and its headless modes:
//   --screenshot OUT.png   one frame without a window (EGL; a hidden GLFW window as fallback),
//                          through render_image and save_image, as `shprt render`
//   --benchmark FRAMES     frames/s against basis size K' = 32, 48, 64, 128, 256, offscreen
//   --bake                 FILE is a scene: bake it in this process and show it while it refines
// Thin: checks every option before any work, parses them into the viewer's ViewRequest (viewer.hpp,
// the viewer's one entry header), runs it, prints its lines on stdout.
#include "shprt/config.hpp"

#if SHPRT_HAS_VIEWER

#include "common/command.hpp"
#include "common/object_options.hpp"
#include "common/option_table.hpp"
#include "common/progress_bar.hpp"
#include "common/shading_options.hpp"

#include "viewer.hpp"

#include "shprt/bake/bake_option_table.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/interrupt.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

struct ViewArgs {
    std::string input;
    LightArgs light;
    CameraChoice camera;
    ObjectArgs object;  // common/object_options.hpp, shared with `render`
    BakeOptionChoice bake;
    bool do_bake = false;
    std::string size = "1280x720";
    ShadingArgs shading;  // its --albedo and --coeffs are the bake options' (below)
    int msaa = viewer::kAutoMsaa;
    bool background = false, wireframe = false, no_vsync = false;
    std::optional<int> benchmark;
    bool benchmark_light = false;
    std::string screenshot;
    // Hidden (tests): close the window after N frames; save its last frame; choose the context.
    std::optional<int> frames;
    std::string window_screenshot, offscreen = "auto";
    // Which bake options were given (only allowed with --bake).
    std::vector<std::string> bake_only_given;
};

bool has_png_extension(const std::string& path) { return lower_extension(path) == ".png"; }

// The request the options describe, every option checked before any work.
viewer::ViewRequest check_view(const ViewArgs& a) {
    // ---- Every option is checked before any work.
    SHPRT_CHECK(a.msaa >= 0 && a.msaa <= 64, invalid_argument,
                "--msaa {}: MSAA samples must be 1 to 64 (or 0: automatic)", a.msaa);
    int width = 0, height = 0;
    parse_size(a.size, width, height);
    check(a.camera);
    // --albedo and --coeffs are registered with the bake options (an interreflected bake's
    // albedo, the K baked). Without --bake, and with a glossy bake (which has no albedo), --albedo
    // overrides the glossy colours; without --bake, --coeffs is the K' shown first.
    const bool bake_glossy = a.do_bake && is_matrix(kind_row(parse_transfer_kind(a.bake.transfer)));
    ShadingArgs shading = a.shading;
    BakeOptionChoice bake_args = a.bake;
    if (!a.do_bake || bake_glossy) {
        shading.albedo = a.bake.albedo;
        bake_args.albedo.clear();
    }
    if (!a.do_bake && a.bake.coeffs)  // the K' shown first: its deprecated name here
        shading.deprecated_coeffs =
            static_cast<int>(std::clamp<long long>(*a.bake.coeffs, -1, 1 << 20));
    const LightSetup setup = light_setup_from(a.light);
    ShadingParams params = shading_params(shading, setup);
    const viewer::OffscreenBackend backend = viewer::parse_offscreen_backend(a.offscreen);
    SHPRT_CHECK(!(a.benchmark && !a.screenshot.empty()), invalid_argument,
                "--benchmark and --screenshot both given; use one");
    SHPRT_CHECK(!a.benchmark || *a.benchmark >= 1, invalid_argument,
                "--benchmark {}: need at least one frame", a.benchmark.value_or(0));
    SHPRT_CHECK(!a.benchmark_light || a.benchmark, invalid_argument,
                "--benchmark-light needs --benchmark FRAMES");
    SHPRT_CHECK(a.screenshot.empty() || has_png_extension(a.screenshot), invalid_argument,
                "--screenshot {}: the viewer writes what it displays, as PNG (use `shprt render` "
                "for .exr/.hdr)",
                a.screenshot);
    SHPRT_CHECK(!a.frames || *a.frames >= 1, invalid_argument, "--frames {}: must be ≥ 1",
                a.frames.value_or(0));
    SHPRT_CHECK(a.window_screenshot.empty() || (a.frames && has_png_extension(a.window_screenshot)),
                invalid_argument, "--window-screenshot {}: needs --frames N and a .png name",
                a.window_screenshot);
    std::vector<std::string> inputs = input_files(a.input, a.light);
    if (!a.object.object.empty()) inputs.push_back(a.object.object);
    for (const std::string& out : {a.screenshot, a.window_screenshot})
        if (!out.empty()) check_output_is_not_input(out, inputs);
    if (!a.do_bake && !a.bake_only_given.empty())
        fail(ErrorCode::invalid_argument, "{} is a bake option: add --bake (FILE is then a scene)",
             a.bake_only_given.front());
    const std::optional<ObjectPose> object_pose = object_pose_from(a.object);
    viewer::ViewRequest r;
    if (a.do_bake) r.bake = bake_options_from(bake_args, Spelling::command_line);
    r.input = a.input;
    r.light = setup;
    r.params = params;
    r.camera = a.camera;
    r.object = a.object.object;
    r.object_pose = object_pose;
    r.width = width, r.height = height, r.msaa = a.msaa;
    r.background = a.background, r.wireframe = a.wireframe, r.vsync = !a.no_vsync;
    r.screenshot = a.screenshot;
    r.benchmark = a.benchmark, r.benchmark_light = a.benchmark_light;
    r.max_frames = a.frames.value_or(0);
    r.window_screenshot = a.window_screenshot;
    r.backend = backend;
    viewer::check(r);
    return r;
}

void run(const ViewArgs& a) {
    viewer::ViewRequest r = check_view(a);
    std::optional<ProgressBar> bar;  // a headless bake's
    r.begin_bake = [&bar] {
        install_interrupt_handler();
        return bar.emplace("bake").callback();
    };
    r.end_bake = [&bar] {
        end_interruptible();  // from here on a signal ends the viewer at once (core/interrupt.hpp)
        bar->finish();
    };
    r.say = [](const std::string& line) { std::fputs(line.c_str(), stdout); };
    try {
        viewer::run_view(r);
    } catch (const Error& e) {
        const std::string what = e.what();
        if (r.windowed() && what.rfind("cannot open a window", 0) == 0)
            fail(e.code(), "{} (without a display, use --screenshot OUT.png or --benchmark N)",
                 what);
        throw;
    }
}

const bool view_registered = register_command(
    {"view", "Interactive viewer (OpenGL window, ImGui panel); --screenshot, --benchmark, --bake",
     70, [](CLI::App& app) {
         auto args = std::make_shared<ViewArgs>();
         app.add_option("file", args->input, "Baked .shprt file (with --bake: a scene to bake)")
             ->required();
         add_light_options(app, args->light);
         add_camera_options(app, args->camera);
         add_object_options(app, args->object);
         app.get_option("--object")
             ->description(
                 "A mesh (any scene file) lit from the file's transfer probes (docs/probes.md); "
                 "in the window G+drag carries it (left button: over the floor, right: up and "
                 "down), the arrow keys move it horizontally and Page Up/Down vertically, and the "
                 "panel shows and edits its position");
         app.add_option("--size", args->size, "Window or image size WxH (default 1280x720)");
         add_shading_options(app, args->shading, kViewOption | kCoeffsOption,
                             "Exposure multiplier (default 1)",
                             "Interreflected bakes: show the direct light only (the file's T_0; "
                             "the panel toggles it)");
         app.add_flag("--background", args->background, "Draw the light behind the scene");
         app.add_flag("--wireframe", args->wireframe, "Draw triangle edges only");
         app.add_option("--msaa", args->msaa,
                        "MSAA samples per pixel; 0 = automatic (default): 4, as `shprt render "
                        "--samples`, but 1 in the window and --benchmark on a software rasteriser "
                        "(llvmpipe), where 4x MSAA more than halves the frame rate");
         app.add_flag("--no-vsync", args->no_vsync, "Do not wait for the display's refresh");
         app.add_flag("--bake", args->do_bake,
                      "FILE is a scene: bake it here and show it while it refines");
         add_table_options(app, bake_option_table(), args->bake);
         // Without --bake, --coeffs is the initial K' (deprecated: --shading-coeffs).
         app.get_option("--coeffs")
             ->description(
                 "With --bake: basis size K to bake (1 to 1024, default 16); otherwise the "
                 "deprecated name of --shading-coeffs");
         app.get_option("--albedo")
             ->description(
                 "With --bake, interreflected: the albedo R,G,B of every vertex; without --bake or "
                 "with a glossy bake: the glossy colour override R,G,B");
         app.add_option("--benchmark", args->benchmark,
                        "Render FRAMES frames offscreen per K' = 32, 48, 64, 128, 256 and print "
                        "frames/s");
         app.add_flag("--benchmark-light", args->benchmark_light,
                      "With --benchmark: also turn the light every frame");
         app.add_option("--screenshot", args->screenshot,
                        "Render one frame without a window into OUT.png and exit");
         app.add_option("--frames", args->frames,
                        "Close the window after N frames (with --bake: N frames after the bake)")
             ->group("");
         app.add_option("--window-screenshot", args->window_screenshot,
                        "With --frames: save the window's last frame (panel included) as PNG")
             ->group("");
         app.add_option("--offscreen", args->offscreen,
                        "Context for --screenshot/--benchmark: auto, egl or window")
             ->group("");
         CLI::App* sub = &app;
         app.callback([args, sub] {
             for (const char* name : {"--transfer", "--bands", "--samples", "--sampler", "--seed",
                                      "--threads", "--device"})
                 if (sub->get_option(name)->count() > 0) args->bake_only_given.push_back(name);
             run(*args);
         });
     }});

}  // namespace
}  // namespace shprt::tools

#endif  // SHPRT_HAS_VIEWER
