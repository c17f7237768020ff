// Offscreen targets: the float render target (RGBA32F colour + 24-bit depth) and the 8-bit
// display target that stands in for a window; reading a framebuffer back.
//
// With MSAA the float target's colour is a multisample texture that `present` averages itself
// (no resolve pass per displayed frame) and `resolve` blits into a single-sample texture for
// read-back; without MSAA the colour texture is drawn into directly and `resolve` has nothing
// to do.
#include "gl_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/render/renderer.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace shprt {

int RenderTarget::supported_samples(int requested) {
    if (requested <= 1) return 1;
    GLint count = 0;
    glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, GL_RGBA32F, GL_NUM_SAMPLE_COUNTS, 1, &count);
    if (count <= 0) return 1;
    std::vector<GLint> counts(static_cast<std::size_t>(count));
    glGetInternalformativ(GL_TEXTURE_2D_MULTISAMPLE, GL_RGBA32F, GL_SAMPLES, count, counts.data());
    int best = 1;
    for (GLint c : counts)
        if (c <= requested) best = std::max(best, static_cast<int>(c));
    return best;
}

namespace {

void check_target_size(const char* what, int width, int height) {
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    SHPRT_CHECK(width >= 1 && height >= 1 && width <= max_size && height <= max_size,
                invalid_argument, "{} {}x{} is outside 1..{} (GL_MAX_RENDERBUFFER_SIZE)", what,
                width, height, max_size);
}

}  // namespace

RenderTarget::RenderTarget(int width, int height, int samples)
    : m_width(width), m_height(height), m_samples(1) {
    check_target_size("render target", width, height);
    m_samples = supported_samples(samples);

    glGenFramebuffers(1, &m_fbo);
    glGenRenderbuffers(1, &m_depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, m_depth_rb);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, m_samples > 1 ? m_samples : 0,
                                     GL_DEPTH_COMPONENT24, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    if (m_samples > 1) {
        glGenTextures(1, &m_color_texture);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, m_color_texture);
        glTexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, m_samples, GL_RGBA32F, width, height,
                                  GL_TRUE);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
    } else {
        m_color_texture = gl::make_texture_2d(width, height, GL_RGBA32F);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glFramebufferTexture(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, m_color_texture, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m_depth_rb);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);

    GLenum resolve_status = GL_FRAMEBUFFER_COMPLETE;
    if (m_samples > 1) {
        m_resolved_texture = gl::make_texture_2d(width, height, GL_RGBA32F);
        glGenFramebuffers(1, &m_resolve_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, m_resolve_fbo);
        glFramebufferTexture(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, m_resolved_texture, 0);
        resolve_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE || resolve_status != GL_FRAMEBUFFER_COMPLETE) {
        release();
        fail(ErrorCode::unsupported,
             "float render target {}x{} ({} samples) is incomplete (0x{:x}, 0x{:x})", width, height,
             m_samples, status, resolve_status);
    }
    gl::check("RenderTarget");
}

RenderTarget::~RenderTarget() { release(); }

void RenderTarget::release() {
    if (m_fbo) glDeleteFramebuffers(1, &m_fbo);
    if (m_resolve_fbo) glDeleteFramebuffers(1, &m_resolve_fbo);
    if (m_depth_rb) glDeleteRenderbuffers(1, &m_depth_rb);
    if (m_color_texture) glDeleteTextures(1, &m_color_texture);
    if (m_resolved_texture) glDeleteTextures(1, &m_resolved_texture);
    m_fbo = m_resolve_fbo = m_depth_rb = m_color_texture = m_resolved_texture = 0;
}

void RenderTarget::bind() {
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glViewport(0, 0, m_width, m_height);
}

void RenderTarget::resolve() {
    if (m_samples == 1) return;  // drawn straight into the texture that is read back
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_resolve_fbo);
    glBlitFramebuffer(0, 0, m_width, m_height, 0, 0, m_width, m_height, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::check("RenderTarget::resolve");
}

Image RenderTarget::read_pixels() const {
    Image image = Image::make(m_width, m_height);
    std::vector<float> rgba(image.pixel_count() * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_samples > 1 ? m_resolve_fbo : m_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, m_width, m_height, GL_RGBA, GL_FLOAT, rgba.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl::check("RenderTarget::read_pixels");
    // GL's row 0 is the bottom; Image's row 0 is the top.
    for (int y = 0; y < m_height; ++y) {
        const float* src = rgba.data() + static_cast<std::size_t>(m_height - 1 - y) * m_width * 4;
        float* dst = image.pixel(0, y);
        for (int x = 0; x < m_width; ++x)
            for (int c = 0; c < 3; ++c) dst[3 * x + c] = src[4 * x + c];
    }
    return image;
}

DisplayTarget::DisplayTarget(int width, int height) : m_width(width), m_height(height) {
    check_target_size("display target", width, height);
    glGenFramebuffers(1, &m_fbo);
    glGenRenderbuffers(1, &m_color_rb);
    glGenRenderbuffers(1, &m_depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, m_color_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, m_depth_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m_depth_rb);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        glDeleteFramebuffers(1, &m_fbo);
        glDeleteRenderbuffers(1, &m_color_rb);
        glDeleteRenderbuffers(1, &m_depth_rb);
        m_fbo = m_color_rb = m_depth_rb = 0;
        fail(ErrorCode::unsupported, "display framebuffer {}x{} is incomplete (0x{:x})", width,
             height, status);
    }
    gl::check("DisplayTarget");
}

DisplayTarget::~DisplayTarget() {
    if (m_fbo) glDeleteFramebuffers(1, &m_fbo);
    if (m_color_rb) glDeleteRenderbuffers(1, &m_color_rb);
    if (m_depth_rb) glDeleteRenderbuffers(1, &m_depth_rb);
}

Rgb8Image read_framebuffer(unsigned framebuffer, int width, int height) {
    Rgb8Image image;
    image.width = width;
    image.height = height;
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    if (framebuffer == 0) glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    const GLenum error = glGetError();
    SHPRT_CHECK(error == GL_NO_ERROR, unsupported, "reading the framebuffer failed (OpenGL 0x{:x})",
                error);
    image.rgb.resize(static_cast<std::size_t>(width) * height * 3);
    // GL's row 0 is the bottom.
    for (int y = 0; y < height; ++y) {
        const std::uint8_t* src =
            rgba.data() + static_cast<std::size_t>(height - 1 - y) * width * 4;
        std::uint8_t* dst = image.rgb.data() + static_cast<std::size_t>(y) * width * 3;
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) dst[3 * x + c] = src[4 * x + c];
    }
    return image;
}

}  // namespace shprt
