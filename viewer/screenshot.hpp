// `shprt view FILE --screenshot OUT.png`: one frame of the viewer without a window — the frame the
// window shows (without the panel), through the same Renderer, the same present pass and an
// offscreen 8-bit framebuffer. For the same camera and light it equals `shprt render`'s PNG up to
// the rounding of the tone map (GPU float here, CPU in save_image).
#pragma once

#include "frame.hpp"
#include "offscreen_context.hpp"

#include "shprt/light/light.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <string>

namespace shprt::viewer {

// Creates an OffscreenContext (`backend`), draws one frame of `config` (its size, MSAA, camera…)
// and returns the displayed bytes. `context_description` (if non-null) receives the context's
// description. Throws what OffscreenContext, Renderer and RenderTarget throw.
Rgb8Image render_screenshot(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                            const FrameConfig& config,
                            OffscreenBackend backend = OffscreenBackend::automatic,
                            std::string* context_description = nullptr);

}  // namespace shprt::viewer
