// The sun's direct light drawn per fragment with a shadow map: the renderer's twin of
// sun_direct_irradiance (shade/sun_shade.hpp, traced with Embree), for a sun kept out of the SH
// sum (`--sun`, docs/lights.md "A sun kept out of the SH sum"). Private to render/: the Renderer
// owns one while it has a sun, redraws the map when the sun turns or the scene changes, and
// binds it to the scene and texel programs, whose fragment shaders splice in sun_functions().
//
// The map: one orthographic depth map of size² texels (kShadowMapSize by default) along the sun's
// direction, fitted to the scene's bounding sphere (the scenes are bounded; a large scene gets
// coarser texels, 2·1.01·radius/size each — one map, no cascades). Both faces of every triangle
// cast.
//
// The filter (percentage-closer soft shadows, Fernando 2005, for a directional light): a
// blocker search over the disc that the sun's angular radius r opens from the receiver toward
// the map (radius = depth·tan r), then percentage-closer filtering over the disc whose radius
// is the receiver's mean distance to its blockers × tan r — the disc of directions the traced
// sun samples, cut through the blockers' plane. So a penumbra widens with the distance to the
// occluder as the traced one does; a point sun's edge is one texel wide. Receivers are offset
// along their normal by one texel before the lookup, every tap is compared with the receiver's
// plane extended to it (receiver-plane depth bias: a lit slope does not shadow itself across the
// filter's width), and the comparison keeps a texel of depth bias.
#pragma once

#include "gl_util.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/render/renderer.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace shprt {

namespace gl {
// GLSL 4.30: `vec3 sun_term(vec3 p, vec3 n, vec3 albedo, uint brdf)`, the direct sun at world
// point p with (unnormalised) normal n: albedo/π · E (mode 1), E (mode 2) or 0 (mode 0), E = E_n
// · V · max(0, n·s), E_n the disc's irradiance at normal incidence; for glossy matrices
// (bind_glossy) k·ρ_d/π·E + (1 − k)·ρ_s·L·Ω·f̄·V, f̄ the mean over the disc of the lobe of BRDF
// `brdf` of the table about the reflection direction (a 7-point disc rule; shade_glossy_with_sun
// sums it over the disc's traced directions). Spliced at "// @sun"
// (after "// @output" in the same shader; needs kPi). `filter` sets the filter's taps
// (renderer.hpp, SunFilter).
std::string sun_functions(SunFilter filter);
// Its uniform locations (layout(location = N)) and the shadow map's texture unit.
// kBasis is a mat3 (columns u, v, s: the map's axes and the direction toward the sun), three
// locations; kToMap a mat4, four.
namespace sun_loc {
inline constexpr int kMode = 20, kBasis = 21, kIrradiance = 24, kToMap = 25, kFilter = 29,
                     kGlossy = 30, kEye = 31, kDiffuseShare = 32, kAlbedo = 33, kRadianceOmega = 34,
                     kBrdfs = 35, kSpecular = 67;
}
inline constexpr int kSunMaxBrdfs = 32;  // BRDFs a glossy draw under the sun holds (u_sun_brdf)
inline constexpr unsigned kShadowMapUnit = 2;
}  // namespace gl

// The sun_term mode for a view: 1 radiance, 2 irradiance, 0 (no sun) for the transfer view.
enum class SunMode { none = 0, radiance = 1, irradiance = 2 };

class SunPass {
public:
    // Compiles the depth program and makes the map, `size` texels a side. Needs a current
    // OpenGL 4.3 core context.
    explicit SunPass(int size = kShadowMapSize);
    ~SunPass();
    SunPass(const SunPass&) = delete;
    SunPass& operator=(const SunPass&) = delete;

    // Redraws the map when the sun's direction, the sphere or `geometry` (a generation the caller
    // bumps whenever the triangles change) differ from the last call: binds the map's
    // framebuffer, sets the depth program's matrix and calls `draw_triangles` (which binds a
    // vertex array with positions at attribute 0 and draws), then restores the framebuffer and
    // viewport that were bound. `sun` is in the scene's frame (already turned with the light).
    void update(const Sun& sun, Vec3f centre, float radius, std::uint64_t geometry,
                const std::function<void()>& draw_triangles);
    // Sets sun_term's uniforms on the program in use, whose fragment shader has the sun `code`
    // (gl::fragment_shader; not none), and binds the map at kShadowMapUnit.
    void bind(SunMode mode, gl::SunCode code = gl::SunCode::full) const;
    // Sets sun_term's mode to none on the program in use (a program without a sun).
    static void bind_none();
    // After bind(SunMode::radiance): glossy matrices' sun term, as shade_glossy_with_sun, with
    // the eye, diffuse share k, the albedo override and the BRDF table (brdf_table order: the
    // vertices' brdf indices point into it; at most kSunMaxBrdfs, else Error(unsupported)).
    void bind_glossy(Vec3f eye, double k, const std::optional<Vec3f>& albedo,
                     const std::vector<Brdf>& brdfs) const;

    std::uint64_t map_builds() const { return m_builds; }  // for tests and statistics
    // Whether the map was drawn for this sun direction and radius, sphere and geometry (update
    // would not redraw it).
    bool drawn_for(const Sun& sun, Vec3f centre, float radius, std::uint64_t geometry) const;
    int size() const { return m_size; }

    // A texel's width (world) of a `size`² map fitted to a sphere of `radius`.
    static double texel_size(float radius, int size);

private:
    unsigned m_program = 0, m_fbo = 0, m_map = 0;
    int m_size = kShadowMapSize;
    Sun m_sun{};
    Vec3f m_centre{0, 0, 0};
    float m_radius = 0;
    std::uint64_t m_geometry = ~std::uint64_t(0), m_builds = 0;
    float m_to_map[16] = {};  // world → (s, t, depth) in [0, 1], column-major
    float m_basis[9] = {};    // u, v, s as columns
};

}  // namespace shprt
