// The OpenGL renderer of baked scenes: one class shared by `shprt render` (headless, through
// EGL) and the interactive viewer (a GLFW window), so both produce the same image.
//
// It owns its GL objects and draws into whatever context and framebuffer are current; it never
// creates a context. It is a frame driver: it keeps the light (3 × K floats, a uniform block),
// the sun, a probe-lit object, the background and the presentation, and hands the scene to one
// pass (src/render/scene_pass.hpp) that set_scene chooses from the kind table (shading_pass,
// transfer/kind_table.hpp, as the CPU's shade_receivers does): a vertex pass for vertex vectors
// and matrices (vertex_pass.hpp: a compute program evaluates the paper's shading once per vertex
// — shade/shade.hpp: E, L_D and the glossy term with the Phong lobe rotated to the reflection
// direction by the SH recurrence of sh/basis.hpp ported to GLSL — or glossy matrices M_v·L, or a
// CPCA code's cluster products, into a colour buffer the draw interpolates; on a software
// rasteriser the diffuse sum runs on the CPU: set_vertex_shading), or a texel pass (per fragment
// from coefficient planes; a matrix set's texels shaded as points). Each frame the pass shades
// only when something its colours depend on changed (diffuse shading does not depend on the
// camera; glossy shading depends on the eye position only; the cluster pass depends on the light
// and K' only), then draws. Depth test on, back-face culling off
// (rooms are seen from inside). The output is linear radiance in a float target; tone mapping
// happens after the multisample resolve (save_image for files; `present`, which resolves as it
// tone-maps, for a window). The one path from a scene to a picture file is render_image, then
// save_image (shade/save_image.hpp): `shprt render` and the viewer's --screenshot both take it.
//
// Typical use:
//     HeadlessGlContext context;              // or a GLFW window's context
//     Renderer renderer;
//     renderer.set_scene(mesh, transfer);
//     renderer.set_light(light);
//     RenderTarget target(width, height);
//     target.bind();  renderer.draw(settings, width, height);  target.resolve();
//     Image image = target.read_pixels();     // or renderer.present(target, exposure)
//
// Every member function needs the context the object was created in to be current.
#pragma once

#include "shprt/light/image.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/object_shade.hpp"
#include "shprt/shade/params.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/transfer/kind_table.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <vector>

namespace shprt {

class ScenePass;   // src/render/scene_pass.hpp: the scene's pass (vertex_pass.hpp, texel_pass.hpp)
class SunPass;     // src/render/sun_pass.hpp
class ObjectPass;  // src/render/object_pass.hpp

// How many times the scene's passes have shaded (Renderer::shading_passes, cluster_passes).
struct PassStats {
    std::uint64_t shading_passes = 0, cluster_passes = 0;
};

// Texels a side of the sun's shadow map by default (Renderer::set_sun, set_shadow_map_size;
// render/sun_pass.hpp).
inline constexpr int kShadowMapSize = 2048;

// The taps of the sun's shadow filter (Renderer::set_sun_filter; render/sun_pass.hpp): full, 16
// for the blocker search (and the receiver's own texel) and 32 for the percentage-closer filter;
// interactive, 8 and 16 — for frames drawn continuously on a software rasteriser, where the
// full filter is most of a frame (viewer/frame.hpp, choose_sun_filter). Fewer taps make the
// penumbra coarser (16 grey levels), not wider or narrower.
enum class SunFilter { full, interactive };

struct DrawSettings {
    Camera camera;
    double k = 1.0;                // diffuse share, as ShadeOptions::k
    double gloss = kDefaultGloss;  // Phong exponent, as ShadeOptions::gloss
    // Glossy transfer matrices only (shade/glossy.hpp, GlossyShadeOptions: k, K_used and the
    // camera's eye are the fields above): the BRDF's zonal lobe, and the colour that replaces
    // both the diffuse (vertex albedo) and the specular (white) colour.
    Brdf brdf;
    // ... where the scene's materials give a BRDF (Mesh::brdfs), it replaces `brdf` for their
    // vertices (GlossyShadeOptions::material_brdfs).
    bool material_brdfs = false;
    std::optional<Vec3f> albedo;
    int K_used = 0;  // first K' coefficients; 0 = all (clamped to the scene's and light's K)
    ShadeView view = ShadeView::radiance;
    bool wireframe = false;      // triangle edges only (glPolygonMode GL_LINE), same colours
    bool background = false;     // draw the light (its SH projection, first K' coefficients)
                                 // behind the scene; otherwise clear to clear_color
    Vec3f clear_color{0, 0, 0};  // linear RGB
    bool reshade = false;        // run the per-vertex shading pass even if its inputs are
                                 // unchanged (benchmarks that measure the per-vertex cost)
    bool front_to_back = true;   // draw the triangles in the draw order nearest the view
                                 // (render/draw_order.hpp); false: in the mesh's order
};

// The settings that draw what `plan` shades (shade/params.hpp): k, gloss, K′ and the glossy
// matrices' BRDF and colour; the camera and the rest are the caller's.
DrawSettings draw_settings(const ShadingPlan& plan, ShadeView view);

// An offscreen float target: RGBA32F colour + 24-bit depth. With MSAA the colour is a
// multisample texture: `Renderer::present` averages its samples while tone mapping (a window's
// frame needs no separate resolve pass), and `resolve` blits it into a single-sample texture for
// `read_pixels`. Without MSAA the colour is a plain texture and `resolve` does nothing.
class RenderTarget {
public:
    // `samples` is clamped to what the implementation supports for RGBA32F (1 = no MSAA):
    // supported_samples(samples).
    // Throws Error(invalid_argument) for sizes outside [1, GL_MAX_RENDERBUFFER_SIZE] and
    // Error(unsupported) if the framebuffer is incomplete.
    RenderTarget(int width, int height, int samples = 4);
    // The largest sample count ≤ `requested` this implementation supports for RGBA32F
    // multisample textures (1 when requested ≤ 1 or none is supported).
    static int supported_samples(int requested);
    ~RenderTarget();
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;

    // Binds the framebuffer for drawing and sets the viewport to the whole target.
    void bind();
    // Averages the samples into the single-sample texture that read_pixels reads (a blit; a
    // no-op without MSAA). Not needed before `Renderer::present`.
    void resolve();
    // The image as linear RGB floats, row 0 at the top (call resolve() first).
    Image read_pixels() const;

    int width() const { return m_width; }
    int height() const { return m_height; }
    int samples() const { return m_samples; }
    // The colour attachment: GL_TEXTURE_2D_MULTISAMPLE when samples() > 1, else GL_TEXTURE_2D.
    unsigned color_texture() const { return m_color_texture; }
    unsigned framebuffer() const { return m_fbo; }  // GL framebuffer name

private:
    void release();

    int m_width, m_height, m_samples;
    unsigned m_fbo = 0, m_depth_rb = 0, m_color_texture = 0;
    unsigned m_resolve_fbo = 0, m_resolved_texture = 0;  // MSAA only
};

// An offscreen RGBA8 framebuffer with a 24-bit depth buffer, standing in for a window's default
// framebuffer: what Renderer::present and Renderer::draw_to_display write display codes into
// when there is no window (the viewer's --benchmark, tests).
class DisplayTarget {
public:
    // Throws Error(invalid_argument) for sizes outside [1, GL_MAX_RENDERBUFFER_SIZE] and
    // Error(unsupported) if the framebuffer is incomplete.
    DisplayTarget(int width, int height);
    ~DisplayTarget();
    DisplayTarget(const DisplayTarget&) = delete;
    DisplayTarget& operator=(const DisplayTarget&) = delete;

    unsigned framebuffer() const { return m_fbo; }  // GL framebuffer name
    int width() const { return m_width; }
    int height() const { return m_height; }

private:
    int m_width, m_height;
    unsigned m_fbo = 0, m_color_rb = 0, m_depth_rb = 0;
};

// Reads the colour buffer of `framebuffer` (0 = the default framebuffer's back buffer) as 8-bit
// RGB, rows top first, for save_png (shade/save_image.hpp). Waits for rendering to finish.
// Throws Error(unsupported) if OpenGL reports an error.
Rgb8Image read_framebuffer(unsigned framebuffer, int width, int height);

class Renderer {
public:
    // Compiles the frame's shaders (the passes compile theirs when first used). Throws
    // Error(unsupported) if the current context is not OpenGL ≥ 4.3 core (naming the version
    // found) and Error(unsupported) with the driver's log if a shader fails to compile.
    Renderer();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Chooses the scene's pass from the kind table (kept from the last scene when it is the
    // same class) and uploads through it positions, normals, albedo, triangles and the
    // transfer: vectors (checked as
    // shade_vertices does) or glossy matrices (checked as shade_glossy does; K ≤ 64), and of a
    // matrix set with a CPCA code only the code. Checks that the buffers fit
    // GL_MAX_SHADER_STORAGE_BLOCK_SIZE. A texel-domain transfer (docs/texels.md) is drawn per
    // fragment instead: its coefficient planes go into a texture array sampled at the mesh's UVs
    // (the radiance view diffuse only: draw throws Error(unsupported) for k < 1); update_transfer
    // is refused for it.
    void set_scene(const Mesh& mesh, const TransferSet& transfer);
    // Replaces the transfer of vertices [first, first + count) (the TransferSet layout's floats
    // per receiver each) without touching the rest: for a bake shown while it refines. Not for a
    // CPCA code (Error(invalid_argument)).
    void update_transfer(std::size_t first_vertex, std::size_t vertex_count, const float* coeffs);
    // The shader storage buffer holding the transfer (GL buffer name, channels × K float32 per
    // vertex, vertex-major), for CUDA–OpenGL interop. Valid after set_scene.
    // 0 for texel vectors (their planes are a texture).
    unsigned transfer_buffer() const;
    // Sets the light: `light` (3 × K floats, channel-major) in its own frame, turned by
    // `rotation` (a feature at direction s appears at R·s, as rotate_light). The renderer shades
    // with rotated_light(light, rotation, K) (light/light_setup.hpp, the one light path:
    // O(bands³) per channel; exact when K is a full band). Cheap: call it whenever the light
    // turns. The background texture is rebuilt (O(texels × K')) only when the coefficients
    // of `light` change: for a full-band K' a turned light is drawn by turning the lookup
    // direction; for a partial band (not rotation invariant) it is rebuilt from the rotated light.
    void set_light(const ShLight& light, const Mat3d& rotation = Mat3d::identity());
    // A sun kept out of the SH sum (docs/lights.md; the CPU twin is shade_with_sun, shade/
    // sun_shade.hpp), or none (nullptr). `sun` is in the light's own frame, as set_light's light:
    // its direction and its SH projection (prepare_sun) turn with set_light's rotation. Drawn as
    //   direct   per fragment, E_n · V · max(0, n·s) with V from a shadow map filtered so that the
    //            penumbra follows the sun's angular radius (render/sun_pass.hpp);
    //   bounced  per vertex, (T − T_0) · c_sun, for a transfer with a direct part (an
    //            interreflected bake: sun_bounced()); without one the sun is direct only;
    // beside the sky (set_light's light, which must not hold the sun), in the radiance (ρ/π · E)
    // and irradiance views; the transfer view has no light and no sun. Diffuse only, as
    // shade_with_sun: a scene of glossy matrices is refused here (Error(unsupported)) and a draw
    // with k < 1 in the radiance view throws Error(unsupported). Per-vertex and per-texel scenes.
    void set_sun(const PreparedSun* sun);
    // Texels a side of the sun's shadow map (kShadowMapSize until set; 64 to 8192): its texel is
    // 2·1.01·r/texels for a scene of bounding radius r. The viewer's continuous frames on a
    // software rasteriser take 1024 (viewer/frame.hpp, choose_shadow_map_size), where the map is
    // redrawn whenever the sun or an object moves.
    void set_shadow_map_size(int texels);
    int shadow_map_size() const { return m_shadow_map_size; }
    // The sun's shadow filter (SunFilter::full until set).
    void set_sun_filter(SunFilter filter);
    // Texels a side of the map drawn while the sun, the scene's bounds or an object move (0, until
    // set: always the map of set_shadow_map_size): a frame whose sun or geometry differ from the
    // last frame's draws this coarser map; the first frame at rest draws the full one. For
    // continuous frames on a software rasteriser, where the map's redraw is a large part of a
    // moving sun's frame (viewer/frame.hpp, choose_moving_shadow_map_size). 64 to 8192.
    void set_moving_shadow_map_size(int texels);
    // A shadow-map texel's width in world units for the scene set (0 before set_scene).
    double shadow_texel_size() const;
    // The sun's bounced light is drawn (set_sun with a transfer that has a direct part).
    bool sun_bounced() const;
    // How many times the sun's shadow map has been drawn (it is redrawn when the sun turns; the
    // coarser map while moving counts too).
    std::uint64_t sun_map_builds() const;

    // A dynamic object lit from the scene's probes (shade/object_shade.hpp, docs/probes.md
    // "Lighting objects"), drawn with the scene, or none (nullptr): `mesh`'s triangles over
    // `shading`'s vertices (world positions, normals, albedo) with its colours as computed on the
    // CPU (ObjectShading::radiance: what the view shows), plus, with a sun (set_sun), the sun's
    // direct light per fragment through the shadow map, into which the object casts. Call it
    // again whenever the object or the light moves (an upload of 48 bytes a vertex; the triangles
    // only when they change). Throws Error(invalid_argument) for arrays that disagree.
    void set_object(const Mesh* mesh, const ObjectShading* shading);

    // Where the diffuse per-vertex sum (E = T·L in the radiance and irradiance views, with the
    // sun's bounced light folded in: T·(c_sky + c_sun) − T_0·c_sun) runs: in the compute pass
    // (device), or on the CPU over the transfer buffer mapped for reading, its colours uploaded
    // (host: on a software rasteriser the buffer is host memory, and llvmpipe's storage-buffer
    // loads are a loop over the SIMD lanes — the pass took ~34 ms of CPU a frame for the room at
    // K' = 256, the CPU's sum ~3 ms, bench/RESULTS.md "The viewer's frame on llvmpipe"). The glossy
    // term, the transfer view and glossy matrices always run in their compute passes. automatic:
    // host on a software rasteriser (is_software_renderer()), else device. The same float sums up
    // to their order (tests/render: HostAndDeviceShadingAgree).
    enum class VertexShading { automatic, device, host };
    void set_vertex_shading(VertexShading where);
    // Whether the last shading pass ran on the host.
    bool last_shading_on_host() const;

    int scene_K() const { return m_K; }
    int scene_channels() const { return m_channels; }
    // The scene's transfer is glossy matrices (drawn with DrawSettings::brdf and albedo).
    bool scene_has_matrices() const { return m_pass && is_glossy_matrix(m_layout); }
    // The scene's materials give BRDFs (Mesh::brdf_index not empty; DrawSettings::material_brdfs).
    bool scene_has_material_brdfs() const;
    // Bytes of transfer the GPU holds per vertex: the rows, or a CPCA code's share (its cluster
    // index and weights, and its part of the means and bases), as uploaded (float32).
    double transfer_bytes_per_vertex() const;
    // The receivers the scene's pass shades: vertices, or a glossy texel set's texels.
    std::size_t vertex_count() const;
    // The K' a draw with `K_used` uses: min(scene K, light K, K_used if > 0).
    int effective_K(int K_used) const;
    // How many times draw() has run the per-vertex shading pass (for tests and statistics).
    std::uint64_t shading_passes() const { return m_stats.shading_passes; }
    // How many times draw() has run the cluster pass of a CPCA code (light × cluster matrices).
    std::uint64_t cluster_passes() const { return m_stats.cluster_passes; }
    // How many times draw() has rebuilt the background texture.
    std::uint64_t background_builds() const { return m_background_builds; }

    // Draws the scene into the currently bound draw framebuffer with viewport (0, 0, width,
    // height), writing linear RGB (alpha 1) into colour attachment 0. Clears colour and depth.
    // Needs set_scene and set_light first (Error(invalid_argument) otherwise).
    void draw(const DrawSettings& settings, int width, int height);

    // Draws `target` into the currently bound framebuffer (viewport 0, 0 and the target's size):
    // the mean of each pixel's samples (the resolve, fused into this pass), scaled by `exposure`,
    // through the same filmic tone map and sRGB encoding as save_image's PNG output — a window
    // then shows what `shprt render` writes to a PNG. Needs no resolve() first.
    void present(const RenderTarget& target, float exposure);

    // draw, then present, in one pass, for single-sample frames: draws the scene straight into
    // the currently bound 8-bit framebuffer (the window's, or a DisplayTarget; it needs a depth
    // buffer), each fragment scaled by `exposure`, tone mapped and sRGB-encoded by the same GLSL
    // as present (the clear colour by display_encode8 on the host). No float target is drawn or
    // read: on a software rasteriser the present pass is about a third of a simple frame
    // (bench/RESULTS.md, "Single-sample frames without the present pass"). Throws what draw and
    // present throw.
    void draw_to_display(const DrawSettings& settings, int width, int height, float exposure);

private:
    // Makes the background texture for K' (if stale); returns the rotation to look it up with.
    Mat3d upload_background(int K);
    VertexShading m_vertex_shading = VertexShading::automatic;
    bool m_software = false;  // is_software_renderer(), asked once
    // The sun in the scene's frame (set_sun's, turned by the light's rotation) and its SH
    // uniform blocks; called by set_sun and set_light.
    void update_world_sun();
    // The sun's shadow map, redrawn if the sun or the scene changed (sun_pass.hpp).
    void update_sun_map();

    // draw and draw_to_display: exposure 0 writes linear radiance (into a float target), > 0
    // display codes.
    void draw_scene(const DrawSettings& settings, int width, int height, float exposure);

    unsigned m_present_program = 0;
    // The background programs writing linear radiance [0] or display codes [1]
    // (gl::fragment_shader), and the scene programs likewise, [display][sun code]: without the
    // sun, with a diffuse receivers' sun, with every sun term (gl::SunCode), compiled when first
    // drawn with (scene_program).
    unsigned m_background_program[2] = {0, 0};
    unsigned m_scene_program[2][3][2] = {};  // [display][sun code][sun filter]
    unsigned scene_program(int display, int sun_code);
    unsigned m_empty_vao = 0;
    unsigned m_light_ubo = 0, m_recurrence_ubo = 0, m_background_texture = 0;
    // The scene's pass, chosen by set_scene from the kind table (shading_pass): a VertexPass for
    // vertex vectors and vertex matrices, a TexelPass for texels; kept while the kind stays (its
    // compiled programs with it).
    std::unique_ptr<ScenePass> m_pass;
    int m_pass_kind = -1;     // the ShadingPass m_pass was made for
    TransferLayout m_layout;  // of the scene's transfer
    int m_K = 0, m_channels = 0;
    ShLight m_light{};         // rotated: what the shading pass uses
    ShLight m_light_source{};  // as given to set_light
    Mat3d m_light_rotation = Mat3d::identity();
    bool m_has_light = false;
    // What the background texture was made from: K', and the generation of the coefficients
    // (m_source_generation when made from the unrotated source, else m_light_generation).
    struct BackgroundKey {
        int K = -1;
        bool from_source = false;
        std::uint64_t generation = 0;
        bool operator==(const BackgroundKey&) const = default;
    };
    BackgroundKey m_background_key{};
    std::uint64_t m_light_generation = 0, m_source_generation = 0, m_background_builds = 0;
    mutable PassStats m_stats;             // the passes' counters, kept across scenes
    std::unique_ptr<ObjectPass> m_object;  // a probe-lit object (set_object), or none
    // The sun (set_sun): as given, and turned into the scene's frame; its SH projection alone
    // and added to the sky (uniform blocks in the light block's layout), for the bounced light
    // T · (c_sky + c_sun) − T_0 · c_sun that a pass with the transfer's direct part draws.
    std::optional<PreparedSun> m_sun_source;
    Sun m_world_sun{};
    ShLight m_world_sun_sh{};             // its SH projection in the scene's frame (host shading)
    std::unique_ptr<SunPass> m_sun_pass;  // the map at rest (set_shadow_map_size)
    std::unique_ptr<SunPass> m_sun_pass_moving;  // the map while moving, or none
    SunPass* m_sun_map = nullptr;                // the one the frame draws with
    int m_moving_shadow_map_size = 0;
    int m_shadow_map_size = kShadowMapSize;
    SunFilter m_sun_filter = SunFilter::full;
    unsigned m_sun_ubo = 0, m_sky_sun_ubo = 0;
    std::uint64_t m_sun_generation = 0, m_geometry_generation = 0;
    Vec3f m_bounds_centre{0, 0, 0};
    float m_bounds_radius = 0;
};

// One frame, headless: creates a HeadlessGlContext and calls render_image_in_current_context.
// What `shprt render` does (then save_image).
// `object`: a probe-lit object drawn with the scene (Renderer::set_object), or none.
struct DrawnObject {
    const Mesh* mesh = nullptr;  // its triangles
    const ObjectShading* shading = nullptr;
};
Image render_image(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                   const DrawSettings& settings, int width, int height, int samples = 4,
                   const PreparedSun* sun = nullptr, const DrawnObject* object = nullptr);

// One frame in the OpenGL context current on the calling thread (4.3 core; e.g. the viewer's
// offscreen context for --screenshot, which may be a hidden window): a Renderer with `light`
// (unrotated: set_light(light)) and `sun` (set_sun; in the light's frame, so prepared with the
// light's rotation), and a RenderTarget with `samples` samples; draws, resolves and reads back
// linear RGB (row 0 top). Its GL objects are released before it returns. Throws what Renderer
// and RenderTarget throw.
Image render_image_in_current_context(const Mesh& mesh, const TransferSet& transfer,
                                      const ShLight& light, const DrawSettings& settings, int width,
                                      int height, int samples = 4, const PreparedSun* sun = nullptr,
                                      const DrawnObject* object = nullptr);

}  // namespace shprt
