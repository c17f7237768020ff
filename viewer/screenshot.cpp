// One offscreen frame of the viewer (screenshot.hpp).
#include "screenshot.hpp"

namespace shprt::viewer {

Image render_screenshot(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                        const FrameConfig& config, OffscreenBackend backend,
                        std::string* context_description, const PreparedSun* sun,
                        const DrawnObject* object) {
    OffscreenContext context(backend);
    if (context_description) *context_description = context.description();
    return render_image_in_current_context(mesh, transfer, light, config.draw, config.width,
                                           config.height, choose_samples(config.msaa, false), sun,
                                           object);
}

}  // namespace shprt::viewer
