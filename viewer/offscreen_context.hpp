// An OpenGL 4.3 core context without a visible window, for --screenshot and --benchmark: EGL
// headless first (no display needed: Mesa's llvmpipe, or the GPU through the EGL device
// platform), then a hidden GLFW window (GLX on $DISPLAY, e.g. an Xvfb server) as the fallback.
#pragma once

#include <memory>
#include <string>

struct GLFWwindow;

namespace shprt {
class HeadlessGlContext;
}

namespace shprt::viewer {

class GlfwSession;

enum class OffscreenBackend {
    automatic,  // EGL, else a hidden GLFW window
    egl,        // EGL only
    window,     // a hidden GLFW window only (needs a display)
};

// "auto", "egl" or "window"; throws Error(invalid_argument).
OffscreenBackend parse_offscreen_backend(const std::string& name);

class OffscreenContext {
public:
    // Creates the context and makes it current on the calling thread. Throws Error(unsupported)
    // naming why each backend tried failed, e.g. "no OpenGL 4.3 context: EGL: …; window: …".
    explicit OffscreenContext(OffscreenBackend backend = OffscreenBackend::automatic);
    ~OffscreenContext();
    OffscreenContext(const OffscreenContext&) = delete;
    OffscreenContext& operator=(const OffscreenContext&) = delete;

    // gl_context_summary() plus the backend, e.g. "OpenGL 4.5 (Core Profile) Mesa 22.3.6
    // (core profile), llvmpipe (LLVM 15.0.6, 256 bits), EGL surfaceless".
    const std::string& description() const { return m_description; }

private:
    std::unique_ptr<HeadlessGlContext> m_egl;
    std::unique_ptr<GlfwSession> m_glfw;
    GLFWwindow* m_window = nullptr;
    std::string m_description;
};

}  // namespace shprt::viewer
