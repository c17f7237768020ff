// GLFW for the viewer: initialisation with errors turned into one-line messages, and windows
// with an OpenGL 4.3 core context. Used by the interactive window and, as a fallback when EGL
// gives no context, by the offscreen modes (a hidden window, e.g. under Xvfb).
#pragma once

#include <string>

struct GLFWwindow;

namespace shprt::viewer {

// glfwInit for the lifetime of the object. Throws Error(unsupported) "cannot open a window: …"
// with GLFW's reason (typically that DISPLAY is not set). One session at a time per process.
class GlfwSession {
public:
    GlfwSession();
    ~GlfwSession();
    GlfwSession(const GlfwSession&) = delete;
    GlfwSession& operator=(const GlfwSession&) = delete;
};

// Creates a window (hidden when !visible) with an OpenGL 4.3 core, forward-compatible context,
// makes the context current and checks the version (require_gl43). Throws Error(unsupported)
// "OpenGL 4.3 core profile needed: …" with GLFW's reason when no such context can be made.
// Needs a GlfwSession.
GLFWwindow* create_gl_window(int width, int height, const std::string& title, bool visible);

// The last GLFW error message ("" if none), and clears it.
std::string take_glfw_error();

}  // namespace shprt::viewer
