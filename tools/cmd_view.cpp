// `shprt view FILE.shprt [options]`: the interactive viewer (GLFW window, OpenGL 4.3 core, ImGui
// panel), and its headless modes:
//   --screenshot OUT.png   one frame without a window (EGL; a hidden GLFW window as fallback),
//                          through render_image and save_image, as `shprt render`
//   --benchmark FRAMES     frames/s against basis size K' = 32, 48, 64, 128, 256, offscreen
//   --bake                 FILE is a scene: bake it in this process and show it while it refines
// Thin: checks every option before any work, reads or bakes, calls viewer/ (shprt_viewer),
// reports on stdout.
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
#include "shprt/bake/object_bake.hpp"
#include "shprt/bake/request.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/interrupt.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/shade/object_shade.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/shade.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

struct ViewArgs {
    std::string input;
    LightArgs light;
    CameraArgs camera;
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

// Bakes before a headless mode (no window to show the progress in): the usual progress bar.
TransferSet bake_now(const Mesh& mesh, BakeOptions options) {
    install_interrupt_handler();
    ProgressBar bar("bake");
    BakeRequest request;
    request.options = std::move(options);
    request.options.progress = bar.callback();
    const auto start = Clock::now();
    TransferSet t = shprt::run(request, mesh).transfer;
    end_interruptible();  // from here on a signal ends the viewer at once (core/interrupt.hpp)
    bar.finish();
    std::printf("baked %zu vertices, K=%d, S=%d in %.2f s (%s)\n", mesh.vertex_count(), t.layout.K,
                t.samples, seconds_since(start), t.stats.device_name.c_str());
    return t;
}

// Everything the command line decides, checked before any work.
struct ViewSetup {
    LightSetup setup;
    ShadingParams params;
    viewer::OffscreenBackend backend = viewer::OffscreenBackend::automatic;
    int width = 0, height = 0;
    bool windowed = false;                    // neither --screenshot nor --benchmark
    std::optional<BakeOptions> bake_options;  // --bake
    std::optional<ObjectPose> object_pose;    // --object
};

ViewSetup check_view(const ViewArgs& a) {
    // ---- Every option is checked before any work.
    SHPRT_CHECK(a.msaa >= 0 && a.msaa <= 64, invalid_argument,
                "--msaa {}: MSAA samples must be 1 to 64 (or 0: automatic)", a.msaa);
    int width = 0, height = 0;
    parse_size(a.size, width, height);
    check_camera_args(a.camera);
    // --albedo and --coeffs are registered with the bake options (an interreflected bake's
    // albedo, the K baked). Without --bake, and with a glossy bake (which has no albedo), --albedo
    // overrides the glossy colours; without --bake, --coeffs is the K' shown first.
    const bool bake_glossy =
        a.do_bake && parse_transfer_kind(a.bake.transfer) == TransferKind::glossy;
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
    SHPRT_CHECK(!a.do_bake || bake_glossy || !params.brdf, invalid_argument,
                "--brdf shades glossy transfer matrices: with --bake, add --transfer glossy");
    SHPRT_CHECK(!(params.direct && a.do_bake), invalid_argument,
                "--direct shows a baked file's direct part; with --bake, bake with "
                "--transfer shadowed instead");
    const bool windowed = a.screenshot.empty() && !a.benchmark;
    // The window draws the matrices as their rows arrive; the paper's term replaces them with
    // vectors, which a finished bake can give (--screenshot, --benchmark), not a refining one.
    SHPRT_CHECK(!(bake_glossy && windowed && params.glossy == GlossyTerm::paper), unsupported,
                "--glossy paper: the window shows a glossy bake's matrices while they refine "
                "(use --brdf phong:E, or bake the file first and view it with --glossy paper)");
    const std::optional<ObjectPose> object_pose = object_pose_from(a.object);
    SHPRT_CHECK(!(object_pose && a.do_bake), invalid_argument,
                "--object is lit from a baked file's probes: bake FILE with shprt bake --probes "
                "first, then view it without --bake");
    std::optional<BakeOptions> bake_options;
    if (a.do_bake) {
        bake_options = bake_options_from(bake_args, Spelling::command_line);
        resolve_device(bake_options->device, bake_options->device_index);  // fail before a window
    }

    return {setup, params, backend, width, height, windowed, std::move(bake_options), object_pose};
}

// The scene (a file, or with --bake one baked here or, for the window, all-zero rows refined as
// they arrive); a glossy file without a BRDF gets --gloss's Phong lobe in v.params.
ShprtFile view_scene(const ViewArgs& a, ViewSetup& v) {
    ShprtFile file;
    if (a.do_bake) {
        file.mesh = load_scene(a.input);
        file.transfer = v.windowed ? TransferSet::zeros(bake_description(*v.bake_options),
                                                        file.mesh.vertex_count())
                                   : bake_now(file.mesh, *v.bake_options);
    } else {
        // The window keeps the whole transfer (its panel toggles the direct part); a screenshot
        // or a benchmark shows what --direct asks for.
        file = read_shprt(a.input);
        if (v.params.direct && v.windowed)
            SHPRT_CHECK(!file.transfer.direct.empty(), invalid_argument,
                        "--direct: {} has no direct part (only interreflected bakes keep one)",
                        a.input);
        check_texel_view(a.input, file.transfer, v.params.k, v.params.view);
    }
    // Glossy matrices are shaded with --brdf, else with the materials' BRDFs, else with --gloss's
    // Phong lobe (the panel changes the BRDF live); --glossy paper turns them into the paper's
    // term.
    if (file.transfer.layout.shape == TransferShape::symmetric_matrix && !v.params.brdf &&
        v.params.glossy == GlossyTerm::matrix && file.mesh.brdf_index.empty())
        v.params.brdf = Brdf{BrdfModel::phong, v.params.gloss};
    return file;
}

void take_screenshot(const ViewArgs& a, const ViewSetup& v, const ShprtFile& file,
                     const viewer::LightRig& rig, const viewer::FrameConfig& config,
                     const viewer::ViewerObject& object, Clock::time_point start) {
    const ShLight light = rig.light();
    std::optional<PreparedSun> sun;  // turned as `light`
    if (v.setup.sun) sun = prepare_sun(v.setup, rig.K());
    ObjectShading lit;
    if (object.object) {
        ObjectShadeOptions options = object.options;
        options.eye = config.draw.camera.eye;
        lit = shade_object(*object.object, object.pose, *object.probes, light, options);
    }
    const DrawnObject drawn{object.object ? &object.object->mesh : nullptr, &lit};
    std::string context;
    const Image image =
        viewer::render_screenshot(file.mesh, file.transfer, light, config, v.backend, &context,
                                  sun ? &*sun : nullptr, object.object ? &drawn : nullptr);
    save_image(a.screenshot, image, config.exposure);
    std::printf("screenshot %dx%d (K'=%d, k=%g) in %.2f s -> %s\n", v.width, v.height,
                effective_basis_size(file.transfer, light, v.params.coeffs), v.params.k,
                seconds_since(start), a.screenshot.c_str());
}

void run_view_benchmark(const ViewArgs& a, const ViewSetup& v, const ShprtFile& file,
                        const viewer::LightRig& rig, const viewer::FrameConfig& config,
                        const viewer::ViewerObject& object, const std::string& name) {
    viewer::BenchmarkOptions options;
    options.frames = *a.benchmark;
    options.rotate_light = a.benchmark_light;
    // Glossy matrices have at most 8 bands: measure the file's own K.
    if (file.transfer.layout.shape == TransferShape::symmetric_matrix)
        options.K_values = {file.transfer.layout.K};
    // With an object: the file's own K, the object moving every frame.
    options.object = object;
    if (object.object) options.K_values = {std::min(file.transfer.layout.K, rig.K())};
    options.backend = v.backend;
    const viewer::BenchmarkReport report =
        viewer::run_benchmark(file.mesh, file.transfer, rig, config, options);
    std::printf("%s: ", name.c_str());
    std::fputs(viewer::format_benchmark(report).c_str(), stdout);
}

void run_view_window(const ViewArgs& a, const ViewSetup& v, const ShprtFile& file,
                     const viewer::FrameConfig& config, const viewer::ViewerObject& object,
                     const std::string& name) {
    viewer::WindowOptions options;
    options.frame = config;
    options.light = v.setup;
    options.title = "shprt view — " + name;
    options.scene_label = name;
    options.max_frames = a.frames.value_or(0);
    options.window_screenshot = a.window_screenshot;
    options.vsync = !a.no_vsync;
    options.direct_only = v.params.direct;
    options.object = object;
    viewer::WindowReport report;
    try {
        report = viewer::run_window(file.mesh, file.transfer, options, v.bake_options);
    } catch (const Error& e) {
        const std::string what = e.what();
        if (what.rfind("cannot open a window", 0) == 0)
            fail(e.code(), "{} (without a display, use --screenshot OUT.png or --benchmark N)",
                 what);
        throw;
    }
    std::printf("view: %d frames in %.2f s (%.1f frames/s); %s\n", report.frames, report.seconds,
                report.seconds > 0 ? report.frames / report.seconds : 0.0, report.context.c_str());
    if (a.do_bake && report.bake_finished)
        std::printf("baked %zu vertices, K=%d in %.2f s\n", file.mesh.vertex_count(),
                    v.bake_options->K, report.bake_seconds);
    SHPRT_CHECK(report.bake_error.empty(), unsupported, "bake failed: {}", report.bake_error);
}

void run(const ViewArgs& a) {
    const auto start = Clock::now();
    ViewSetup v = check_view(a);
    ShprtFile file = view_scene(a, v);
    if (v.object_pose) check_probes(file.transfer.probes, a.input);
    // The window keeps the whole transfer (its panel toggles the direct part); a screenshot or a
    // benchmark shows what --direct asks for.
    ShadingParams resolved = v.params;
    resolved.direct = v.params.direct && !v.windowed;
    const ShadingPlan plan = resolve_shading(resolved, file, a.input, Spelling::command_line);
    viewer::LightRig rig(std::min(file.transfer.layout.K, kMaxLightK));
    rig.set_source(v.setup);  // a missing light file fails here, before any window

    viewer::FrameConfig config;
    config.width = v.width;
    config.height = v.height;
    config.msaa = a.msaa;
    config.exposure = static_cast<float>(v.params.exposure);
    config.draw = draw_settings(plan, v.params.view);
    config.draw.camera =
        camera_from(a.camera, file.mesh, float(v.width) / float(v.height), a.input);
    config.draw.background = a.background;
    config.draw.wireframe = a.wireframe;
    const std::string name = std::filesystem::path(a.input).filename().string();
    // The object: baked for its self-shadowing once, then lit by the probes every time it or
    // the light moves.
    std::optional<DynamicObject> object;
    viewer::ViewerObject shown;
    if (v.object_pose) {
        const ProbeGrid& probes = file.transfer.probes;
        ObjectBakeOptions bake_options;
        bake_options.K = probes.K;
        object = load_dynamic_object(a.object.object, bake_options);
        shown = {&*object, &probes, *v.object_pose, object_shade_options(plan, v.params.view),
                 std::filesystem::path(a.object.object).filename().string()};
        if (sample_probes(probes, v.object_pose->position).clamped)
            log_warn("{}", clamped_warning(probes, v.object_pose->position, "--at"));
        std::printf("object: %s (%zu vertices, %s) at %g,%g,%g lit from %zu probes\n",
                    a.object.object.c_str(), object->mesh.vertex_count(),
                    object->self.coeffs.empty() ? "no self-shadowing" : "self-shadowing baked",
                    v.object_pose->position.x, v.object_pose->position.y, v.object_pose->position.z,
                    probes.count());
    }
    if (!a.screenshot.empty())
        take_screenshot(a, v, file, rig, config, shown, start);
    else if (a.benchmark)
        run_view_benchmark(a, v, file, rig, config, shown, name);
    else
        run_view_window(a, v, file, config, shown, name);
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
