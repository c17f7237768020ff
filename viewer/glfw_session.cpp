// GLFW initialisation and OpenGL 4.3 windows (glfw_session.hpp).
#include "glfw_session.hpp"

#include "shprt/core/error.hpp"
#include "shprt/render/gl_context.hpp"

#include <epoxy/gl.h>
// After epoxy: GLFW must not include the system GL header itself.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <mutex>

namespace shprt::viewer {
namespace {

std::mutex g_error_mutex;
std::string g_last_error;

void on_glfw_error(int code, const char* description) {
    std::lock_guard lock(g_error_mutex);
    g_last_error = fmt::format("{} (GLFW error 0x{:x})", description ? description : "?", code);
}

}  // namespace

std::string take_glfw_error() {
    std::lock_guard lock(g_error_mutex);
    std::string e;
    e.swap(g_last_error);
    return e;
}

GlfwSession::GlfwSession() {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        std::string why = take_glfw_error();
        if (why.empty()) why = "glfwInit failed";
        fail(ErrorCode::unsupported, "cannot open a window: {}", why);
    }
}

GlfwSession::~GlfwSession() { glfwTerminate(); }

GLFWwindow* create_gl_window(int width, int height, const std::string& title, bool visible) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, 0);      // the renderer has its own multisampled target
    glfwWindowHint(GLFW_DEPTH_BITS, 24);  // single-sample frames are drawn straight into it
    GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window) {
        std::string why = take_glfw_error();
        if (why.empty()) why = "glfwCreateWindow failed";
        fail(ErrorCode::unsupported, "OpenGL 4.3 core profile needed: no such context ({})", why);
    }
    glfwMakeContextCurrent(window);
    try {
        require_gl43();
    } catch (...) {
        glfwDestroyWindow(window);
        throw;
    }
    return window;
}

}  // namespace shprt::viewer
