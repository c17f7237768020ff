// Offscreen OpenGL for the viewer's headless modes: EGL, else a hidden GLFW window
// (offscreen_context.hpp).
#include "offscreen_context.hpp"

#include "glfw_session.hpp"
#include "shprt/core/error.hpp"
#include "shprt/render/gl_context.hpp"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace shprt::viewer {

OffscreenBackend parse_offscreen_backend(const std::string& name) {
    if (name == "auto") return OffscreenBackend::automatic;
    if (name == "egl") return OffscreenBackend::egl;
    if (name == "window") return OffscreenBackend::window;
    fail(ErrorCode::invalid_argument, "offscreen backend '{}': expected auto, egl or window", name);
}

OffscreenContext::OffscreenContext(OffscreenBackend backend) {
    std::string why;
    if (backend != OffscreenBackend::window) {
        try {
            m_egl = std::make_unique<HeadlessGlContext>();
            m_description = m_egl->description();
            return;
        } catch (const Error& e) {
            why = std::string("EGL: ") + e.what();
        }
    }
    if (backend != OffscreenBackend::egl) {
        try {
            m_glfw = std::make_unique<GlfwSession>();
            m_window = create_gl_window(64, 64, "shprt (offscreen)", false);
            m_description = gl_context_summary() + ", GLFW hidden window";
            return;
        } catch (const Error& e) {
            m_glfw.reset();
            why += std::string(why.empty() ? "" : "; ") + "window: " + e.what();
        }
    }
    fail(ErrorCode::unsupported, "no OpenGL 4.3 context: {}", why);
}

OffscreenContext::~OffscreenContext() {
    if (m_window) glfwDestroyWindow(m_window);
}

}  // namespace shprt::viewer
