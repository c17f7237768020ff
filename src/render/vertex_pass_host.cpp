// The vertex pass's diffuse per-vertex sum on the CPU (vertex_pass.hpp;
// Renderer::set_vertex_shading): the twin of the compute pass's E = T·L for the radiance and
// irradiance views, with the sun's bounced light folded into the same sum, T·(c_sky + c_sun) −
// T_0·c_sun, so that the draw reads one colour per vertex. The transfer (and T_0) are read where
// they lie, through a read-only map of their buffers: on a software rasteriser that is host memory,
// and no copy is kept.
#include "gl_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "vertex_pass.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <optional>
#include <vector>

namespace shprt {

namespace {

// Σ a_i b_i, i < n, in float: eight running sums (one SIMD register's worth, which the compiler
// vectorises), then the tail, then the eight in a fixed order: the same bits on every run and
// thread count.
float host_shading_dot(const float* a, const float* b, int n) {
    float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    int i = 0;
    for (; i + 8 <= n; i += 8)
        for (int j = 0; j < 8; ++j) acc[j] += a[i + j] * b[i + j];
    float sum = 0;
    for (; i < n; ++i) sum += a[i] * b[i];
    for (float x : acc) sum += x;
    return sum;
}

// A buffer mapped for reading while it lives.
class MappedBuffer {
public:
    MappedBuffer(unsigned buffer, std::size_t bytes) : m_buffer(buffer) {
        glBindBuffer(GL_COPY_READ_BUFFER, buffer);
        m_data = static_cast<const float*>(
            glMapBufferRange(GL_COPY_READ_BUFFER, 0, GLsizeiptr(bytes), GL_MAP_READ_BIT));
        glBindBuffer(GL_COPY_READ_BUFFER, 0);
        SHPRT_CHECK(m_data != nullptr, unsupported,
                    "Renderer: mapping buffer {} ({} bytes) for the host's shading failed", buffer,
                    bytes);
    }
    ~MappedBuffer() {
        glBindBuffer(GL_COPY_READ_BUFFER, m_buffer);
        glUnmapBuffer(GL_COPY_READ_BUFFER);
        glBindBuffer(GL_COPY_READ_BUFFER, 0);
    }
    MappedBuffer(const MappedBuffer&) = delete;
    MappedBuffer& operator=(const MappedBuffer&) = delete;
    const float* data() const { return m_data; }

private:
    unsigned m_buffer = 0;
    const float* m_data = nullptr;
};

}  // namespace

void VertexPass::run_host_shading(const ShadingKey& key, const PassFrame& frame) {
    const std::size_t V = m_vertex_count, stride = std::size_t(m_K);
    const int K = key.K;
    // The light of the sum over T: the sky, plus the sun when its bounce is drawn (its T_0 part
    // is taken out below), each channel K' wide.
    std::vector<float> light(3 * std::size_t(K), 0.0f), sun;
    for (int c = 0; c < 3; ++c)
        std::copy_n(frame.light.sky->channel(c), K, light.begin() + std::ptrdiff_t(c) * K);
    if (key.bounced_sun) {
        const ShLight& sun_sh = *frame.light.sun_sh;
        sun.assign(light.size(), 0.0f);
        const int KS = std::min(K, sun_sh.K);
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < KS; ++i) {
                sun[std::size_t(c) * K + i] = sun_sh.channel(c)[i];
                light[std::size_t(c) * K + i] += sun_sh.channel(c)[i];
            }
    }
    std::vector<float> colors(4 * V);
    {
        const MappedBuffer transfer(m_transfer_ssbo, V * m_channels * stride * sizeof(float));
        const MappedBuffer albedo(m_albedo_vbo, V * 3 * sizeof(float));
        std::optional<MappedBuffer> direct;
        if (key.bounced_sun) direct.emplace(m_direct_ssbo, V * stride * sizeof(float));
        const bool radiance = key.view == static_cast<int>(ShadeView::radiance);
        parallel_for(0, V, 512, Split::automatic, [&](std::size_t first, std::size_t last) {
            for (std::size_t v = first; v != last; ++v) {
                const float* t = transfer.data() + v * m_channels * stride;
                float E[3];
                for (int c = 0; c < 3; ++c) {
                    const float* l = light.data() + std::size_t(c) * K;
                    E[c] = host_shading_dot(m_channels == 3 ? t + c * stride : t, l, K);
                    if (direct)
                        E[c] -= host_shading_dot(direct->data() + v * stride,
                                                 sun.data() + std::size_t(c) * K, K);
                }
                float* out = colors.data() + 4 * v;
                for (int c = 0; c < 3; ++c)
                    out[c] = radiance ? albedo.data()[3 * v + c] / kPiF * E[c] : E[c];
                out[3] = 1.0f;
            }
        });
    }
    glBindBuffer(GL_ARRAY_BUFFER, m_color_buffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(colors.size() * sizeof(float)), colors.data());
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    finish_shading_pass(key, frame, "Renderer::run_host_shading");
}

}  // namespace shprt
