// Per-vertex shading (vertex_pass.hpp): the scene's vertex buffers, the vector program
// (gl_shaders.cpp) and the draw of the interpolated colours. The matrix program is in
// vertex_pass_matrices.cpp, the CPU's vector sum in vertex_pass_host.cpp.
//
// Implements the display side of Sloan, Kautz & Snyder 2002 (per-vertex dot products of transfer
// and light on the GPU) with the paper's glossy term (PAPER.md "Shading").
#include "vertex_pass.hpp"

#include "gl_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/transfer/cpca.hpp"
#include "sun_pass.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <optional>
#include <vector>

namespace shprt {

namespace {

// The glossy shaders keep K' coefficients per colour in a local array of this size (8 bands),
// and their lobe uniforms hold this many bands.
constexpr int kMaxMatrixK = 64;

}  // namespace

VertexPass::VertexPass() {
    glGenVertexArrays(1, &m_vao);
    GLint max_block = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    m_max_ubo_bytes = max_block;
    glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &m_ubo_alignment);
    gl::check("VertexPass");
}

VertexPass::~VertexPass() {
    release_buffers();
    gl::delete_buffer(m_lobe_ubo);
    if (m_vao) glDeleteVertexArrays(1, &m_vao);
    if (m_shade_program) glDeleteProgram(m_shade_program);
    for (const auto& entry : m_glossy_programs) glDeleteProgram(entry.second);
}

void VertexPass::release_buffers() {
    for (unsigned* b :
         {&m_position_vbo, &m_normal_vbo, &m_albedo_vbo, &m_index_buffer, &m_color_buffer,
          &m_transfer_ssbo, &m_cluster_ssbo, &m_weight_ssbo, &m_cluster_light_ssbo,
          &m_cluster_vertex_ssbo, &m_brdf_index_ssbo, &m_direct_ssbo, &m_sun_color_buffer})
        gl::delete_buffer(*b);
}

void VertexPass::set_scene(const Mesh& mesh, const TransferSet& transfer) {
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(V > 0, invalid_argument, "mesh {} has no vertices to shade", mesh.source);
    const ShadingPass pass = shading_pass(transfer.layout);
    const bool matrices = pass == ShadingPass::vertex_matrices;
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

    release_buffers();
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
    m_pass = pass;
    m_cluster_key = ClusterKey{};
    m_vertex_count = V;
    m_index_count = mesh.triangles.size() * 3;
    m_floats_per_vertex = D;
    m_K = transfer.layout.K;
    m_channels = transfer.layout.channels;
    ++m_transfer_generation;
    m_shading_valid = false;
    gl::check("VertexPass::set_scene");
}

void VertexPass::update_transfer(std::size_t first_vertex, std::size_t vertex_count,
                                 const float* coeffs) {
    SHPRT_CHECK(m_transfer_ssbo != 0, invalid_argument, "update_transfer before set_scene");
    SHPRT_CHECK(m_cpca_clusters == 0, invalid_argument,
                "update_transfer: the scene's transfer is a CPCA code, not rows");
    SHPRT_CHECK(first_vertex <= m_vertex_count && vertex_count <= m_vertex_count - first_vertex,
                invalid_argument, "transfer update of vertices [{}, {}) outside the scene's {}",
                first_vertex, first_vertex + vertex_count, m_vertex_count);
    const std::size_t per_vertex = m_floats_per_vertex * sizeof(float);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, m_transfer_ssbo);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(first_vertex * per_vertex),
                    static_cast<GLsizeiptr>(vertex_count * per_vertex), coeffs);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    ++m_transfer_generation;
    gl::check("Renderer::update_transfer");
}

VertexPass::ShadingKey VertexPass::shading_key(const PassFrame& frame) const {
    const DrawSettings& s = *frame.settings;
    const bool glossy = s.k < 1 && s.view == ShadeView::radiance;
    ShadingKey key;
    key.K = frame.K;
    key.view = static_cast<int>(s.view);
    key.glossy = glossy;
    key.k = s.view == ShadeView::radiance ? s.k : 1.0;
    key.gloss = glossy && !matrices() ? s.gloss : 0.0;
    key.eye = glossy ? s.camera.eye : Vec3f{0, 0, 0};
    if (matrices()) {
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
    key.light_generation = frame.light.generation;
    key.transfer_generation = m_transfer_generation;
    key.bounced_sun = frame.bounced_sun;
    key.sun_generation = key.bounced_sun ? frame.light.sun_generation : 0;
    key.host = !matrices() && !glossy && s.view != ShadeView::transfer && frame.host;
    return key;
}

void VertexPass::shade(const PassFrame& frame) {
    const ShadingKey key = shading_key(frame);
    if (!frame.settings->reshade && m_shading_valid && key == m_shading_key) return;
    if (matrices())
        run_glossy_shading(key, frame);
    else if (key.host)
        run_host_shading(key, frame);
    else
        run_shading(key, frame);
}

void VertexPass::run_shading(const ShadingKey& key, const PassFrame& frame) {
    if (!m_shade_program)
        m_shade_program = gl::compile_compute_program(gl::kShadeComputeShader, "shading");
    glUseProgram(m_shade_program);
    glUniform3f(gl::loc::kEye, key.eye.x, key.eye.y, key.eye.z);
    glUniform1i(gl::loc::kK, key.K);
    glUniform1i(gl::loc::kStrideK, m_K);
    glUniform1i(gl::loc::kChannels, m_channels);
    glUniform1i(gl::loc::kLightStride, frame.light.stride);
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
                     key.bounced_sun ? frame.light.sky_sun_ubo : frame.light.ubo);
    glBindBufferBase(GL_UNIFORM_BUFFER, gl::kRecurrenceBlockBinding, frame.light.recurrence_ubo);
    dispatch_per_vertex();
    if (key.bounced_sun) {
        glUniform1i(gl::loc::kStrideK, m_K);
        glUniform1i(gl::loc::kChannels, 1);
        glUniform1i(gl::loc::kGlossy, 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kTransferBinding, m_direct_ssbo);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kColorBinding, m_sun_color_buffer);
        glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLightBlockBinding, frame.light.sun_ubo);
        dispatch_per_vertex();
    }
    finish_shading_pass(key, frame, "Renderer::run_shading");
}

void VertexPass::finish_shading_pass(const ShadingKey& key, const PassFrame& frame,
                                     const char* what) {
    for (unsigned b = 0; b <= gl::kBrdfIndexBinding; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
    for (unsigned b : {gl::kLightBlockBinding, gl::kRecurrenceBlockBinding,
                       gl::kClusterLightBlockBinding, gl::kLobeBlockBinding})
        glBindBufferBase(GL_UNIFORM_BUFFER, b, 0);
    glUseProgram(0);
    m_shading_key = key;
    m_shading_valid = true;
    ++frame.stats->shading_passes;
    gl::check(what);
}

void VertexPass::dispatch_per_vertex() {
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

void VertexPass::bind_vertex_storage() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kTransferBinding, m_transfer_ssbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kPositionBinding, m_position_vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kNormalBinding, m_normal_vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kAlbedoBinding, m_albedo_vbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kColorBinding, m_color_buffer);
}

void VertexPass::draw(const PassFrame& frame) {
    const DrawSettings& s = *frame.settings;
    const ShadingKey& key = m_shading_key;  // the colours drawn
    const bool sun_glossy = frame.sun_mode == SunMode::radiance && matrices();
    if (sun_glossy) {
        std::vector<Brdf> table{key.brdf};
        if (key.material_brdfs)
            table.insert(table.end(), m_material_brdfs.begin(), m_material_brdfs.end());
        frame.sun->bind_glossy(
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
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_index_count), GL_UNSIGNED_INT,
                   gl::draw_order_offset(m_draw_orders, m_index_count, s));
}

void VertexPass::draw_triangles() const {
    glBindVertexArray(m_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_index_count), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

}  // namespace shprt
