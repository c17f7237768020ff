// One offscreen frame of the viewer (screenshot.hpp).
#include "screenshot.hpp"

namespace shprt::viewer {

Rgb8Image render_screenshot(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                            const FrameConfig& config, OffscreenBackend backend,
                            std::string* context_description) {
    OffscreenContext context(backend);
    if (context_description) *context_description = context.description();
    // GL objects die before the context does.
    Renderer renderer;
    renderer.set_scene(mesh, transfer);
    renderer.set_light(light);
    RenderTarget target(config.width, config.height, choose_samples(config.msaa, false));
    DisplayTarget display(config.width, config.height);
    draw_frame(renderer, target, config.draw, config.exposure, display.framebuffer());
    return read_framebuffer(display.framebuffer(), config.width, config.height);
}

}  // namespace shprt::viewer
