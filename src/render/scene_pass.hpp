// The scene's shading pass: the one interface through which the Renderer (renderer.hpp), a frame
// driver, shades and draws a scene. Private to render/.
//
// Renderer::set_scene chooses the pass ONCE per scene from the kind table (shading_pass,
// transfer/kind_table.hpp), as the CPU's shade_receivers (shade/texel_shade.hpp) does:
//   vertex_vectors, vertex_matrices  VertexPass (vertex_pass.hpp): a colour per vertex from a
//                                    compute program (vectors; matrices or a CPCA code) or the
//                                    CPU (vectors on a software rasteriser), interpolated;
//   texels                           TexelPass (texel_pass.hpp): per fragment from coefficient
//                                    planes, or a matrix set's per-texel colours (its points
//                                    shaded by an inner VertexPass) filtered at the UV.
//
// A pass owns what is the scene's: its geometry on the GPU (vertex array, draw orders), its
// transfer (buffers or textures), its programs, and the key of what its colours were last shaded
// with. It owns no light, no frame and no target: per frame the Renderer hands it a PassFrame
// (the settings, K', the matrix, the exposure, the light's uniform blocks and generations, the
// sun's shadow map and mode) after clearing the target and drawing the sun's map, and asks it to
// shade (skipped when its key is unchanged) and then to draw with the scene program bound.
//
// What is not a ScenePass: the sun (SunPass, sun_pass.hpp) is a light term — a shadow map that
// every scene pass and the object read per fragment, drawn from the scene pass's triangles; the
// probe-lit object (ObjectPass, object_pass.hpp) is an extra mesh with CPU-shaded colours drawn
// after the scene by the scene program. Neither has a transfer or a shading key; the Renderer
// owns them beside the scene's pass.
#pragma once

#include "shprt/light/light.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/transfer/transfer.hpp"
#include "sun_pass.hpp"

#include <cstddef>
#include <cstdint>

namespace shprt {

// The Renderer's light as the passes read it: the rotated sky (host copy and uniform block), and
// with a sun its SH projection alone and added to the sky (Renderer::set_sun).
struct PassLight {
    const ShLight* sky = nullptr;     // rotated: what the shading uses
    unsigned ubo = 0;                 // the sky's block (gl::kLightBlockBinding layout)
    unsigned recurrence_ubo = 0;      // the SH rotation recurrence's table
    int stride = 0;                   // floats per channel in the blocks (gl::light_stride)
    std::uint64_t generation = 0;     // changes whenever the sky does
    const ShLight* sun_sh = nullptr;  // the sun's SH projection in the scene's frame, or none
    unsigned sun_ubo = 0, sky_sun_ubo = 0;
    std::uint64_t sun_generation = 0;
};

// One frame, as a pass sees it.
struct PassFrame {
    const DrawSettings* settings = nullptr;
    int K = 0;  // K' (Renderer::effective_K)
    Mat4f view_proj;
    float exposure = 0;  // 0: linear radiance; > 0: display codes (draw_to_display)
    PassLight light;
    SunMode sun_mode{};
    SunPass* sun = nullptr;    // the shadow map of this frame, when sun_mode is not none
    bool bounced_sun = false;  // the sun's bounce (T − T_0)·c_sun is in the colours
    bool host = false;         // vector sums may run on the CPU (Renderer::set_vertex_shading)
    PassStats* stats = nullptr;
};

class ScenePass {
public:
    virtual ~ScenePass() = default;
    // Uploads the scene (Renderer::set_scene's checks and errors).
    virtual void set_scene(const Mesh& mesh, const TransferSet& transfer) = 0;
    // Renderer::update_transfer.
    virtual void update_transfer(std::size_t first, std::size_t count, const float* coeffs) = 0;
    // Runs the shading if what the colours depend on changed (or settings->reshade).
    virtual void shade(const PassFrame& frame) = 0;
    // Draws the scene with the Renderer's scene program in use (its matrix, exposure and sun
    // bound); a pass that draws with its own program says so (own_program) and unbinds it.
    virtual void draw(const PassFrame& frame) = 0;
    virtual bool own_program() const = 0;
    // The triangles in the mesh's order, positions at attribute 0, the current program: the
    // sun's depth pass.
    virtual void draw_triangles() const = 0;
    virtual void set_sun_filter(SunFilter) {}

    // What the Renderer reports about the scene (renderer.hpp).
    virtual std::size_t receiver_count() const = 0;
    virtual double bytes_per_receiver() const = 0;
    virtual unsigned transfer_buffer() const = 0;
    virtual bool has_direct_part() const = 0;  // T_0 uploaded: the sun's bounce is drawn
    virtual bool has_material_brdfs() const = 0;
    virtual bool last_shading_on_host() const = 0;
};

}  // namespace shprt
