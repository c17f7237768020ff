// Headless OpenGL through EGL without a surface: the EGL device platform
// (EGL_EXT_device_enumeration / EGL_EXT_platform_device, NVIDIA and Mesa) or Mesa's surfaceless
// platform (EGL_MESA_platform_surfaceless), a 4.3 core context made current with
// EGL_NO_SURFACE (EGL_KHR_surfaceless_context). libepoxy resolves every EGL and GL entry point.
//
// Displays are never eglTerminate'd: an EGLDisplay is a per-device singleton, so terminating it
// would pull the rug from under any other context on it (two renders in one process).
#include "shprt/render/gl_context.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

namespace shprt {
namespace {

bool has_extension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

const char* gl_string(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "?";
}

struct Attempt {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string platform;
};

using Reasons = std::vector<std::pair<std::string, std::string>>;  // (platform, why it failed)

// Initialises `display` and creates a current 4.3 core context on it. On failure returns false
// and appends the reason to `why` (with the version of whatever context the display does give,
// so the user learns what was found).
bool try_display(EGLDisplay display, const std::string& platform, Attempt& out, Reasons& why) {
    if (display == EGL_NO_DISPLAY) {
        why.emplace_back(platform, "no display");
        return false;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        why.emplace_back(platform, fmt::format("eglInitialize failed (0x{:x})", eglGetError()));
        return false;
    }
    const char* ext = eglQueryString(display, EGL_EXTENSIONS);
    if (!eglBindAPI(EGL_OPENGL_API)) {
        why.emplace_back(platform, "desktop OpenGL not supported by EGL");
        return false;
    }
    if (!has_extension(ext, "EGL_KHR_surfaceless_context")) {
        why.emplace_back(platform, "no EGL_KHR_surfaceless_context");
        return false;
    }
    EGLConfig config = nullptr;
    EGLint count = 0;
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    if (!eglChooseConfig(display, config_attribs, &config, 1, &count) || count < 1) {
        // Surfaceless Mesa exposes no configs for desktop GL; a config-less context still works.
        if (!has_extension(ext, "EGL_KHR_no_config_context")) {
            why.emplace_back(platform, "no OpenGL config");
            return false;
        }
        config = EGL_NO_CONFIG_KHR;
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      4,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
    if (context == EGL_NO_CONTEXT) {
        // Find out what the display does offer, for the message.
        std::string found = "no OpenGL context at all";
        EGLContext any = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
        if (any != EGL_NO_CONTEXT) {
            if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, any))
                found = fmt::format("found OpenGL {} ({})", gl_string(GL_VERSION),
                                    gl_string(GL_RENDERER));
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display, any);
        }
        why.emplace_back(platform, "OpenGL 4.3 core profile needed, " + found);
        return false;
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        why.emplace_back(platform, fmt::format("eglMakeCurrent failed (0x{:x})", eglGetError()));
        eglDestroyContext(display, context);
        return false;
    }
    out = {display, context, platform};
    return true;
}

// "reason (platform, platform); other reason (platform)": one line, each distinct reason once.
std::string summarise(const Reasons& why) {
    if (why.empty()) return "no EGL device or surfaceless platform";
    std::vector<std::pair<std::string, std::string>> grouped;  // (reason, platforms)
    for (const auto& [platform, reason] : why) {
        auto it = std::find_if(grouped.begin(), grouped.end(),
                               [&r = reason](const auto& g) { return g.first == r; });
        if (it == grouped.end())
            grouped.emplace_back(reason, platform);
        else
            it->second += ", " + platform;
    }
    std::string out;
    for (const auto& [reason, platforms] : grouped)
        out += (out.empty() ? "" : "; ") + reason + " [" + platforms + "]";
    return out;
}

}  // namespace

bool is_software_renderer() {
    const std::string renderer = gl_string(GL_RENDERER);
    for (const char* name : {"llvmpipe", "softpipe", "Software Rasterizer", "SWR"})
        if (renderer.find(name) != std::string::npos) return true;
    return false;
}

std::string gl_context_summary() {
    GLint mask = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
    return fmt::format("OpenGL {} ({} profile), {}", gl_string(GL_VERSION),
                       (mask & GL_CONTEXT_CORE_PROFILE_BIT) ? "core" : "compatibility",
                       gl_string(GL_RENDERER));
}

void require_gl43() {
    const int version = epoxy_gl_version();  // major·10 + minor
    SHPRT_CHECK(epoxy_is_desktop_gl() && version >= 43, unsupported,
                "OpenGL 4.3 core profile needed, found {}", gl_context_summary());
}

HeadlessGlContext::HeadlessGlContext() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    SHPRT_CHECK(client != nullptr, unsupported,
                "EGL is not available (no client extensions; is libEGL installed?)");
    Reasons why;
    Attempt got;
    bool ok = false;
    if (has_extension(client, "EGL_EXT_device_enumeration") &&
        has_extension(client, "EGL_EXT_platform_device")) {
        EGLint n = 0;
        eglQueryDevicesEXT(0, nullptr, &n);
        std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(std::max(n, 0)));
        if (n > 0) eglQueryDevicesEXT(n, devices.data(), &n);
        // Hardware devices first; Mesa's software device (llvmpipe) last.
        std::vector<std::pair<EGLDeviceEXT, bool>> order;
        for (EGLDeviceEXT d : devices) {
            const char* dext = has_extension(client, "EGL_EXT_device_query")
                                   ? eglQueryDeviceStringEXT(d, EGL_EXTENSIONS)
                                   : nullptr;
            order.emplace_back(d, has_extension(dext, "EGL_MESA_device_software"));
        }
        std::stable_partition(order.begin(), order.end(), [](const auto& d) { return !d.second; });
        for (std::size_t i = 0; i < order.size() && !ok; ++i) {
            EGLDisplay display =
                eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, order[i].first, nullptr);
            ok = try_display(
                display, fmt::format("EGL device {}{}", i, order[i].second ? " (software)" : ""),
                got, why);
        }
    }
    if (!ok && has_extension(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        ok = try_display(display, "EGL surfaceless", got, why);
    }
    if (!ok) {
        fail(ErrorCode::unsupported, "cannot create a headless OpenGL 4.3 context: {}",
             summarise(why));
    }
    m_display = got.display;
    m_context = got.context;
    try {
        require_gl43();
    } catch (...) {
        eglMakeCurrent(got.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(got.display, got.context);
        throw;
    }
    m_description = gl_context_summary() + ", " + got.platform;
    log_debug("headless GL: {}", m_description);
}

HeadlessGlContext::~HeadlessGlContext() {
    auto display = static_cast<EGLDisplay>(m_display);
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, static_cast<EGLContext>(m_context));
}

void HeadlessGlContext::make_current() {
    SHPRT_CHECK(eglMakeCurrent(static_cast<EGLDisplay>(m_display), EGL_NO_SURFACE, EGL_NO_SURFACE,
                               static_cast<EGLContext>(m_context)),
                unsupported, "eglMakeCurrent failed (0x{:x})", eglGetError());
}

}  // namespace shprt
