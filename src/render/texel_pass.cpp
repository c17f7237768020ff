// Per-fragment shading of texel-domain transfer (texel_pass.hpp): the coefficient planes as a
// texture array, sampled at each fragment's UV.
#include "texel_pass.hpp"

#include "gl_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <vector>

namespace shprt {
TexelPass::TexelPass(SunFilter filter) {
    set_sun_filter(filter);
    glGenVertexArrays(1, &m_vao);
    gl::check("TexelPass");
}

void TexelPass::set_sun_filter(SunFilter filter) {
    for (int display = 0; display < 2; ++display) {
        if (m_program[display]) glDeleteProgram(m_program[display]);
        m_program[display] = gl::compile_program(
            gl::kTexelVertexShader,
            gl::fragment_shader(gl::kTexelFragmentShader, display == 1, gl::SunCode::full, filter)
                .c_str(),
            "texel");
    }
}

TexelPass::~TexelPass() {
    for (unsigned* b : {&m_position_vbo, &m_uv_vbo, &m_albedo_vbo, &m_normal_vbo, &m_index_buffer})
        if (*b) glDeleteBuffers(1, b);
    for (unsigned* t : {&m_planes, &m_receivers})
        if (*t) glDeleteTextures(1, t);
    if (m_vao) glDeleteVertexArrays(1, &m_vao);
    for (unsigned program : {m_program[0], m_program[1], m_colour_program[0], m_colour_program[1]})
        if (program) glDeleteProgram(program);
}

void TexelPass::set_scene(const Mesh& mesh, const TransferSet& transfer) {
    transfer.check(mesh);
    const TexelAtlas& atlas = transfer.texels;
    SHPRT_CHECK(is_texel(transfer.layout) && !atlas.empty(), invalid_argument,
                "{}: not a texel transfer", mesh.source);
    const bool colours = is_glossy_matrix(transfer.layout);
    SHPRT_CHECK(!is_matrix(transfer.layout) || colours, unsupported,
                "{}: {} texel transfer cannot be drawn (it needs a vector or a glossy matrix per "
                "texel)",
                mesh.source, to_string(transfer.layout.shape));
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(mesh.uvs.size() == V, invalid_argument,
                "{}: a texel transfer needs the mesh's UVs ({} for {} vertices)", mesh.source,
                mesh.uvs.size(), V);
    SHPRT_CHECK(V > 0 && mesh.triangle_count() > 0, invalid_argument,
                "mesh {} has no triangles to draw", mesh.source);
    for (const auto& t : mesh.triangles)
        SHPRT_CHECK(t[0] < V && t[1] < V && t[2] < V, invalid_argument,
                    "mesh {}: triangle index out of range ({} vertices)", mesh.source, V);
    const int K = transfer.layout.K, C = transfer.layout.channels;
    const int per_channel = colours ? 0 : (K + 3) / 4;
    GLint max_size = 0, max_layers = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    SHPRT_CHECK(
        atlas.width <= max_size && atlas.height <= max_size && C * per_channel <= max_layers,
        unsupported,
        "{}: a {}x{} atlas with {} layers of 4 coefficients exceeds this OpenGL's "
        "textures ({} texels a side, {} layers)",
        mesh.source, atlas.width, atlas.height, C * per_channel, max_size, max_layers);

    for (unsigned* b : {&m_position_vbo, &m_uv_vbo, &m_albedo_vbo, &m_normal_vbo, &m_index_buffer})
        if (*b) glDeleteBuffers(1, b), *b = 0;
    for (unsigned* t : {&m_planes, &m_receivers})
        if (*t) glDeleteTextures(1, t), *t = 0;

    glBindVertexArray(m_vao);
    m_position_vbo =
        gl::make_buffer(GL_ARRAY_BUFFER, V * sizeof(Vec3f), mesh.positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3f), nullptr);
    glEnableVertexAttribArray(0);
    m_uv_vbo =
        gl::make_buffer(GL_ARRAY_BUFFER, V * sizeof(mesh.uvs[0]), mesh.uvs.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(mesh.uvs[0]), nullptr);
    glEnableVertexAttribArray(1);
    m_albedo_vbo =
        gl::make_buffer(GL_ARRAY_BUFFER, V * sizeof(Vec3f), mesh.albedo.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3f), nullptr);
    glEnableVertexAttribArray(2);
    m_normal_vbo =
        gl::make_buffer(GL_ARRAY_BUFFER, V * sizeof(Vec3f), mesh.normals.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3f), nullptr);
    glEnableVertexAttribArray(3);
    m_index_buffer = gl::upload_draw_orders(mesh, m_draw_orders);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    const std::vector<std::int64_t> source = dilate_texels(atlas, kTexelGutter);
    m_index_count = mesh.triangles.size() * 3;
    m_channels = C;
    m_layers_per_channel = per_channel;
    m_colours = colours;
    m_vertex_count = V;
    if (colours) {
        // Each texel's receiver (the colour it shows), −1 beyond the gutter.
        std::vector<std::int32_t> receiver(source.size());
        for (std::size_t p = 0; p < source.size(); ++p)
            receiver[p] = static_cast<std::int32_t>(source[p]);
        glGenTextures(1, &m_receivers);
        glBindTexture(GL_TEXTURE_2D, m_receivers);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32I, atlas.width, atlas.height);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, atlas.width, atlas.height, GL_RED_INTEGER, GL_INT,
                        receiver.data());
        glBindTexture(GL_TEXTURE_2D, 0);
        if (!m_colour_program[0])
            for (int display = 0; display < 2; ++display)
                m_colour_program[display] = gl::compile_program(
                    gl::kTexelVertexShader,
                    gl::fragment_shader(gl::kTexelColourFragmentShader, display == 1).c_str(),
                    "texel colours");
        // The texels as points, shaded by the vertex pass's matrix program.
        if (!m_points) m_points = std::make_unique<VertexPass>();
        const TexelPoints points = texel_points(mesh, transfer);
        m_points->set_scene(points.points, points.rows);
        gl::check("TexelPass::set_scene");
        return;
    }
    m_points.reset();
    // The planes, one layer at a time (a layer's staging image is W × H × 4 floats).
    glGenTextures(1, &m_planes);
    glBindTexture(GL_TEXTURE_2D_ARRAY, m_planes);
    const GLenum format =
        transfer.layout.encoding == TransferEncoding::f16 ? GL_RGBA16F : GL_RGBA32F;
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, format, atlas.width, atlas.height, C * per_channel);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    std::vector<float> layer(source.size() * 4);
    for (int c = 0; c < C; ++c)
        for (int j = 0; j < per_channel; ++j) {
            std::fill(layer.begin(), layer.end(), 0.0f);
            const int first = 4 * j, count = std::min(4, K - first);
            for (std::size_t p = 0; p < source.size(); ++p)
                if (source[p] >= 0)
                    std::copy_n(transfer.receiver(std::size_t(source[p]), c) + first, count,
                                layer.begin() + std::ptrdiff_t(4 * p));
            glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, c * per_channel + j, atlas.width,
                            atlas.height, 1, GL_RGBA, GL_FLOAT, layer.data());
        }
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    gl::check("TexelPass::set_scene");
}

void TexelPass::draw_triangles() const {
    glBindVertexArray(m_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_index_count), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

void TexelPass::update_transfer(std::size_t, std::size_t, const float*) {
    fail(ErrorCode::unsupported, "texel transfer is not updated in place");
}

std::size_t TexelPass::receiver_count() const {
    return m_points ? m_points->receiver_count() : m_vertex_count;
}

void TexelPass::shade(const PassFrame& frame) {
    if (m_points) m_points->shade(frame);
}

void TexelPass::draw(const PassFrame& frame) {
    draw_texels(frame.view_proj, *frame.settings, frame.K, frame.light.ubo, frame.light.stride,
                frame.exposure, m_points ? m_points->colour_buffer() : 0,
                frame.sun_mode != SunMode::none ? frame.sun : nullptr, frame.sun_mode);
}

void TexelPass::draw_texels(const Mat4f& view_proj, const DrawSettings& s, int K,
                            unsigned light_ubo, int light_stride, float exposure,
                            unsigned colour_buffer, const SunPass* sun, SunMode sun_mode) {
    SHPRT_CHECK(m_planes != 0 || m_receivers != 0, invalid_argument,
                "TexelPass::draw before set_scene");
    SHPRT_CHECK(m_colours || s.k >= 1 || s.view != ShadeView::radiance, unsupported,
                "the paper's glossy term (k = {} < 1) is not drawn per texel: diffuse texel "
                "transfer is shown diffuse (k = 1), or as irradiance or transfer",
                s.k);
    const int display = exposure > 0 ? 1 : 0;
    glUseProgram(m_colours ? m_colour_program[display] : m_program[display]);
    glUniformMatrix4fv(gl::texel_loc::kViewProj, 1, GL_FALSE, view_proj.m);
    if (display) glUniform1f(gl::loc::kDisplayExposure, exposure);
    if (m_colours) {
        // The shading pass wrote the colours as a storage buffer: make them visible here.
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kColorBinding, colour_buffer);
        glActiveTexture(GL_TEXTURE0 + gl::kTexelReceiverUnit);
        glBindTexture(GL_TEXTURE_2D, m_receivers);
    } else {
        glUniform1i(gl::texel_loc::kK, K);
        glUniform1i(gl::texel_loc::kChannels, m_channels);
        glUniform1i(gl::texel_loc::kLayersPerChannel, m_layers_per_channel);
        glUniform1i(gl::texel_loc::kLightStride, light_stride);
        glUniform1i(gl::texel_loc::kView, static_cast<int>(s.view));
        glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLightBlockBinding, light_ubo);
        if (sun)
            sun->bind(sun_mode);
        else
            SunPass::bind_none();
        glActiveTexture(GL_TEXTURE0 + gl::kTexelPlanesUnit);
        glBindTexture(GL_TEXTURE_2D_ARRAY, m_planes);
    }
    glBindVertexArray(m_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_index_count), GL_UNSIGNED_INT,
                   gl::draw_order_offset(m_draw_orders, m_index_count, s));
    glBindVertexArray(0);
    if (m_colours) {
        glBindTexture(GL_TEXTURE_2D, 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kColorBinding, 0);
    } else {
        glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
        glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLightBlockBinding, 0);
    }
    glActiveTexture(GL_TEXTURE0);
    glUseProgram(0);
    gl::check("TexelPass::draw");
}

}  // namespace shprt
