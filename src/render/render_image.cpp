// One headless frame: EGL context, renderer, float target, read-back (what `shprt render` runs).
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"

namespace shprt {

Image render_image(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                   const DrawSettings& settings, int width, int height, int samples) {
    HeadlessGlContext context;
    Image image;
    {
        // GL objects die before the context does.
        Renderer renderer;
        renderer.set_scene(mesh, transfer);
        renderer.set_light(light);
        RenderTarget target(width, height, samples);
        target.bind();
        renderer.draw(settings, width, height);
        target.resolve();
        image = target.read_pixels();
    }
    return image;
}

}  // namespace shprt
