// One frame into an Image: the first half of the one picture path (render_image, then
// save_image). `shprt render` runs it in a headless EGL context, the viewer's --screenshot in its
// offscreen context.
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"

namespace shprt {

Image render_image_in_current_context(const Mesh& mesh, const TransferSet& transfer,
                                      const ShLight& light, const DrawSettings& settings, int width,
                                      int height, int samples, const PreparedSun* sun,
                                      const DrawnObject* object) {
    // GL objects die before the function returns, while the caller's context is still current.
    Renderer renderer;
    renderer.set_sun(sun);
    renderer.set_scene(mesh, transfer);
    renderer.set_light(light);
    if (object) renderer.set_object(object->mesh, object->shading);
    RenderTarget target(width, height, samples);
    target.bind();
    renderer.draw(settings, width, height);
    target.resolve();
    return target.read_pixels();
}

Image render_image(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                   const DrawSettings& settings, int width, int height, int samples,
                   const PreparedSun* sun, const DrawnObject* object) {
    HeadlessGlContext context;
    return render_image_in_current_context(mesh, transfer, light, settings, width, height, samples,
                                           sun, object);
}

}  // namespace shprt
