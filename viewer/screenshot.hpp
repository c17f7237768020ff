// `shprt view FILE --screenshot OUT.png`: one frame of the viewer without a window (without the
// panel), taken by the one picture path: render_image's drawing (render_image_in_current_context)
// in an offscreen context, then save_image (shade/save_image.hpp). For the same camera, light
// and options it is `shprt render`'s PNG, byte for byte.
#pragma once

#include "frame.hpp"
#include "offscreen_context.hpp"

#include "shprt/light/image.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <string>

namespace shprt::viewer {

// Creates an OffscreenContext (`backend`) and draws one frame of `config` (its size, MSAA chosen
// by choose_samples(config.msaa, false), camera…) with render_image_in_current_context; returns
// the linear picture, for save_image with config.exposure. `context_description` (if non-null)
// receives the context's description. `sun`: a sun kept out of the SH sum, in `light`'s frame
// (Renderer::set_sun); `object` a probe-lit object (Renderer::set_object). Throws what
// OffscreenContext, Renderer and RenderTarget throw.
Image render_screenshot(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                        const FrameConfig& config,
                        OffscreenBackend backend = OffscreenBackend::automatic,
                        std::string* context_description = nullptr,
                        const PreparedSun* sun = nullptr, const DrawnObject* object = nullptr);

}  // namespace shprt::viewer
