// One displayed frame: through a multisampled float target and present, or straight into the
// framebuffer (frame.hpp).
#include "frame.hpp"

#include "shprt/core/error.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/transfer/cpca_summary.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <string>

namespace shprt::viewer {

int choose_samples(int requested, bool continuous) {
    if (requested > 0) return requested;
    return continuous && is_software_renderer() ? 1 : 4;
}

int choose_shadow_map_size(bool continuous) {
    return continuous && is_software_renderer() ? 1024 : kShadowMapSize;
}

int choose_moving_shadow_map_size(bool continuous) {
    return continuous && is_software_renderer() ? 512 : 0;
}

SunFilter choose_sun_filter(bool continuous) {
    return continuous && is_software_renderer() ? SunFilter::interactive : SunFilter::full;
}

std::string describe_gpu_transfer(const TransferSet& transfer, double bytes_per_vertex) {
    if (!is_glossy_matrix(transfer.layout)) return {};
    return fmt::format("{}: {:.0f} B/vertex on the GPU (float32)", describe_matrices(transfer),
                       bytes_per_vertex);
}

namespace {

// Whether `framebuffer` (0 = the default framebuffer) has a depth buffer to draw into.
bool has_depth_buffer(unsigned framebuffer) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    GLint bits = 0;
    glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER,
                                          framebuffer == 0 ? GL_DEPTH : GL_DEPTH_ATTACHMENT,
                                          GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &bits);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return glGetError() == GL_NO_ERROR && bits > 0;
}

}  // namespace

void FrameTarget::prepare(int width, int height, int samples, unsigned framebuffer) {
    if (width == m_width && height == m_height && samples == m_requested &&
        framebuffer == m_framebuffer)
        return;
    m_target.reset();  // its GL memory goes before a new one is taken
    m_width = width;
    m_height = height;
    m_requested = samples;
    m_framebuffer = framebuffer;
    m_samples = RenderTarget::supported_samples(samples);
    if (m_samples > 1 || !has_depth_buffer(framebuffer))
        m_target = std::make_unique<RenderTarget>(width, height, m_samples);
}

void draw_frame(Renderer& renderer, FrameTarget& target, const DrawSettings& settings,
                float exposure, unsigned framebuffer, int width, int height) {
    if (RenderTarget* linear = target.float_target()) {
        linear->bind();
        renderer.draw(settings, width, height);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        renderer.present(*linear, exposure);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        renderer.draw_to_display(settings, width, height, exposure);
    }
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
