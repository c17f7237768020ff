// `shprt view`'s composition (view_entry.hpp).
#include "view_entry.hpp"

#include "benchmark.hpp"
#include "light_rig.hpp"
#include "screenshot.hpp"
#include "viewer_app.hpp"

#include "shprt/bake/gpu.hpp"
#include "shprt/bake/object_bake.hpp"
#include "shprt/bake/request.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/shade/object_shade.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fmt/printf.h>

#include <algorithm>
#include <filesystem>

namespace shprt::viewer {
namespace {

// Bakes before a headless mode (no window to show the progress in).
TransferSet bake_now(const ViewRequest& r, const Mesh& mesh) {
    BakeRequest request;
    request.options = *r.bake;
    if (r.begin_bake) request.options.progress = r.begin_bake();
    const auto start = Clock::now();
    TransferSet t = shprt::run(request, mesh).transfer;
    if (r.end_bake) r.end_bake();
    r.say(fmt::sprintf("baked %zu vertices, K=%d, S=%d in %.2f s (%s)\n", mesh.vertex_count(),
                       t.layout.K, t.samples, seconds_since(start), t.stats.device_name));
    return t;
}

// The scene (a file, or with a bake one baked here or, for the window, all-zero rows refined as
// they arrive); a glossy file without a BRDF gets --gloss's Phong lobe in `params`.
ShprtFile view_scene(const ViewRequest& r, ShadingParams& params) {
    ShprtFile file;
    if (r.bake) {
        file.mesh = load_scene(r.input);
        file.transfer =
            r.windowed() ? TransferSet::zeros(bake_description(*r.bake), file.mesh.vertex_count())
                         : bake_now(r, file.mesh);
    } else {
        // The window keeps the whole transfer (its panel toggles the direct part); a screenshot
        // or a benchmark shows what --direct asks for.
        file = read_shprt(r.input);
        if (params.direct && r.windowed())
            SHPRT_CHECK(!file.transfer.direct.empty(), invalid_argument,
                        "--direct: {} has no direct part (only interreflected bakes keep one)",
                        r.input);
        check_texel_view(r.input, file.transfer, params.k, params.view);
    }
    // Glossy matrices are shaded with --brdf, else with the materials' BRDFs, else with --gloss's
    // Phong lobe (the panel changes the BRDF live); --glossy paper turns them into the paper's
    // term.
    if (is_glossy_matrix(file.transfer.layout) && !params.brdf &&
        params.glossy == GlossyTerm::matrix && file.mesh.brdf_index.empty())
        params.brdf = Brdf{BrdfModel::phong, params.gloss};
    return file;
}

void take_screenshot(const ViewRequest& r, const ShadingParams& params, const ShprtFile& file,
                     const LightRig& rig, const FrameConfig& config, const ViewerObject& object,
                     Clock::time_point start) {
    const ShLight light = rig.light();
    std::optional<PreparedSun> sun;  // turned as `light`
    if (r.light.sun) sun = prepare_sun(r.light, rig.K());
    ObjectShading lit;
    if (object.object) {
        ObjectShadeOptions options = object.options;
        options.eye = config.draw.camera.eye;
        lit = shade_object(*object.object, object.pose, *object.probes, light, options);
    }
    const DrawnObject drawn{object.object ? &object.object->mesh : nullptr, &lit};
    std::string context;
    const Image image =
        render_screenshot(file.mesh, file.transfer, light, config, r.backend, &context,
                          sun ? &*sun : nullptr, object.object ? &drawn : nullptr);
    save_image(r.screenshot, image, config.exposure);
    r.say(fmt::sprintf("screenshot %dx%d (K'=%d, k=%g) in %.2f s -> %s\n", r.width, r.height,
                       effective_basis_size(file.transfer, light, params.coeffs), params.k,
                       seconds_since(start), r.screenshot));
}

void run_view_benchmark(const ViewRequest& r, const ShprtFile& file, const LightRig& rig,
                        const FrameConfig& config, const ViewerObject& object,
                        const std::string& name) {
    BenchmarkOptions options;
    options.frames = *r.benchmark;
    options.rotate_light = r.benchmark_light;
    // Glossy matrices have at most 8 bands: measure the file's own K.
    if (is_glossy_matrix(file.transfer.layout)) options.K_values = {file.transfer.layout.K};
    // With an object: the file's own K, the object moving every frame.
    options.object = object;
    if (object.object) options.K_values = {std::min(file.transfer.layout.K, rig.K())};
    options.backend = r.backend;
    const BenchmarkReport report = run_benchmark(file.mesh, file.transfer, rig, config, options);
    r.say(name + ": " + format_benchmark(report));
}

void run_view_window(const ViewRequest& r, const ShadingParams& params, const ShprtFile& file,
                     const FrameConfig& config, const ViewerObject& object,
                     const std::string& name) {
    WindowOptions options;
    options.frame = config;
    options.light = r.light;
    options.title = "shprt view — " + name;
    options.scene_label = name;
    options.max_frames = r.max_frames;
    options.window_screenshot = r.window_screenshot;
    options.vsync = r.vsync;
    options.params = params;
    options.object = object;
    const WindowReport report = run_window(file.mesh, file.transfer, options, r.bake);
    r.say(fmt::sprintf("view: %d frames in %.2f s (%.1f frames/s); %s\n", report.frames,
                       report.seconds, report.seconds > 0 ? report.frames / report.seconds : 0.0,
                       report.context));
    if (r.bake && report.bake_finished)
        r.say(fmt::sprintf("baked %zu vertices, K=%d in %.2f s\n", file.mesh.vertex_count(),
                           r.bake->K, report.bake_seconds));
    SHPRT_CHECK(report.bake_error.empty(), unsupported, "bake failed: {}", report.bake_error);
}

}  // namespace

void check(const ViewRequest& r) {
    const bool bake_glossy = r.bake && is_matrix(kind_row(r.bake->transfer));
    SHPRT_CHECK(!r.bake || bake_glossy || !r.params.brdf, invalid_argument,
                "--brdf shades glossy transfer matrices: with --bake, add --transfer glossy");
    SHPRT_CHECK(!(r.params.direct && r.bake), invalid_argument,
                "--direct shows a baked file's direct part; with --bake, bake with "
                "--transfer shadowed instead");
    // The window draws the matrices as their rows arrive; the paper's term replaces them with
    // vectors, which a finished bake can give (--screenshot, --benchmark), not a refining one.
    SHPRT_CHECK(!(bake_glossy && r.windowed() && r.params.glossy == GlossyTerm::paper), unsupported,
                "--glossy paper: the window shows a glossy bake's matrices while they refine "
                "(use --brdf phong:E, or bake the file first and view it with --glossy paper)");
    SHPRT_CHECK(!(r.object_pose && r.bake), invalid_argument,
                "--object is lit from a baked file's probes: bake FILE with shprt bake --probes "
                "first, then view it without --bake");
    if (r.bake) {
        BakeOptions options = *r.bake;
        resolve_device(options.device, options.device_index);  // fail before a window
    }
}

void run_view(const ViewRequest& r) {
    const auto start = Clock::now();
    ShadingParams params = r.params;
    ShprtFile file = view_scene(r, params);
    if (r.object_pose) check_probes(file.transfer.probes, r.input);
    // The window keeps the whole transfer (its panel toggles the direct part); a screenshot or a
    // benchmark shows what --direct asks for.
    ShadingParams resolved = params;
    resolved.direct = params.direct && !r.windowed();
    const ShadingPlan plan = resolve_shading(resolved, file, r.input, Spelling::command_line);
    LightRig rig(std::min(file.transfer.layout.K, kMaxLightK));
    rig.set_source(r.light);  // a missing light file fails here, before any window

    FrameConfig config;
    config.width = r.width;
    config.height = r.height;
    config.msaa = r.msaa;
    config.exposure = static_cast<float>(params.exposure);
    config.draw = draw_settings(plan, params.view);
    config.draw.camera =
        camera_from(r.camera, file.mesh, float(r.width) / float(r.height), r.input);
    config.draw.background = r.background;
    config.draw.wireframe = r.wireframe;
    const std::string name = std::filesystem::path(r.input).filename().string();
    // The object: baked for its self-shadowing once, then lit by the probes every time it or
    // the light moves.
    std::optional<DynamicObject> object;
    ViewerObject shown;
    if (r.object_pose) {
        const ProbeGrid& probes = file.transfer.probes;
        ObjectBakeOptions bake_options;
        bake_options.K = probes.K;
        object = load_dynamic_object(r.object, bake_options);
        shown = {&*object, &probes, *r.object_pose, object_shade_options(plan, params.view),
                 std::filesystem::path(r.object).filename().string()};
        if (sample_probes(probes, r.object_pose->position).clamped)
            log_warn("{}", clamped_warning(probes, r.object_pose->position, "--at"));
        r.say(
            fmt::sprintf("object: %s (%zu vertices, %s) at %g,%g,%g lit from %zu probes\n",
                         r.object, object->mesh.vertex_count(),
                         object->self.coeffs.empty() ? "no self-shadowing" : "self-shadowing baked",
                         r.object_pose->position.x, r.object_pose->position.y,
                         r.object_pose->position.z, probes.count()));
    }
    if (!r.screenshot.empty())
        take_screenshot(r, params, file, rig, config, shown, start);
    else if (r.benchmark)
        run_view_benchmark(r, file, rig, config, shown, name);
    else
        run_view_window(r, params, file, config, shown, name);
}

const std::vector<OptionRow<ViewChoice>>& view_option_table() {
    static const std::vector<OptionRow<ViewChoice>> table = [] {
        using C = ViewChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "size", &C::size, "Window or image size WxH (default 1280x720)");
        add_row(t, "background", &C::background, "Draw the light behind the scene");
        add_row(t, "wireframe", &C::wireframe, "Draw triangle edges only");
        add_row(t, "msaa", &C::msaa,
                "MSAA samples per pixel; 0 = automatic (default): 4, as `shprt render "
                "--samples`, but 1 in the window and --benchmark on a software rasteriser "
                "(llvmpipe), where 4x MSAA more than halves the frame rate");
        add_row(t, "no_vsync", &C::no_vsync, "Do not wait for the display's refresh");
        add_row(t, "bake", &C::bake_scene,
                "FILE is a scene: bake it here and show it while it refines");
        add_row(t, "benchmark", &C::benchmark,
                "Render FRAMES frames offscreen per K' = 32, 48, 64, 128, 256 and print "
                "frames/s");
        add_row(t, "benchmark_light", &C::benchmark_light,
                "With --benchmark: also turn the light every frame");
        add_row(t, "screenshot", &C::screenshot,
                "Render one frame without a window into OUT.png and exit");
        add_row(t, "frames", &C::frames,
                "Close the window after N frames (with --bake: N frames after the bake)")
            .hidden = true;
        add_row(t, "window_screenshot", &C::window_screenshot,
                "With --frames: save the window's last frame (panel included) as PNG")
            .hidden = true;
        add_row(t, "offscreen", &C::offscreen,
                "Context for --screenshot/--benchmark: auto, egl or window")
            .hidden = true;
        return complete_rows(std::move(t));
    }();
    return table;
}

ViewRequest request_from(const ViewChoice& a) {
    const auto png = [](const std::string& path) { return lower_extension(path) == ".png"; };
    SHPRT_CHECK(a.msaa >= 0 && a.msaa <= 64, invalid_argument,
                "--msaa {}: MSAA samples must be 1 to 64 (or 0: automatic)", a.msaa);
    int width = 0, height = 0;
    parse_size(a.size, width, height);
    check(a.camera);
    // --albedo and --coeffs are registered with the bake options (an interreflected bake's
    // albedo, the K baked). Without --bake, and with a glossy bake (which has no albedo), --albedo
    // overrides the glossy colours; without --bake, --coeffs is the K' shown first.
    const bool bake_glossy =
        a.bake_scene && is_matrix(kind_row(parse_transfer_kind(a.bake.transfer)));
    ShadingChoice shading = a.shading;
    BakeOptionChoice bake_args = a.bake;
    if (!a.bake_scene || bake_glossy) {
        shading.albedo = a.bake.albedo;
        bake_args.albedo.clear();
    }
    if (!a.bake_scene && a.bake.coeffs)  // the K' shown first: its deprecated name here
        shading.coeffs = static_cast<int>(std::clamp<long long>(*a.bake.coeffs, -1, 1 << 20));
    const LightSetup setup = light_setup_from(a.light);
    ShadingParams params = shading_params(shading, setup.sun);
    const OffscreenBackend backend = parse_offscreen_backend(a.offscreen);
    SHPRT_CHECK(!(a.benchmark && !a.screenshot.empty()), invalid_argument,
                "--benchmark and --screenshot both given; use one");
    SHPRT_CHECK(!a.benchmark || *a.benchmark >= 1, invalid_argument,
                "--benchmark {}: need at least one frame", a.benchmark.value_or(0));
    SHPRT_CHECK(!a.benchmark_light || a.benchmark, invalid_argument,
                "--benchmark-light needs --benchmark FRAMES");
    SHPRT_CHECK(a.screenshot.empty() || png(a.screenshot), invalid_argument,
                "--screenshot {}: the viewer writes what it displays, as PNG (use `shprt render` "
                "for .exr/.hdr)",
                a.screenshot);
    SHPRT_CHECK(!a.frames || *a.frames >= 1, invalid_argument, "--frames {}: must be ≥ 1",
                a.frames.value_or(0));
    SHPRT_CHECK(a.window_screenshot.empty() || (a.frames && png(a.window_screenshot)),
                invalid_argument, "--window-screenshot {}: needs --frames N and a .png name",
                a.window_screenshot);
    std::vector<std::string> inputs = input_files(a.input, a.light);
    if (!a.object.object.empty()) inputs.push_back(a.object.object);
    for (const std::string& out : {a.screenshot, a.window_screenshot})
        if (!out.empty()) check_output_is_not_input(out, inputs);
    if (!a.bake_scene && !a.bake_only_given.empty())
        fail(ErrorCode::invalid_argument, "{} is a bake option: add --bake (FILE is then a scene)",
             a.bake_only_given.front());
    const std::optional<ObjectPose> object_pose = object_pose_from(a.object);
    ViewRequest r;
    if (a.bake_scene) r.bake = bake_options_from(bake_args, Spelling::command_line);
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
    check(r);
    return r;
}

}  // namespace shprt::viewer
