// The vertex pass's glossy transfer matrices (vertex_pass.hpp, the kind table's vertex_matrices):
// the compute programs that shade vertex matrices and CPCA codes per vertex
// (gl_glossy_shaders.cpp), the clusters' light products, and the pass that runs them with the BRDF
// lobes of the materials or the one --brdf. The vector program and the draw are in
// vertex_pass.cpp.
#include "gl_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/shade/glossy.hpp"
#include "vertex_pass.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <tuple>
#include <vector>

namespace shprt {

VertexPass::ClusterLayout VertexPass::cluster_layout(int K) const {
    ClusterLayout l;
    const int align = std::max(1, m_ubo_alignment / 16);  // in vec4s
    l.stride = ((1 + m_cpca_vectors) * K + align - 1) / align * align;
    l.clusters_per_dispatch = m_max_ubo_bytes / (16 * l.stride);
    l.block_vec4s = l.clusters_per_dispatch * l.stride;
    if (l.clusters_per_dispatch == 0) l.clusters_per_dispatch = 65535;  // storage buffer reads
    l.clusters_per_dispatch = std::min(l.clusters_per_dispatch, 65535);
    return l;
}

unsigned VertexPass::glossy_program(int K, int vectors, bool cluster_pass, bool materials) {
    const int block = vectors > 0 && !cluster_pass ? cluster_layout(K).block_vec4s : 0;
    const auto key = std::make_tuple(K, m_K, vectors, block, cluster_pass, materials);
    if (auto it = m_glossy_programs.find(key); it != m_glossy_programs.end()) return it->second;
    const unsigned program =
        cluster_pass ? gl::compile_compute_program(
                           gl::glossy_cluster_shader(K, m_K, vectors).c_str(), "glossy cluster")
                     : gl::compile_compute_program(
                           gl::glossy_vertex_shader(K, m_K, vectors, block, materials).c_str(),
                           "glossy shading");
    m_glossy_programs.emplace(key, program);
    return program;
}

void VertexPass::update_cluster_light(int K, bool white_sky, const PassFrame& frame) {
    const ClusterKey key{K, white_sky, white_sky ? 0 : frame.light.generation};
    if (m_cluster_key == key) return;
    const std::size_t count = std::size_t(m_cpca_clusters) * (1 + std::size_t(m_cpca_vectors));
    glUseProgram(glossy_program(K, m_cpca_vectors, true));
    glUniform1ui(gl::loc::kClusterStride, static_cast<GLuint>(cluster_layout(K).stride));
    glUniform1i(gl::loc::kLightStride, frame.light.stride);
    glUniform1i(gl::loc::kView, white_sky ? static_cast<int>(ShadeView::transfer) : 0);
    glUniform1ui(gl::loc::kVertexCount, static_cast<GLuint>(count));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kTransferBinding, m_transfer_ssbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kClusterLightBinding, m_cluster_light_ssbo);
    glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLightBlockBinding, frame.light.ubo);
    glDispatchCompute(static_cast<GLuint>((count + gl::kShadeGroupSize - 1) / gl::kShadeGroupSize),
                      1, 1);
    // The vertex pass reads the products (from a uniform block or the storage buffer).
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT);
    m_cluster_key = key;
    ++frame.stats->cluster_passes;
    gl::check("VertexPass::update_cluster_light");
}

void VertexPass::run_glossy_shading(const ShadingKey& key, const PassFrame& frame) {
    const int bands = sh_bands_for(key.K);
    const bool white_sky = key.view == static_cast<int>(ShadeView::transfer);
    if (m_cpca_clusters > 0) update_cluster_light(key.K, white_sky, frame);
    const bool materials = key.material_brdfs && !m_material_brdfs.empty();
    if (!(m_lobe_key == LobeKey{key.brdf, bands, materials})) {
        std::vector<Brdf> table{key.brdf};
        if (materials) table.insert(table.end(), m_material_brdfs.begin(), m_material_brdfs.end());
        constexpr std::size_t kPerBrdf = 4 * gl::kLobeVec4sPerBrdf;
        m_lobe_factors.assign(table.size() * kPerBrdf, 0.0f);
        for (std::size_t b = 0; b < table.size(); ++b) {
            const std::vector<float> g = zonal_band_factors(brdf_lobe(table[b], bands).zonal);
            const auto at = m_lobe_factors.begin() + std::ptrdiff_t(b * kPerBrdf);
            std::copy(g.begin(), g.end(), at);
            const auto colour = at + 4 * (gl::kLobeVec4sPerBrdf - 1);  // the last vec4's xyz
            colour[0] = table[b].specular.x;
            colour[1] = table[b].specular.y;
            colour[2] = table[b].specular.z;
        }
        if (materials) {
            if (!m_lobe_ubo)
                m_lobe_ubo = gl::make_buffer(GL_UNIFORM_BUFFER, gl::kLobeBlockVec4s * 16, nullptr,
                                             GL_DYNAMIC_DRAW);
            glBindBuffer(GL_UNIFORM_BUFFER, m_lobe_ubo);
            glBufferSubData(GL_UNIFORM_BUFFER, 0, GLsizeiptr(m_lobe_factors.size() * sizeof(float)),
                            m_lobe_factors.data());
            glBindBuffer(GL_UNIFORM_BUFFER, 0);
        }
        m_lobe_key = LobeKey{key.brdf, bands, materials};
    }
    const std::vector<float> cosine = zonal_band_factors(clamped_cosine_zonal(bands));
    glUseProgram(glossy_program(key.K, m_cpca_clusters > 0 ? m_cpca_vectors : 0, false, materials));
    glUniform3f(gl::loc::kEye, key.eye.x, key.eye.y, key.eye.z);
    glUniform1i(gl::loc::kLightStride, frame.light.stride);
    glUniform1f(gl::loc::kDiffuseShare, static_cast<float>(key.k));
    glUniform1i(gl::loc::kView, key.view);
    glUniform1ui(gl::loc::kVertexCount, static_cast<GLuint>(m_vertex_count));
    glUniform4f(gl::loc::kAlbedoOverride, key.albedo.x, key.albedo.y, key.albedo.z,
                key.override_albedo ? 1.0f : 0.0f);
    if (!materials) {
        glUniform1fv(gl::loc::kBrdfLobe, bands, m_lobe_factors.data());
        glUniform3f(gl::loc::kSpecular, key.brdf.specular.x, key.brdf.specular.y,
                    key.brdf.specular.z);
    }
    glUniform1fv(gl::loc::kCosineLobe, bands, cosine.data());
    bind_vertex_storage();
    if (m_cpca_clusters > 0) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kClusterLightBinding, m_cluster_light_ssbo);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kClusterBinding, m_cluster_ssbo);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kWeightBinding, m_weight_ssbo);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kClusterVertexBinding,
                         m_cluster_vertex_ssbo);
    }
    glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLightBlockBinding, frame.light.ubo);
    glBindBufferBase(GL_UNIFORM_BUFFER, gl::kRecurrenceBlockBinding, frame.light.recurrence_ubo);
    if (materials) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::kBrdfIndexBinding, m_brdf_index_ssbo);
        glBindBufferBase(GL_UNIFORM_BUFFER, gl::kLobeBlockBinding, m_lobe_ubo);
    }
    if (m_cpca_clusters > 0) {
        // A work group per cluster; per dispatch, the clusters whose products fit a uniform block
        // (or 65535 groups when they are read from the storage buffer).
        const ClusterLayout l = cluster_layout(key.K);
        glUniform1ui(gl::loc::kClusterStride, static_cast<GLuint>(l.stride));
        for (int first = 0; first < m_cpca_clusters; first += l.clusters_per_dispatch) {
            const int count = std::min(l.clusters_per_dispatch, m_cpca_clusters - first);
            if (l.block_vec4s > 0)
                glBindBufferRange(GL_UNIFORM_BUFFER, gl::kClusterLightBlockBinding,
                                  m_cluster_light_ssbo, GLintptr(first) * l.stride * 16,
                                  GLsizeiptr(l.block_vec4s) * 16);
            glUniform1ui(gl::loc::kFirstVertex, static_cast<GLuint>(first));
            glDispatchCompute(static_cast<GLuint>(count), 1, 1);
        }
        glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
    } else {
        dispatch_per_vertex();
    }
    finish_shading_pass(key, frame, "Renderer::run_glossy_shading");
}

}  // namespace shprt
