// Per-fragment shading of texel-domain transfer (docs/texels.md): the scene pass of the kind
// table's texels (scene_pass.hpp). The coefficient planes of a texel bake in a 2D texture array,
// sampled at each fragment's UV and dotted with the light; or, for glossy matrices per texel,
// each texel shaded as a point by an inner VertexPass (vertex_pass.hpp) and those colours
// filtered at the UV. Private to render/: the camera, the light (its uniform block), the
// background, wireframe and presentation stay the Renderer's.
#pragma once

#include "scene_pass.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/transfer/transfer.hpp"
#include "sun_pass.hpp"
#include "vertex_pass.hpp"

#include <cstddef>
#include <memory>

namespace shprt {

namespace gl {
// GLSL 4.30 sources of the texel pass (gl_texel_shaders.cpp).
extern const char* const kTexelVertexShader;    // transforms; passes UV and albedo on
extern const char* const kTexelFragmentShader;  // @output: the planes dotted with the light
// @output: per-texel colours (a storage buffer, one per receiver) filtered at the fragment's UV
extern const char* const kTexelColourFragmentShader;
// Uniform locations fixed with layout(location = N) in those shaders.
namespace texel_loc {
inline constexpr int kViewProj = 0, kK = 1, kChannels = 2, kLayersPerChannel = 3, kLightStride = 4,
                     kView = 5;
}
// Texture units of the planes (the light block is bound at gl::kLightBlockBinding) and of the
// receiver index map (per-texel colours; the colours are bound at gl::kColorBinding).
inline constexpr unsigned kTexelPlanesUnit = 0, kTexelReceiverUnit = 1;
}  // namespace gl

class TexelPass final : public ScenePass {
public:
    // Compiles the program (Error(unsupported) with the driver's log if it fails). Needs a
    // current OpenGL 4.3 core context, as Renderer.
    // `filter`: the sun's shadow filter the texel programs are built with (set_sun_filter).
    explicit TexelPass(SunFilter filter = SunFilter::full);
    ~TexelPass() override;
    // Rebuilds the texel programs with the sun's shadow filter `filter` (renderer.hpp).
    void set_sun_filter(SunFilter filter) override;
    TexelPass(const TexelPass&) = delete;
    TexelPass& operator=(const TexelPass&) = delete;

    // Uploads the mesh (positions, UVs, albedo, normals, triangles) and the coefficient planes: for
    // each channel c and each group j of four coefficients (4j … 4j+3, zero past K), one RGBA layer
    // of the atlas's width × height, layer c·⌈K/4⌉ + j; RGBA16F when the transfer's encoding is f16
    // (the file's values are exact in it), else RGBA32F. Texel (x, y) (row 0 at the top) is GL
    // texel (x, y), so a fragment samples at (u, 1 − v). Empty texels take the nearest chart
    // texel's row up to kTexelGutter rings away (dilate_texels), 0 beyond, so linear filtering
    // does not bleed black into the charts. Throws Error(invalid_argument) for a transfer that is
    // not texel-domain vectors or a mesh without one UV per vertex (transfer.check(mesh) first),
    // Error(unsupported) when the atlas or its layers exceed this OpenGL's texture limits.
    //
    // Glossy matrices per texel (shape symmetric_matrix) are not drawn from planes: an inner
    // VertexPass shades each texel as a point (one colour per receiver, texel_points), and
    // set_scene uploads, instead of planes, each texel's receiver index (R32I; the dilated map of
    // dilate_texels, −1 beyond the gutter), through which draw filters those colours.
    void set_scene(const Mesh& mesh, const TransferSet& transfer) override;
    // Refused: Error(unsupported).
    void update_transfer(std::size_t first, std::size_t count, const float* coeffs) override;
    // Glossy matrices: the inner VertexPass's shading; vectors: nothing (shaded per fragment).
    void shade(const PassFrame& frame) override;
    // draw_texels with the frame's values.
    void draw(const PassFrame& frame) override;
    bool own_program() const override { return true; }

    // Draws the triangles into the current framebuffer with the current depth and polygon state:
    // per fragment E = Σ_i T_i(uv) L_i over the first K coefficients (per colour channel, grey
    // transfer shared), then radiance = albedo/π · E (albedo interpolated from the vertices),
    // irradiance E, or transfer T_0 · 2/√π (as the per-vertex pass's views). `light_ubo` is the
    // Renderer's light block (3 channels of `light_stride` floats, vec4-aligned). Throws
    // Error(unsupported) for the paper's glossy term of vector transfer (k < 1 in the radiance
    // view): it is not drawn per texel. Glossy matrices instead take each fragment's colour as
    // the bilinear filtering, at its UV, of the per-texel colours in `colour_buffer` (vec4 per
    // receiver, as the inner VertexPass writes them; texels outside the map are black).
    // `exposure` > 0: display codes instead of radiance, as Renderer::draw_to_display.
    // `sun`: the sun's direct light per fragment (Renderer::set_sun), bound as SunPass::bind(
    // sun_mode); nullptr: none. Not with per-texel colours (glossy matrices have no sun).
    void draw_texels(const Mat4f& view_proj, const DrawSettings& settings, int K,
                     unsigned light_ubo, int light_stride, float exposure, unsigned colour_buffer,
                     const SunPass* sun = nullptr, SunMode sun_mode = SunMode::none);
    // Draws the triangles in the mesh's order with the vertex array's positions (attribute 0)
    // and the current program: the sun's depth pass.
    void draw_triangles() const override;

    // Vectors: the mesh's vertices and no transfer buffer (the planes are a texture); glossy
    // matrices: the inner pass's texels.
    std::size_t receiver_count() const override;
    double bytes_per_receiver() const override {
        return m_points ? m_points->bytes_per_receiver() : 0;
    }
    unsigned transfer_buffer() const override { return m_points ? m_points->transfer_buffer() : 0; }
    bool has_direct_part() const override { return false; }  // the sun is direct only here
    bool has_material_brdfs() const override { return m_points && m_points->has_material_brdfs(); }
    bool last_shading_on_host() const override {
        return m_points && m_points->last_shading_on_host();
    }

private:
    unsigned m_program[2] = {0, 0};  // linear radiance, display codes (gl::fragment_shader)
    // The same for per-texel colours (glossy matrices), compiled when first needed.
    unsigned m_colour_program[2] = {0, 0};
    unsigned m_vao = 0, m_planes = 0, m_receivers = 0;
    bool m_colours = false;  // glossy matrices: draw filters per-texel colours
    unsigned m_position_vbo = 0, m_uv_vbo = 0, m_albedo_vbo = 0, m_normal_vbo = 0,
             m_index_buffer = 0;
    std::size_t m_index_count = 0;
    int m_draw_orders = 1;  // index lists in m_index_buffer (gl::upload_draw_orders)
    int m_channels = 0, m_layers_per_channel = 0;
    std::size_t m_vertex_count = 0;
    std::unique_ptr<VertexPass> m_points;  // glossy matrices: the texels shaded as points
};

}  // namespace shprt
