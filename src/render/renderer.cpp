// The OpenGL renderer of baked PRT scenes (render/renderer.hpp): buffers, the per-vertex shading
// program (gl_shaders.cpp), the light's background and the tone-mapped presentation.
//
// Implements the display side of Sloan, Kautz & Snyder 2002 (per-vertex dot products of transfer
// and light on the GPU) with the paper's glossy term (PAPER.md "Shading").
#include "shprt/render/renderer.hpp"

#include "gl_util.hpp"
#include "object_pass.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/light/equirect.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/shade/tonemap.hpp"
#include "shprt/transfer/cpca.hpp"
#include "shprt/transfer/kind_table.hpp"
#include "sun_pass.hpp"
#include "texel_pass.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace shprt {

DrawSettings draw_settings(const ShadingPlan& plan, ShadeView view) {
    DrawSettings settings;
    settings.view = view;
    settings.k = plan.options.k;
    settings.gloss = plan.options.gloss;
    settings.K_used = plan.options.K_used;
    if (plan.glossy) {  // transfer matrices, shaded on the GPU
        settings.brdf = plan.glossy->brdf;
        settings.material_brdfs = plan.glossy->material_brdfs;
        settings.albedo = plan.glossy->albedo;
    }
    return settings;
}
namespace {

// Size of the equirect texture the background is drawn from: the light is band-limited (at most
// 32 bands, features ≳ 5°), so 256 × 128 texels (1.4° each) resolve it.
constexpr int kBackgroundWidth = 256, kBackgroundHeight = 128;

using gl::kLightBlockBytes;
using gl::light_stride;
// The glossy shaders keep K' coefficients per colour in a local array of this size (8 bands),
// and their lobe uniforms hold this many bands.
constexpr int kMaxMatrixK = 64;
static_assert(gl::kLightBlockVec4s * 4 == 3 * kMaxLightK, "light block: 3 padded channels");
static_assert(gl::kRecurrenceBlockVec4s * 2 == kMaxLightK, "recurrence block: (a, b) per index");

void delete_buffer(unsigned& buffer) {
    if (buffer) glDeleteBuffers(1, &buffer);
    buffer = 0;
}

}  // namespace

Renderer::Renderer() {
    require_gl43();
    m_software = is_software_renderer();
    m_shade_program = gl::compile_compute_program(gl::kShadeComputeShader, "shading");
    for (int display = 0; display < 2; ++display) {
        m_background_program[display] = gl::compile_program(
            gl::kFullscreenVertexShader,
            gl::fragment_shader(gl::kBackgroundFragmentShader, display == 1).c_str(), "background");
    }
    m_present_program =
        gl::compile_program(gl::kFullscreenVertexShader, gl::present_shader().c_str(), "present");
    glGenVertexArrays(1, &m_vao);
    glGenVertexArrays(1, &m_empty_vao);
    GLint max_block = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    m_max_ubo_bytes = max_block;
    glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &m_ubo_alignment);
    SHPRT_CHECK(max_block >= kLightBlockBytes, unsupported,
                "this OpenGL's uniform blocks hold {} bytes; the light needs {}", max_block,
                kLightBlockBytes);
    // Enough bands for any K' (K' ≤ light K ≤ kMaxLightK).
    const std::vector<float> table = gl::recurrence_table(sh_bands_for(kMaxLightK));
    m_recurrence_ubo = gl::make_buffer(GL_UNIFORM_BUFFER, table.size() * sizeof(float),
                                       table.data(), GL_STATIC_DRAW);
    m_light_ubo = gl::make_buffer(GL_UNIFORM_BUFFER, kLightBlockBytes, nullptr, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    gl::check("Renderer");
}

Renderer::~Renderer() {
    release_scene_buffers();
    delete_buffer(m_light_ubo);
    delete_buffer(m_recurrence_ubo);
    delete_buffer(m_lobe_ubo);
    delete_buffer(m_sun_ubo);
    delete_buffer(m_sky_sun_ubo);
    if (m_background_texture) glDeleteTextures(1, &m_background_texture);
    if (m_vao) glDeleteVertexArrays(1, &m_vao);
    if (m_empty_vao) glDeleteVertexArrays(1, &m_empty_vao);
    for (unsigned p :
         {m_shade_program, m_background_program[0], m_background_program[1], m_present_program})
        if (p) glDeleteProgram(p);
    for (const auto& by_code : m_scene_program)
        for (const auto& programs : by_code)
            for (unsigned p : programs)
                if (p) glDeleteProgram(p);
    for (const auto& entry : m_glossy_programs) glDeleteProgram(entry.second);
}

unsigned Renderer::scene_program(int display, int sun_code) {
    unsigned& program = m_scene_program[display][sun_code][static_cast<int>(m_sun_filter)];
    if (!program)
        program = gl::compile_program(
            gl::kSceneVertexShader,
            gl::fragment_shader(gl::kSceneFragmentShader, display == 1,
                                static_cast<gl::SunCode>(sun_code), m_sun_filter)
                .c_str(),
            "scene");
    return program;
}

void Renderer::release_scene_buffers() {
    for (unsigned* b :
         {&m_position_vbo, &m_normal_vbo, &m_albedo_vbo, &m_index_buffer, &m_color_buffer,
          &m_transfer_ssbo, &m_cluster_ssbo, &m_weight_ssbo, &m_cluster_light_ssbo,
          &m_cluster_vertex_ssbo, &m_brdf_index_ssbo, &m_direct_ssbo, &m_sun_color_buffer})
        delete_buffer(*b);
}

void Renderer::set_scene(const Mesh& mesh, const TransferSet& transfer) {
    SHPRT_CHECK(!m_sun_source || !is_matrix(transfer.layout) || !is_texel(transfer.layout),
                unsupported,
                "a sun kept out of the SH sum lights glossy matrices per vertex only: texel "
                "matrices are not drawn with it; a sun: light projects the sun into SH for them");
    // The sun's shadow map covers the scene's bounding sphere.
    const Bounds bounds = mesh_bounds(mesh);
    m_bounds_centre = (bounds.lo + bounds.hi) * 0.5f;
    m_bounds_radius = 0.5f * length(bounds.hi - bounds.lo);
    ++m_geometry_generation;
    if (is_texel(transfer.layout)) return set_texel_scene(mesh, transfer);
    m_texel.reset();
    SHPRT_CHECK(mesh.triangle_count() > 0, invalid_argument, "mesh {} has no triangles to draw",
                mesh.source);
    upload_receivers(mesh, transfer);
}

void Renderer::upload_receivers(const Mesh& mesh, const TransferSet& transfer) {
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(V > 0, invalid_argument, "mesh {} has no vertices to shade", mesh.source);
    const bool matrices = is_glossy_matrix(transfer.layout);
    if (matrices) {
        check_glossy_shadable(mesh, transfer);
        SHPRT_CHECK(transfer.layout.K <= kMaxMatrixK, unsupported,
                    "glossy matrices of K = {} are not drawn (at most {}: 8 bands)",
                    transfer.layout.K, kMaxMatrixK);
    } else {
        check_shadable(mesh, transfer);
    }
    for (const auto& t : mesh.triangles)
        SHPRT_CHECK(t[0] < V && t[1] < V && t[2] < V, invalid_argument,
                    "mesh {}: triangle index out of range ({} vertices)", mesh.source, V);
    // A glossy CPCA code is drawn from the code: each cluster's mean and basis, packed.
    const CpcaCode& code = transfer.cpca;
    const bool cpca = matrices && !code.empty();
    const std::size_t D = transfer.layout.floats_per_receiver();
    std::vector<float> cluster_matrices;
    if (cpca) {
        const std::size_t C = std::size_t(code.clusters), N = std::size_t(code.vectors);
        SHPRT_CHECK(code.means.size() == C * D && code.basis.size() == C * N * D &&
                        code.weights.size() == V * N && code.cluster.size() == V,
                    invalid_argument, "the transfer's CPCA code does not fit its {} receivers", V);
        for (std::uint32_t c : code.cluster)
            SHPRT_CHECK(c < C, invalid_argument, "CPCA cluster index {} out of range ({})", c, C);
        cluster_matrices.resize(C * (1 + N) * D);
        for (std::size_t c = 0; c < C; ++c) {
            float* out = cluster_matrices.data() + c * (1 + N) * D;
            std::copy_n(code.means.data() + c * D, D, out);
            std::copy_n(code.basis.data() + c * N * D, N * D, out + D);
        }
    }
    const float* transfer_data = cpca ? cluster_matrices.data() : transfer.coeffs.data();
    const std::size_t transfer_bytes =
        (cpca ? cluster_matrices.size() : transfer.coeffs.size()) * sizeof(float);
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    SHPRT_CHECK(transfer_bytes <= static_cast<std::size_t>(max_block), unsupported,
                "transfer of {} MiB exceeds this OpenGL's shader storage block limit of {} MiB "
                "(use fewer coefficients{})",
                transfer_bytes >> 20, max_block >> 20,
                matrices && !cpca ? ", or compress it: shprt compress --cpca" : "");

    release_scene_buffers();
    glBindVertexArray(m_vao);
    const std::size_t vec_bytes = V * sizeof(Vec3f);
    m_position_vbo =
        gl::make_buffer(GL_ARRAY_BUFFER, vec_bytes, mesh.positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3f), nullptr);
    glEnableVertexAttribArray(0);
    // Normals and albedo: read by the shading pass (as storage buffers) and by the draw's sun.
    m_normal_vbo = gl::make_buffer(GL_ARRAY_BUFFER, vec_bytes, mesh.normals.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3f), nullptr);
    glEnableVertexAttribArray(1);
    m_albedo_vbo = gl::make_buffer(GL_ARRAY_BUFFER, vec_bytes, mesh.albedo.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3f), nullptr);
    glEnableVertexAttribArray(2);
    // The shading pass writes one vec4 per vertex; the draw reads it as attribute 3.
    m_color_buffer =
        gl::make_buffer(GL_ARRAY_BUFFER, V * 4 * sizeof(float), nullptr, GL_DYNAMIC_COPY);
    glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
    glEnableVertexAttribArray(3);
    m_index_buffer = gl::upload_draw_orders(mesh, m_draw_orders);
    // The sun's T_0 · c_sun per vertex (attribute 4), when the transfer has a direct part: the
    // sun pass writes it, the draw subtracts it. Without one the attribute is off and reads 0.
    const bool direct_part = !matrices && !transfer.direct.empty();
    if (direct_part) {
        m_sun_color_buffer =
            gl::make_buffer(GL_ARRAY_BUFFER, V * 4 * sizeof(float), nullptr, GL_DYNAMIC_COPY);
        glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
        m_direct_ssbo =
            gl::make_buffer(GL_SHADER_STORAGE_BUFFER, transfer.direct.size() * sizeof(float),
                            transfer.direct.data(), GL_STATIC_DRAW);
    }
    glDisableVertexAttribArray(4);
    glBindVertexArray(0);
    // Dynamic: a progressive bake rewrites it chunk by chunk (update_transfer).
    m_transfer_ssbo =
        gl::make_buffer(GL_SHADER_STORAGE_BUFFER, transfer_bytes, transfer_data, GL_DYNAMIC_DRAW);
    m_cpca_clusters = cpca ? code.clusters : 0;
    m_cpca_vectors = cpca ? code.vectors : 0;
    if (cpca) {
        // The vertices grouped by cluster (the vertex pass runs a work group per cluster).
        std::vector<std::uint32_t> start(std::size_t(code.clusters) + 1, 0), order(V);
        for (std::uint32_t c : code.cluster) ++start[c + 1];
        for (std::size_t c = 0; c < std::size_t(code.clusters); ++c) start[c + 1] += start[c];
        std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
        for (std::size_t v = 0; v < V; ++v) order[next[code.cluster[v]]++] = std::uint32_t(v);
        m_cluster_ssbo =
            gl::make_buffer(GL_SHADER_STORAGE_BUFFER, start.size() * sizeof(std::uint32_t),
                            start.data(), GL_STATIC_DRAW);
        m_cluster_vertex_ssbo = gl::make_buffer(GL_SHADER_STORAGE_BUFFER, V * sizeof(std::uint32_t),
                                                order.data(), GL_STATIC_DRAW);
        // At least one float: a CPCA code always has vectors ≥ 1, but keep the buffer valid.
        m_weight_ssbo = gl::make_buffer(
            GL_SHADER_STORAGE_BUFFER, std::max<std::size_t>(1, code.weights.size()) * sizeof(float),
            code.weights.data(), GL_STATIC_DRAW);
        // A uniform block's worth more than the clusters need: the last dispatch of the vertex
        // pass binds a whole block too (a range shorter than the block is undefined in GL),
        // whatever K' (a smaller K' has a smaller stride and more clusters per block).
        m_cluster_light_ssbo = gl::make_buffer(
            GL_SHADER_STORAGE_BUFFER,
            std::size_t(code.clusters) * cluster_layout(transfer.layout.K).stride * 16 +
                std::size_t(m_max_ubo_bytes),
            nullptr, GL_DYNAMIC_COPY);
        m_bytes_per_vertex = cpca_bytes_per_receiver(code, D, V, sizeof(float));
    } else {
        m_bytes_per_vertex = double(D) * sizeof(float);
    }
    // Per-material BRDFs: each vertex's entry in the lobe block (brdf_table order).
    m_material_brdfs.clear();
    if (matrices && !mesh.brdf_index.empty()) {
        const std::vector<Brdf> table = brdf_table(mesh, true, Brdf{});
        SHPRT_CHECK(table.size() <= std::size_t(gl::kLobeBlockVec4s / gl::kLobeVec4sPerBrdf),
                    unsupported, "mesh {}: {} distinct material BRDFs (at most {} are drawn)",
                    mesh.source, table.size() - 1, gl::kLobeBlockVec4s / gl::kLobeVec4sPerBrdf - 1);
        m_material_brdfs.assign(table.begin() + 1, table.end());
        std::vector<std::uint32_t> index(V);
        for (std::size_t v = 0; v < V; ++v) index[v] = brdf_table_index(mesh, true, v);
        m_brdf_index_ssbo = gl::make_buffer(GL_SHADER_STORAGE_BUFFER, V * sizeof(std::uint32_t),
                                            index.data(), GL_STATIC_DRAW);
        // ... and attribute 5 of the draw, for the sun's glossy term (switched on per draw).
        glBindVertexArray(m_vao);
        glBindBuffer(GL_ARRAY_BUFFER, m_brdf_index_ssbo);
        glVertexAttribIPointer(5, 1, GL_UNSIGNED_INT, sizeof(std::uint32_t), nullptr);
        glBindVertexArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
    }
    m_lobe_key = LobeKey{Brdf{}, -1, false};
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    m_matrices = matrices;
    m_cluster_key = ClusterKey{};
    m_vertex_count = V;
    m_index_count = mesh.triangles.size() * 3;
    m_layout = transfer.layout;
    m_K = transfer.layout.K;
    m_channels = transfer.layout.channels;
    ++m_transfer_generation;
    m_shading_valid = false;
    gl::check("Renderer::upload_receivers");
}

void Renderer::set_texel_scene(const Mesh& mesh, const TransferSet& transfer) {
    if (!m_texel) m_texel = std::make_unique<TexelPass>(m_sun_filter);
    m_texel->set_scene(mesh, transfer);
    if (is_glossy_matrix(transfer.layout)) {
        // Glossy matrices: the texels are shaded as points by the glossy passes (one colour per
        // texel), and the texel pass filters those colours at each fragment's UV.
        const TexelPoints points = texel_points(mesh, transfer);
        return upload_receivers(points.points, points.rows);
    }
    m_matrices = false;
    m_cpca_clusters = m_cpca_vectors = 0;
    m_bytes_per_vertex = 0;
    m_vertex_count = mesh.vertex_count();
    m_layout = transfer.layout;
    m_K = transfer.layout.K;
    m_channels = transfer.layout.channels;
    ++m_transfer_generation;
    m_shading_valid = false;
}

void Renderer::update_transfer(std::size_t first_vertex, std::size_t vertex_count,
                               const float* coeffs) {
    SHPRT_CHECK(!m_texel, unsupported, "texel transfer is not updated in place");
    SHPRT_CHECK(m_transfer_ssbo != 0, invalid_argument, "update_transfer before set_scene");
    SHPRT_CHECK(m_cpca_clusters == 0, invalid_argument,
                "update_transfer: the scene's transfer is a CPCA code, not rows");
    SHPRT_CHECK(first_vertex <= m_vertex_count && vertex_count <= m_vertex_count - first_vertex,
                invalid_argument, "transfer update of vertices [{}, {}) outside the scene's {}",
                first_vertex, first_vertex + vertex_count, m_vertex_count);
    const std::size_t per_vertex = m_layout.floats_per_receiver() * sizeof(float);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, m_transfer_ssbo);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(first_vertex * per_vertex),
                    static_cast<GLsizeiptr>(vertex_count * per_vertex), coeffs);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    ++m_transfer_generation;
    gl::check("Renderer::update_transfer");
}

void Renderer::set_light(const ShLight& light, const Mat3d& rotation) {
    SHPRT_CHECK(
        light.K > 0 && light.K <= kMaxLightK && light.coeffs.size() == 3 * std::size_t(light.K),
        invalid_argument, "light has K = {} and {} coefficients (expected 3 × K, K ≤ {})", light.K,
        light.coeffs.size(), kMaxLightK);
    if (!m_has_light || light.K != m_light_source.K || light.coeffs != m_light_source.coeffs) {
        m_light_source = light;
        ++m_source_generation;
    }
    m_light_rotation = rotation;
    // The coefficients to shade with come from the one light path; only the background keeps
    // its shortcut for full bands (upload_background).
    m_light = rotated_light(light, rotation, light.K);
    // The uniform block's layout: each channel padded to a multiple of 4 coefficients.
    const int stride = light_stride(m_light.K);
    std::vector<float> padded(3 * std::size_t(stride), 0.0f);
    for (int c = 0; c < 3; ++c)
        std::copy_n(m_light.channel(c), m_light.K, padded.begin() + std::ptrdiff_t(c) * stride);
    glBindBuffer(GL_UNIFORM_BUFFER, m_light_ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, static_cast<GLsizeiptr>(padded.size() * sizeof(float)),
                    padded.data());
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    m_has_light = true;
    ++m_light_generation;
    update_world_sun();
    gl::check("Renderer::set_light");
}

int Renderer::effective_K(int K_used) const {
    SHPRT_CHECK(K_used >= 0, invalid_argument, "basis size K' = {} is negative", K_used);
    int K = std::min(m_K, m_light.K);
    if (K_used > 0) K = std::min(K, K_used);
    return K;
}

Mat3d Renderer::upload_background(int K) {
    // A full band is rotation invariant: the unrotated source's texture, looked up along R^T·d,
    // shows the rotated light exactly, and turning the light costs nothing here. A partial last
    // band is not: the texture is then made from the rotated (then truncated) light.
    const bool from_source = sh_count(sh_bands_for(K)) == K;
    const BackgroundKey key{K, from_source, from_source ? m_source_generation : m_light_generation};
    const Mat3d lookup = from_source ? m_light_rotation : Mat3d::identity();
    if (m_background_texture && m_background_key == key) return lookup;
    const ShLight& light = from_source ? m_light_source : m_light;
    // The light's SH reconstruction over the equirect grid, rows from the zenith down.
    std::vector<float> texels(std::size_t(kBackgroundWidth) * kBackgroundHeight * 3);
    parallel_for(
        0, kBackgroundHeight, 1, Split::automatic, [&](std::size_t first, std::size_t last) {
            std::vector<float> y(K);
            for (int row = int(first); row != int(last); ++row)
                for (int x = 0; x < kBackgroundWidth; ++x) {
                    const Vec3f d = equirect_pixel_direction<float>(x, row, kBackgroundWidth,
                                                                    kBackgroundHeight);
                    sh_eval_k(K, d.x, d.y, d.z, y.data());
                    float* out = texels.data() + (std::size_t(row) * kBackgroundWidth + x) * 3;
                    for (int c = 0; c < 3; ++c) {
                        const float* l = light.channel(c);
                        double s = 0;
                        for (int i = 0; i < K; ++i) s += double(l[i]) * y[i];
                        out[c] = static_cast<float>(s);
                    }
                }
        });
    if (!m_background_texture) {
        glGenTextures(1, &m_background_texture);
        glBindTexture(GL_TEXTURE_2D, m_background_texture);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGB32F, kBackgroundWidth, kBackgroundHeight);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);  // u wraps around
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, m_background_texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kBackgroundWidth, kBackgroundHeight, GL_RGB, GL_FLOAT,
                    texels.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    m_background_key = key;
    ++m_background_builds;
    gl::check("Renderer::upload_background");
    return lookup;
}

void Renderer::run_shading(const ShadingKey& key) {
    glUseProgram(m_shade_program);
    glUniform3f(gl::loc::kEye, key.eye.x, key.eye.y, key.eye.z);
    glUniform1i(gl::loc::kK, key.K);
    glUniform1i(gl::loc::kStrideK, m_K);
    glUniform1i(gl::loc::kChannels, m_channels);
    glUniform1i(gl::loc::kLightStride, light_stride(m_light.K));
    glUniform1f(gl::loc::kDiffuseShare, static_cast<float>(key.k));
    glUniform1i(gl::loc::kView, key.view);
    glUniform1f(gl::loc::kMinCosEta, static_cast<float>(kMinCosEta));
    glUniform1i(gl::loc::kGlossy, key.glossy ? 1 : 0);
    glUniform1ui(gl::loc::kVertexCount, static_cast<GLuint>(m_vertex_count));
    if (key.glossy) {
        const int bands = sh_bands_for(key.K);
        const std::vector<float> g = lobe_band_factors(bands, key.gloss);
        glUniform1fv(gl::loc::kLobe, bands, g.data());
    }
    bind_vertex_storage();
    // With the sun's bounced light: T · (c_sky + c_sun) here, T_0 · c_sun below; the draw takes
    // the difference, (T − T_0) · c_sun + T · c_sky.
    glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLightBlockBinding,
                     key.bounced_sun ? m_sky_sun_ubo : m_light_ubo);
    glBindBufferBase(GL_UNIFORM_BUFFER, gl::kRecurrenceBlockBinding, m_recurrence_ubo);
    dispatch_per_vertex();
    if (key.bounced_sun) {
        glUniform1i(gl::loc::kStrideK, m_K);
        glUniform1i(gl::loc::kChannels, 1);
        glUniform1i(gl::loc::kGlossy, 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kTransferBinding, m_direct_ssbo);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kColorBinding, m_sun_color_buffer);
        glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLightBlockBinding, m_sun_ubo);
        dispatch_per_vertex();
    }
    finish_shading_pass(key, "Renderer::run_shading");
}

void Renderer::finish_shading_pass(const ShadingKey& key, const char* what) {
    for (unsigned b = 0; b <= gl::kBrdfIndexBinding; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
    for (unsigned b : {gl::kLightBlockBinding, gl::kRecurrenceBlockBinding,
                       gl::kClusterLightBlockBinding, gl::kLobeBlockBinding})
        glBindBufferBase(GL_UNIFORM_BUFFER, b, 0);
    glUseProgram(0);
    m_shading_key = key;
    m_shading_valid = true;
    ++m_shading_passes;
    gl::check(what);
}

double Renderer::transfer_bytes_per_vertex() const { return m_bytes_per_vertex; }

void Renderer::dispatch_per_vertex() {
    // One invocation per vertex, in dispatches of at most 65535 groups (the guaranteed minimum
    // of GL_MAX_COMPUTE_WORK_GROUP_COUNT).
    const std::size_t per_dispatch = std::size_t(65535) * gl::kShadeGroupSize;
    for (std::size_t first = 0; first < m_vertex_count; first += per_dispatch) {
        const std::size_t count = std::min(per_dispatch, m_vertex_count - first);
        glUniform1ui(gl::loc::kFirstVertex, static_cast<GLuint>(first));
        glDispatchCompute(
            static_cast<GLuint>((count + gl::kShadeGroupSize - 1) / gl::kShadeGroupSize), 1, 1);
    }
    // The draw reads the colours as a vertex attribute.
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
}

void Renderer::draw(const DrawSettings& s, int width, int height) {
    draw_scene(s, width, height, 0.0f);
}

void Renderer::draw_to_display(const DrawSettings& s, int width, int height, float exposure) {
    SHPRT_CHECK(exposure > 0 && std::isfinite(exposure), invalid_argument,
                "exposure {} must be positive", exposure);
    draw_scene(s, width, height, exposure);
}

void Renderer::draw_scene(const DrawSettings& s, int width, int height, float exposure) {
    SHPRT_CHECK((m_transfer_ssbo || m_texel) && m_has_light, invalid_argument,
                "Renderer::draw before set_scene and set_light");
    SHPRT_CHECK(width >= 1 && height >= 1, invalid_argument, "viewport {}x{} is empty", width,
                height);
    SHPRT_CHECK(s.k >= 0 && s.k <= 1, invalid_argument, "diffuse share k = {} is outside [0, 1]",
                s.k);
    const int K = effective_K(s.K_used);
    const Mat4f view_proj = view_projection_matrix(s.camera, float(width) / float(height));
    // The sun: drawn in the radiance and irradiance views (the transfer view has no light).
    const SunMode sun_mode = !m_sun_source                     ? SunMode::none
                             : s.view == ShadeView::radiance   ? SunMode::radiance
                             : s.view == ShadeView::irradiance ? SunMode::irradiance
                                                               : SunMode::none;
    SHPRT_CHECK(sun_mode != SunMode::radiance || s.k == 1 || m_matrices, unsupported,
                "a sun kept out of the SH sum lights diffuse receivers only (k = 1, got {}) or "
                "glossy matrices: the paper's glossy term is not linear in the light, so the sun "
                "cannot be taken out of it; a sun: light projects the sun into SH",
                s.k);
    if (sun_mode != SunMode::none) update_sun_map();

    glViewport(0, 0, width, height);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);  // rooms are seen from inside: both sides of every triangle
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    const int display = exposure > 0 ? 1 : 0;
    if (display) {
        glDisable(GL_FRAMEBUFFER_SRGB);  // the shaders encode sRGB themselves, as present does
        // The code present would write for the clear colour (exactly k/255 in the 8-bit target).
        auto code = [&](float c) { return float(display_encode8(c, exposure)) / 255.0f; };
        glClearColor(code(s.clear_color.x), code(s.clear_color.y), code(s.clear_color.z), 1.0f);
    } else {
        glClearColor(s.clear_color.x, s.clear_color.y, s.clear_color.z, 1.0f);
    }
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    const bool glossy = s.k < 1 && s.view == ShadeView::radiance;
    ShadingKey key;
    key.K = K;
    key.view = static_cast<int>(s.view);
    key.glossy = glossy;
    key.k = s.view == ShadeView::radiance ? s.k : 1.0;
    key.gloss = glossy && !m_matrices ? s.gloss : 0.0;
    key.eye = glossy ? s.camera.eye : Vec3f{0, 0, 0};
    if (m_matrices) {
        // The transfer-only view is E under a white sky (no light, hence no K'): all of M, as
        // the vector path's T_0 and glossy_to_diffuse.
        if (s.view == ShadeView::transfer) key.K = m_K;
        SHPRT_CHECK(key.K <= kMaxMatrixK, invalid_argument, "K' = {} above {}", key.K, kMaxMatrixK);
        if (s.view == ShadeView::radiance) {
            key.brdf = s.brdf;
            key.material_brdfs = s.material_brdfs && !m_material_brdfs.empty();
            key.override_albedo = s.albedo.has_value();
            key.albedo = s.albedo.value_or(Vec3f{0, 0, 0});
            if (key.override_albedo)
                SHPRT_CHECK(key.albedo.x >= 0 && key.albedo.x <= 1 && key.albedo.y >= 0 &&
                                key.albedo.y <= 1 && key.albedo.z >= 0 && key.albedo.z <= 1,
                            invalid_argument, "albedo ({}, {}, {}) must be in [0, 1]", key.albedo.x,
                            key.albedo.y, key.albedo.z);
        }
    }
    key.light_generation = m_light_generation;
    key.transfer_generation = m_transfer_generation;
    key.bounced_sun = sun_mode != SunMode::none && sun_bounced();
    key.sun_generation = key.bounced_sun ? m_sun_generation : 0;
    key.host = !m_matrices && !m_texel && !glossy && s.view != ShadeView::transfer &&
               (m_vertex_shading == VertexShading::host ||
                (m_vertex_shading == VertexShading::automatic && m_software));
    if ((!m_texel || m_matrices) && (s.reshade || !m_shading_valid || !(key == m_shading_key))) {
        if (m_matrices)
            run_glossy_shading(key);
        else if (key.host)
            run_host_shading(key);
        else
            run_shading(key);
    }

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    // The scene's program with the frame's matrix, exposure and sun: for the scene, and again for
    // the object after a texel scene (whose pass has its own program).
    // Without a sun the program carries no sun code; glossy matrices may need the BRDF lobes.
    const gl::SunCode sun_code = sun_mode == SunMode::none ? gl::SunCode::none
                                 : m_matrices              ? gl::SunCode::full
                                                           : gl::SunCode::diffuse;
    const auto use_scene_program = [&] {
        glUseProgram(scene_program(display, static_cast<int>(sun_code)));
        glUniformMatrix4fv(gl::loc::kViewProj, 1, GL_FALSE, view_proj.m);
        if (display) glUniform1f(gl::loc::kDisplayExposure, exposure);
        if (sun_mode != SunMode::none) m_sun_map->bind(sun_mode, sun_code);
    };
    use_scene_program();
    const bool sun_glossy = sun_mode == SunMode::radiance && m_matrices;
    if (sun_glossy) {
        std::vector<Brdf> table{key.brdf};
        if (key.material_brdfs)
            table.insert(table.end(), m_material_brdfs.begin(), m_material_brdfs.end());
        m_sun_map->bind_glossy(
            s.camera.eye, key.k,
            key.override_albedo ? std::optional<Vec3f>(key.albedo) : std::nullopt, table);
    }
    glBindVertexArray(m_vao);
    if (m_brdf_index_ssbo) {  // the vertices' BRDF entries, or entry 0
        if (sun_glossy && key.material_brdfs)
            glEnableVertexAttribArray(5);
        else
            glDisableVertexAttribArray(5);
    }
    glVertexAttribI4ui(5, 0, 0, 0, 0);
    if (m_sun_color_buffer) {  // the sun's T_0 · c_sun, subtracted, or 0
        if (key.bounced_sun && !key.host)
            glEnableVertexAttribArray(4);
        else
            glDisableVertexAttribArray(4);
    }
    glVertexAttrib4f(4, 0.0f, 0.0f, 0.0f, 0.0f);
    glPolygonMode(GL_FRONT_AND_BACK, s.wireframe ? GL_LINE : GL_FILL);
    if (m_texel)  // per fragment, from the coefficient planes
        m_texel->draw(view_proj, s, K, m_light_ubo, light_stride(m_light.K), exposure,
                      m_color_buffer, sun_mode != SunMode::none ? m_sun_map : nullptr, sun_mode);
    else
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_index_count), GL_UNSIGNED_INT,
                       gl::draw_order_offset(m_draw_orders, m_index_count, s));
    if (m_object) {
        // The object through the scene's program: its colours and the sun's direct term.
        // Attributes 4 and 5 are off in its vertex array and read 0.
        if (m_texel) use_scene_program();
        m_object->draw();
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glBindVertexArray(0);
    glActiveTexture(GL_TEXTURE0 + gl::kShadowMapUnit);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);

    if (s.background) {
        const Mat3d rotation = upload_background(K);
        // After the scene, at depth 1 with LEQUAL: only the pixels the scene left empty run the
        // (transcendental-heavy) lookup.
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
        glDepthMask(GL_FALSE);
        glUseProgram(m_background_program[display]);
        if (display) glUniform1f(gl::loc::kDisplayExposure, exposure);
        const Mat4f inv = inverse(view_proj);
        glUniformMatrix4fv(gl::loc::kInvViewProj, 1, GL_FALSE, inv.m);
        glUniform3f(gl::loc::kBgEye, s.camera.eye.x, s.camera.eye.y, s.camera.eye.z);
        // GLSL reads column-major: R's rows, given as columns, are the matrix R^T.
        float rows[9];
        for (int i = 0; i < 9; ++i) rows[i] = static_cast<float>(rotation.m[i / 3][i % 3]);
        glUniformMatrix3fv(gl::loc::kBgLightToTexture, 1, GL_FALSE, rows);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, m_background_texture);
        glBindVertexArray(m_empty_vao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindVertexArray(0);
        glDepthMask(GL_TRUE);
        glDepthFunc(GL_LESS);
    }
    glUseProgram(0);
    gl::check("Renderer::draw");
}

void Renderer::present(const RenderTarget& target, float exposure) {
    SHPRT_CHECK(exposure > 0 && std::isfinite(exposure), invalid_argument,
                "exposure {} must be positive", exposure);
    glViewport(0, 0, target.width(), target.height());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_FRAMEBUFFER_SRGB);  // the shader encodes sRGB itself, as the PNG writer does
    glUseProgram(m_present_program);
    glUniform1f(gl::loc::kExposure, exposure);
    glUniform1i(gl::loc::kSamples, target.samples());
    // Units 0 and 1 hold the two sampler types; the one the shader does not read stays empty.
    const bool multisampled = target.samples() > 1;
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, multisampled ? 0 : target.color_texture());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, multisampled ? target.color_texture() : 0);
    glBindVertexArray(m_empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
    glActiveTexture(GL_TEXTURE0);
    glUseProgram(0);
    gl::check("Renderer::present");
}

void Renderer::bind_vertex_storage() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kTransferBinding, m_transfer_ssbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kPositionBinding, m_position_vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kNormalBinding, m_normal_vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kAlbedoBinding, m_albedo_vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kColorBinding, m_color_buffer);
}

}  // namespace shprt
