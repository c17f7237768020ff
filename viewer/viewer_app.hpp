// The interactive viewer: a GLFW window with an OpenGL 4.3 core context, the shared Renderer, the
// ImGui panel (panel.hpp), orbit/fly camera (camera_controller.hpp), light rotation by
// Shift/Ctrl+drag (light_rig.hpp) and, optionally, a bake shown while it refines
// (shprt/bake/background.hpp; on a CUDA build with --device cuda the GPU bake writes into the
// renderer's transfer buffer through CUDA–OpenGL interop).
//
// Controls: left drag turns the camera; Shift or Ctrl + left drag turns the light; right or
// middle drag pans; the wheel zooms (orbit) or moves forward (fly); W/A/S/D/Q/E move; Tab
// switches orbit/fly; R resets the camera; Esc closes. With an object (--object, docs/probes.md):
// the arrow keys move it horizontally (relative to the camera), Page Up/Down vertically; the
// panel shows and edits its position.
#pragma once

#include "frame.hpp"
#include "lit_object.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <optional>
#include <string>
#include <vector>

namespace shprt::viewer {

struct WindowOptions {
    FrameConfig frame;  // initial size, camera, shading, exposure, MSAA
    LightSetup light;   // the command line's light (specs, window, --rotate)
    std::string title = "shprt view";
    std::string scene_label;        // shown in the panel, e.g. the file name
    int max_frames = 0;             // close after this many frames (with a bake: after it ended);
                                    // 0 = when the user closes
    std::string window_screenshot;  // PNG of the last frame's default framebuffer (panel
                                    // included); empty = none
    bool vsync = true;
    bool show_panel = true;
    // The shading the panel starts from and edits (its `direct`: an interreflected transfer's
    // direct part shown first), as the command line gave it and resolved against the file
    // (resolve_shading, with the transfer kept whole); frame.draw is its draw_settings.
    ShadingParams params;
    ViewerObject object;  // a probe-lit object (none: object.object null)
};

struct WindowReport {
    int frames = 0;
    double seconds = 0;          // wall time of the loop
    std::string context;         // gl_context_summary()
    bool bake_finished = false;  // a --bake bake ran to the end
    double bake_seconds = 0;
    std::string bake_error;  // the bake's failure ("" if none)
};

// Opens the window and runs until it is closed (or max_frames). `transfer` is what is drawn (for
// a bake: TransferSet::zeros(...) of the bake's layout, refined as chunks arrive); with `bake` set,
// the bake (mesh, *bake) starts on a worker thread once the window is up. Throws Error(unsupported)
// "cannot open a window: …" when there is no display, "OpenGL 4.3 core profile needed: …" when
// the context is older, and what the Renderer throws.
WindowReport run_window(const Mesh& mesh, const TransferSet& transfer, const WindowOptions& options,
                        const std::optional<BakeOptions>& bake = std::nullopt);

}  // namespace shprt::viewer
