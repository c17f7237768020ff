// `shprt view`'s composition, behind the viewer's entry header (viewer.hpp): the command line
// (tools/cmd_view.cpp) checks its options, parses them into a ViewRequest of the library's types
// and calls run_view, which reads the file (or bakes the scene), prepares the light, the frame and
// the probe-lit object, and shows one screenshot, the benchmark or the window. What it reports is
// handed to the request's `say` line by line; the shell prints it.
#pragma once

#include "frame.hpp"
#include "offscreen_context.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/bake/bake_option_table.hpp"
#include "shprt/core/options.hpp"
#include "shprt/core/progress.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/object_shade.hpp"
#include "shprt/shade/params.hpp"
#include "shprt/transfer/object.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace shprt::viewer {

struct ViewRequest {
    std::string input;                // a .shprt file; with `bake`, a scene file to bake
    std::optional<BakeOptions> bake;  // bake the scene here: first (headless) or live (window)
    LightSetup light;
    ShadingParams params;  // checked (shade/params.hpp: check)
    CameraChoice camera;
    std::string object;                     // a mesh lit from the file's transfer probes, or empty
    std::optional<ObjectPose> object_pose;  // set with `object`
    int width = 1280, height = 720, msaa = kAutoMsaa;
    bool background = false, wireframe = false, vsync = true;
    std::string screenshot;         // one frame as PNG, without a window
    std::optional<int> benchmark;   // frames per K', offscreen
    bool benchmark_light = false;   // with `benchmark`: turn the light every frame too
    int max_frames = 0;             // the window closes after them (0: when the user closes it)
    std::string window_screenshot;  // with max_frames: the window's last frame as PNG
    OffscreenBackend backend = OffscreenBackend::automatic;
    // A headless bake (not the window's, which the panel shows): begin_bake() is called once the
    // scene is loaded and gives the bake's progress callback; end_bake() once the bake is over,
    // before its line is said.
    std::function<ProgressFn()> begin_bake;
    std::function<void()> end_bake;
    // One line of the report, ending in '\n' ("screenshot 640x360 (K'=16, k=1) in 0.41 s -> ...").
    std::function<void(const std::string& line)> say;

    // Neither a screenshot nor a benchmark: the window.
    bool windowed() const { return screenshot.empty() && !benchmark; }
};

// The combinations the viewer refuses, one line each (before any work): --brdf, --direct or
// --object with a bake (a bake's BRDF is --transfer glossy's; a direct part and probes are a baked
// file's), a glossy bake refined in the window with the paper's term; and a bake's device that
// this machine does not have.
void check(const ViewRequest& request);

// Runs the request. Throws Error naming the file for a file that does not read or lacks what is
// asked (a direct part, probes), what the window throws ("cannot open a window: …" without a
// display) and Error(unsupported) "bake failed: …" for a bake that failed in the window.
void run_view(const ViewRequest& request);

// `shprt view`'s options as typed: the light, camera, object, bake and shading choices of the
// library's tables, and the view's own (view_option_table).
struct ViewChoice {
    std::string input;
    LightChoice light;
    CameraChoice camera;
    ObjectChoice object;
    BakeOptionChoice bake;
    ShadingChoice shading;  // its --albedo and --coeffs are the bake options' (request_from)
    // The view's own, view_option_table's rows.
    bool bake_scene = false;  // --bake: `input` is a scene, baked here
    std::string size = "1280x720";
    int msaa = kAutoMsaa;
    bool background = false, wireframe = false, no_vsync = false;
    std::optional<int> benchmark;
    bool benchmark_light = false;
    std::string screenshot;
    // Hidden (tests): close the window after N frames; save its last frame; choose the context.
    std::optional<int> frames;
    std::string window_screenshot, offscreen = "auto";
    // Which bake options were given (only allowed with --bake), as the command line spells them.
    std::vector<std::string> bake_only_given;
};
// The view's own options (core/options.hpp), in the command line's help order.
const std::vector<OptionRow<ViewChoice>>& view_option_table();
// The request the choice describes, every option checked before any work (one line naming the
// option as the command line spells it), check(request) included; the callbacks are left empty.
ViewRequest request_from(const ViewChoice& choice);

}  // namespace shprt::viewer
