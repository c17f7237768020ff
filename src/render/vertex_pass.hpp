// Per-vertex shading inside the Renderer (scene_pass.hpp): the pass of the kind table's
// vertex_vectors and vertex_matrices. Private to render/.
//
// It owns the scene's vertices on the GPU — positions, normals and albedo (vertex attributes and,
// for the compute programs, storage buffers), the draw orders, the transfer in a storage buffer
// (channels × K floats per vertex, the TransferSet layout), T_0 when the transfer has a direct
// part — and the colour buffer (a vec4 per vertex) that its shading writes and the draw
// interpolates (attribute 3). Two programs fill that buffer, one per kind-table pass:
//   vertex_vectors   the paper's shading (shade/shade.hpp: E, L_D and the glossy term with the
//                    Phong lobe rotated by the SH recurrence, gl_shaders.cpp) in a compute pass,
//                    or for the diffuse sum on a software rasteriser the CPU (vertex_pass_host.cpp,
//                    the twin of the compute pass up to the float sum's order);
//   vertex_matrices  glossy matrices M_v·L per vertex, or for a CPCA code the light transformed
//                    once per cluster matrix by a cluster pass and T = mean·L + Σ w_i (B_i·L) per
//                    vertex (vertex_pass_matrices.cpp, gl_glossy_shaders.cpp), with the BRDF
//                    lobes of --brdf or of the materials.
// One class, not two: the two programs read and write the same buffers, skip on the same key and
// draw the same way; what differs is a program and its uniforms, chosen from the kind table's
// answer kept at set_scene. (A matrix set per texel is this pass too, over its texels as points:
// TexelPass holds one.)
//
// The shading is skipped when nothing the colours depend on changed since the last frame
// (diffuse shading does not depend on the camera; glossy shading depends on the eye position
// only; the cluster pass depends on the light and K' only).
#pragma once

#include "scene_pass.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

namespace shprt {

class VertexPass final : public ScenePass {
public:
    VertexPass();
    ~VertexPass() override;
    VertexPass(const VertexPass&) = delete;
    VertexPass& operator=(const VertexPass&) = delete;

    // Vectors (checked as shade_vertices does) or glossy matrices (as shade_glossy does; K ≤
    // 64), of a matrix set with a CPCA code only the code; the buffers must fit
    // GL_MAX_SHADER_STORAGE_BLOCK_SIZE. The mesh needs no triangles (a texel set's points).
    void set_scene(const Mesh& mesh, const TransferSet& transfer) override;
    void update_transfer(std::size_t first, std::size_t count, const float* coeffs) override;
    void shade(const PassFrame& frame) override;
    void draw(const PassFrame& frame) override;
    bool own_program() const override { return false; }
    void draw_triangles() const override;

    std::size_t receiver_count() const override { return m_vertex_count; }
    double bytes_per_receiver() const override { return m_bytes_per_vertex; }
    unsigned transfer_buffer() const override { return m_transfer_ssbo; }
    bool has_direct_part() const override { return m_direct_ssbo != 0; }
    bool has_material_brdfs() const override { return !m_material_brdfs.empty(); }
    bool last_shading_on_host() const override { return m_shading_valid && m_shading_key.host; }
    // The vec4 per vertex the shading writes (TexelPass filters it for a matrix set's texels).
    unsigned colour_buffer() const { return m_color_buffer; }

private:
    // Everything the per-vertex colours depend on.
    struct ShadingKey {
        int K = 0, view = 0;
        bool glossy = false;
        double k = 0, gloss = 0;
        Brdf brdf;
        bool material_brdfs = false;
        bool override_albedo = false;
        Vec3f albedo{0, 0, 0};
        Vec3f eye{0, 0, 0};
        std::uint64_t light_generation = 0, transfer_generation = 0;
        bool bounced_sun = false;  // the sun's bounced light is in the colours
        std::uint64_t sun_generation = 0;
        bool host = false;  // shaded on the CPU: T_0 · c_sun subtracted there, not by the draw
        bool operator==(const ShadingKey&) const = default;
    };
    ShadingKey shading_key(const PassFrame& frame) const;
    bool matrices() const { return m_pass == ShadingPass::vertex_matrices; }
    // Binds what every shading program reads and writes per vertex: the transfer, positions,
    // normals, albedo and the output colours, at their storage-buffer bindings.
    void bind_vertex_storage() const;
    void run_shading(const ShadingKey& key, const PassFrame& frame);
    // run_shading's diffuse sum on the CPU, into the colour buffer (vertex_pass_host.cpp).
    void run_host_shading(const ShadingKey& key, const PassFrame& frame);
    void run_glossy_shading(const ShadingKey& key, const PassFrame& frame);
    // The cluster pass of a CPCA code, if its light or K' changed since it last ran.
    void update_cluster_light(int K, bool white_sky, const PassFrame& frame);
    // Dispatches the bound compute program once per vertex, then the barrier the draw needs.
    void dispatch_per_vertex();
    // After a shading pass: unbinds its buffers and program, records `key`, checks for errors.
    void finish_shading_pass(const ShadingKey& key, const PassFrame& frame, const char* what);
    void release_buffers();

    ShadingPass m_pass = ShadingPass::vertex_vectors;
    unsigned m_shade_program = 0;  // compiled when first shaded with
    unsigned m_vao = 0;
    unsigned m_position_vbo = 0, m_normal_vbo = 0, m_albedo_vbo = 0, m_index_buffer = 0;
    unsigned m_color_buffer = 0;  // V × vec4: the shading pass's output
    unsigned m_transfer_ssbo = 0;
    // The sun's bounce: the transfer's direct part T_0 (one channel per vertex), and T_0 · c_sun
    // per vertex (attribute 4), subtracted by the draw from the colours of T · (c_sky + c_sun).
    unsigned m_direct_ssbo = 0, m_sun_color_buffer = 0;
    // Glossy matrices: their programs, compiled per (K', stored K, vectors, uniform block size,
    // cluster pass) when first drawn with; a CPCA code's cluster indices, weights and the cluster
    // pass's output (m_transfer_ssbo then holds each cluster's mean and basis, packed).
    unsigned glossy_program(int K, int vectors, bool cluster_pass, bool materials = false);
    std::map<std::tuple<int, int, int, int, bool, bool>, unsigned> m_glossy_programs;
    // Where the cluster pass puts a cluster's products for K': `stride` vec4s per cluster (a
    // multiple of the uniform buffer offset alignment), and how many clusters a dispatch of the
    // vertex pass reads through one uniform block (block_vec4s = 0: through the storage buffer).
    struct ClusterLayout {
        int stride = 0, clusters_per_dispatch = 0, block_vec4s = 0;
    };
    ClusterLayout cluster_layout(int K) const;
    int m_max_ubo_bytes = 0, m_ubo_alignment = 16;
    unsigned m_cluster_ssbo = 0, m_weight_ssbo = 0, m_cluster_light_ssbo = 0,
             m_cluster_vertex_ssbo = 0;
    int m_cpca_clusters = 0, m_cpca_vectors = 0;  // 0 clusters: raw matrices
    double m_bytes_per_vertex = 0;
    struct ClusterKey {
        int K = -1;
        bool white_sky = false;
        std::uint64_t light_generation = 0;
        bool operator==(const ClusterKey&) const = default;
    };
    ClusterKey m_cluster_key{};
    // The band factors of the BRDF lobes (brdf_table: DrawSettings::brdf, then with material
    // BRDFs the scene's), 8 floats each, kept while the BRDF, band count and material switch
    // stay (Blinn and GGX are fitted by quadrature); the lobe block holds them for the
    // per-material program.
    struct LobeKey {
        Brdf brdf;
        int bands = 0;
        bool materials = false;
        bool operator==(const LobeKey&) const = default;
    };
    LobeKey m_lobe_key{Brdf{}, -1, false};
    std::vector<float> m_lobe_factors;
    std::vector<Brdf> m_material_brdfs;  // the scene's (Mesh::brdfs), empty when it has none
    unsigned m_brdf_index_ssbo = 0, m_lobe_ubo = 0;
    std::size_t m_vertex_count = 0, m_index_count = 0;
    int m_draw_orders = 1;  // index lists in m_index_buffer: 1 (the mesh's), or 1 + kDrawOrderCount
    int m_K = 0, m_channels = 0;
    std::size_t m_floats_per_vertex = 0;
    std::uint64_t m_transfer_generation = 0;
    ShadingKey m_shading_key;
    bool m_shading_valid = false;
};

}  // namespace shprt
