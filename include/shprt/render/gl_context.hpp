// A headless OpenGL 4.3+ core context through EGL, with no window and no surface: the renderer
// draws into its own framebuffer objects. Works on a machine with neither GPU nor display (Mesa's
// llvmpipe through EGL_PLATFORM_SURFACELESS_MESA) and on NVIDIA machines (EGL device platform).
//
// Context creation is kept apart from the renderer (render/renderer.hpp): the viewer makes its
// own context with GLFW and uses the same Renderer in it.
#pragma once

#include <string>

namespace shprt {

class HeadlessGlContext {
public:
    // Creates the context and makes it current on the calling thread. Tries, in order: each EGL
    // device (EGL_EXT_device_enumeration + EGL_EXT_platform_device), hardware devices before
    // Mesa's software device, then the Mesa surfaceless platform. Throws Error(unsupported) with
    // the reason when EGL is missing or no display gives a 4.3 core context; when a context
    // exists but is older, the message names the version found.
    HeadlessGlContext();
    ~HeadlessGlContext();
    HeadlessGlContext(const HeadlessGlContext&) = delete;
    HeadlessGlContext& operator=(const HeadlessGlContext&) = delete;

    // Makes the context current on the calling thread (a context is current on one thread).
    void make_current();
    // E.g. "OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits), EGL
    // surfaceless".
    const std::string& description() const { return m_description; }

private:
    void* m_display = nullptr;  // EGLDisplay
    void* m_context = nullptr;  // EGLContext
    std::string m_description;
};

// The current context's GL_VERSION, GL_RENDERER and profile as one line; and a check that it is
// OpenGL ≥ 4.3 core, throwing Error(unsupported) "OpenGL 4.3 core profile needed, found …"
// otherwise. Needs a current context.
std::string gl_context_summary();
void require_gl43();

// Whether the current context rasterises on the CPU: Mesa's llvmpipe or softpipe (GL_RENDERER
// names them), or another renderer that calls itself a software rasteriser. Needs a current
// context.
bool is_software_renderer();

}  // namespace shprt
