// Distant light as SH vectors: every light source shprt knows — environment maps (equirect,
// cube cross, six faces) and analytic skies (constant, gradient, sun disc, the built-in sky) —
// becomes an ShLight, three channels (RGB) × K coefficients in the basis of sh/basis.hpp.
//
// Conventions
// * A light is the radiance L(d) arriving from direction d (d a unit world vector pointing from
//   the scene toward the source; right-handed, +Y up). Its coefficients are
//   c_i = ∫ L(d) y_i(d) dω, so a constant sky of radiance 1 has c_0 = sqrt(4π) and the diffuse
//   transfer of DESIGN.md turns it into irradiance π.
// * Maps are projected with the exact solid angle of every pixel or texel, a pixel being a patch
//   of constant radiance. Equirect pixels are integrated against the basis exactly (to
//   rounding); cube texels use the basis at the texel centre times the exact texel solid angle
//   (so only c_0 is exact for a constant cube map; the others are off by O(texel²)). Analytic
//   lights that are symmetric about an axis (sun disc, gradient sky) are projected exactly: their
//   zonal coefficients by Gauss–Legendre quadrature in 1D (exact for the polynomial pieces), then
//   turned toward their axis with c_lm = sqrt(4π/(2l+1)) z_l y_lm(axis). No sampling noise.
// * A basis size K that is not a full band (K ≠ n²) is allowed; rotating such a light pads the
//   last band with zeros, which is not rotation invariant (see rotate_light).
//
// Light specs (`--light`, repeatable; several specs are summed):
//   FILE.hdr | FILE.exr | FILE.png   2:1 → equirect map; 4:3 or 3:4 → cube cross
//   equirect:FILE, cross:FILE        force the layout
//   faces:PX,NX,PY,NY,PZ,NZ          six square face images (orientations: light/cubemap.hpp)
//   constant[:V | :R,G,B]            uniform sky, radiance 1 by default
//   gradient[:ZR,ZG,ZB[:HR,HG,HB[:GR,GG,GB]]]   zenith / horizon / ground sky (GradientSky)
//   sun:X,Y,Z[,RADIUS_DEG[,R,G,B]]   disc toward (X,Y,Z), radius 2° by default, radiance R,G,B
//                                    (default: white with irradiance 3 at normal incidence)
//   builtin                          built-in sky + sun (builtin_light)
// docs/lights.md has examples and pictures in words.
#pragma once

#include "shprt/sh/basis.hpp"

#include "shprt/core/vec.hpp"
#include "shprt/light/image.hpp"
#include "shprt/sh/window.hpp"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace shprt {

struct ShLight {
    int K = 0;
    std::vector<float> coeffs;  // 3·K floats, channel-major: coeffs[c·K + i], c = 0 R, 1 G, 2 B

    // A black light of basis size K. Throws Error(invalid_argument) unless 1 ≤ K ≤ kMaxLightK.
    static ShLight zero(int K);

    const float* channel(int c) const { return coeffs.data() + static_cast<std::size_t>(c) * K; }
    float* channel(int c) { return coeffs.data() + static_cast<std::size_t>(c) * K; }
};

// Largest basis size a light may have (32 bands, the largest transfer the library bakes).
inline constexpr int kMaxLightK = sh_count(kMaxComputeBands);

// Adds `b` into `a` coefficient by coefficient; both must have the same K
// (Error(invalid_argument) otherwise).
void add_light(ShLight& a, const ShLight& b);

// Radiance of the band-limited light in unit direction d (the SH reconstruction, RGB).
Vec3d light_radiance(const ShLight& light, Vec3d d);

// ---- Parsing ---------------------------------------------------------------------------------

// One spec (syntax above) projected to basis size K. Throws shprt::Error naming the spec (and
// the file, for file specs) and saying what was expected: Error(invalid_argument) for a bad
// spec or K, the errors of load_image for files, Error(format) for a map of the wrong shape
// (checked from the file's header, before decoding) or with a negative pixel (a light is
// radiance ≥ 0, as constant:V, sun and gradient colours), Error(invalid_argument) for a light
// so bright that a coefficient overflows float (constant:1e38).
ShLight parse_light(const std::string& spec, int K);

// Sum of the specs, each through parse_light; an empty list means {"builtin"}. A sum that
// overflows float is Error(invalid_argument).
ShLight make_light(const std::vector<std::string>& specs, int K);

// The files a spec reads (FILE.hdr, equirect:FILE, cross:FILE, the six of faces:...), without
// reading them; empty for analytic lights and for text that is no spec. For the check that an
// output does not overwrite an input (core/file.hpp check_output_is_not_input).
std::vector<std::string> light_spec_files(const std::string& spec);

// ---- Checks (the command line's, for lights from elsewhere: Python arrays) ---------------------

// Throws Error(format) naming `name` and the first pixel that is NaN, infinite ("image NAME has a
// NaN value at pixel (x, y) channel R") or negative (a light's radiance is ≥ 0): what parse_light
// refuses in a file.
void check_radiance_map(const std::string& name, const Image& image);

// Throws Error(invalid_argument) for the first non-finite coefficient: "WHAT is too bright: its
// SH coefficient i of channel C overflows float" (infinite: what parse_light refuses for
// constant:1e38 or a map of 3e38 pixels), or "WHAT is not a number: ... is NaN".
void check_finite_light(const ShLight& light, const std::string& what);

// ---- Environment maps ------------------------------------------------------------------------

// Projects an equirect map (any width × height, light/equirect.hpp orientation). Each pixel is
// a patch of constant radiance, and its integral against every basis function is computed to
// rounding (closed form in φ, Gauss–Legendre in θ), so a constant map gives exactly
// c_0 = sqrt(4π)·L and zero elsewhere, and the pixel solid angles are exact. Separable fast
// path: per row, Fourier sums over the columns in a frame whose pole is +Y, then one SH rotation
// to world axes; O(W·H·bands + H·K). Agrees with project_equirect_reference to rounding.
// Throws Error(invalid_argument) for an empty image or a bad K.
ShLight project_equirect(const Image& map, int K);

// The same projection fed one row at a time, top row first, so that a map need never be held
// whole (light_from_file streams an OpenEXR light through it in blocks of rows): memory is
// O(W·bands + K), and the result is bit for bit project_equirect's. Throws Error(invalid_argument)
// for an empty size or a bad K, a row beyond the height, or finish() before every row was added.
class EquirectProjection {
public:
    EquirectProjection(int width, int height, int K);
    ~EquirectProjection();
    EquirectProjection(EquirectProjection&&) noexcept;
    EquirectProjection& operator=(EquirectProjection&&) noexcept;
    int width() const;
    int height() const;
    int rows_added() const;
    // Adds the next row: `rgb` holds width() pixels of three floats (light/image.hpp layout).
    void add_row(const float* rgb);
    ShLight finish() const;

private:
    struct State;
    std::unique_ptr<State> m_state;
};

// Slow reference for the same pixel integrals: a tensor Gauss–Legendre rule over every pixel's
// (θ, φ) rectangle in world coordinates; O(W·H·K·n²) with n ≈ 6 + bands·π/H nodes per side.
ShLight project_equirect_reference(const Image& map, int K);

// Projects a cube cross: horizontal 4:3 (face size W/4 = H/3) or vertical 3:4 (W/3 = H/4), with
// exact texel solid angles; orientation in light/cubemap.hpp. Throws Error(format) if the image
// is not an exact 4:3 or 3:4 cross.
ShLight project_cube_cross(const Image& cross, int K);

// Projects six square face images of equal size, in CubeFace order (+X, −X, +Y, −Y, +Z, −Z),
// each oriented as in the horizontal cross. Throws Error(format) on mismatched or non-square
// faces.
ShLight project_cube_faces(const std::array<Image, 6>& faces, int K);

// ---- Analytic lights -------------------------------------------------------------------------

// Uniform sky of the given radiance: c_0 = sqrt(4π)·radiance, all else 0.
ShLight constant_light(Vec3d radiance, int K);

// A smooth sky, symmetric about +Y, as a function of t = d.y:
//   t ≥ 0: L = horizon + (zenith − horizon)·(1 − (1 − t)³)
//   t < 0: L = horizon + (ground − horizon)·(1 − (1 + t)⁸)
// continuous at the horizon; the ground darkens within ~15° below it.
struct GradientSky {
    Vec3d zenith{0.25, 0.45, 0.95};
    Vec3d horizon{0.85, 0.9, 1.0};
    Vec3d ground{0.12, 0.1, 0.08};
};
Vec3d gradient_radiance(const GradientSky& sky, Vec3d d);  // the function above; d unit
ShLight gradient_light(const GradientSky& sky, int K);     // exact projection

// Radiance (per channel) that gives irradiance E at normal incidence for a disc of the given
// angular radius: E = L·π·sin²(radius).
Vec3d sun_radiance_for_irradiance(Vec3d irradiance, double radius_deg);

// A disc of angular radius `radius_deg` ∈ (0, 90] around direction `dir` (any non-zero length;
// normalised) with constant radiance `radiance`, projected exactly (zonal quadrature + the
// zonal rotation identity). Throws Error(invalid_argument) for a zero direction, a radius
// outside (0, 90] or a bad K.
ShLight sun_light(Vec3d dir, double radius_deg, Vec3d radiance, int K);

// The built-in environment, so demos need no files: gradient_light(GradientSky{}) plus a warm
// sun of radius 2° and irradiance ≈ (3.2, 3.0, 2.7) at normal incidence toward
// builtin_sun_direction(), plus a broad glow around the sun, exp(8(d·s − 1)) × 0.3·(1, 0.9, 0.7).
// Every part is zonal, so the whole is projected exactly.
ShLight builtin_light(int K);
Vec3d builtin_sun_direction();    // unit: 50° above the horizon, azimuth 35° from −Z to +X
Vec3d builtin_radiance(Vec3d d);  // the built-in environment's radiance function (unlimited)

// ---- Operations ------------------------------------------------------------------------------

// Rotates the light by the rotation matrix R: afterwards L'(d) = L(R⁻¹ d), i.e. a sun toward s
// moves toward R·s. Done on the coefficients through ShRotation (never by re-projecting). When
// K is not a full band the last band is padded with zeros, rotated, and truncated again, which
// is only approximate; callers that care use full bands.
void rotate_light(ShLight& light, const Mat3d& R);

// Multiplies the coefficients of every channel by the window `kind` (sh/window.hpp), e.g. to
// tame ringing around a sun. `strength` as in apply_window.
void window_light(ShLight& light, WindowKind kind, double strength = 0);

}  // namespace shprt
