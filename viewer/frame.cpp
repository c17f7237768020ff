// One displayed frame: draw, then present (which resolves); and reading the displayed bytes back
// (frame.hpp).
#include "frame.hpp"

#include "shprt/core/error.hpp"
#include "shprt/render/gl_context.hpp"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <string>

namespace shprt::viewer {

int choose_samples(int requested, bool continuous) {
    if (requested > 0) return requested;
    return continuous && is_software_renderer() ? 1 : 4;
}

std::string describe_gpu_transfer(const TransferSet& transfer, double bytes_per_vertex) {
    if (transfer.layout.shape != TransferShape::symmetric_matrix) return {};
    const int K = transfer.layout.K;
    if (transfer.cpca.empty())
        return fmt::format("{}x{} matrices: {:.0f} B/vertex on the GPU", K, K, bytes_per_vertex);
    return fmt::format(
        "CPCA {}x{} (clusters x vectors) of {}x{} matrices: {:.0f} B/vertex on "
        "the GPU (float32)",
        transfer.cpca.clusters, transfer.cpca.vectors, K, K, bytes_per_vertex);
}

void draw_frame(Renderer& renderer, RenderTarget& target, const DrawSettings& settings,
                float exposure, unsigned framebuffer) {
    target.bind();
    renderer.draw(settings, target.width(), target.height());
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    renderer.present(target, exposure);
}

DisplayTarget::DisplayTarget(int width, int height) : m_width(width), m_height(height) {
    glGenFramebuffers(1, &m_fbo);
    glGenRenderbuffers(1, &m_color_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, m_color_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_color_rb);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        glDeleteFramebuffers(1, &m_fbo);
        glDeleteRenderbuffers(1, &m_color_rb);
        m_fbo = m_color_rb = 0;
        fail(ErrorCode::unsupported, "display framebuffer {}x{} is incomplete (0x{:x})", width,
             height, status);
    }
}

DisplayTarget::~DisplayTarget() {
    if (m_fbo) glDeleteFramebuffers(1, &m_fbo);
    if (m_color_rb) glDeleteRenderbuffers(1, &m_color_rb);
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

std::vector<float> read_gl_buffer(unsigned buffer, std::size_t count) {
    glBindBuffer(GL_COPY_READ_BUFFER, buffer);
    GLint64 size = 0;
    glGetBufferParameteri64v(GL_COPY_READ_BUFFER, GL_BUFFER_SIZE, &size);
    if (static_cast<std::size_t>(size) < count * sizeof(float)) {
        glBindBuffer(GL_COPY_READ_BUFFER, 0);
        fail(ErrorCode::invalid_argument, "GL buffer {} holds {} bytes, {} floats requested",
             buffer, size, count);
    }
    std::vector<float> out(count);
    glGetBufferSubData(GL_COPY_READ_BUFFER, 0, static_cast<GLsizeiptr>(count * sizeof(float)),
                       out.data());
    glBindBuffer(GL_COPY_READ_BUFFER, 0);
    return out;
}

}  // namespace shprt::viewer
