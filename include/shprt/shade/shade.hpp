// Per-vertex shading with baked transfer and an SH light: the paper's shading model, evaluated on
// the CPU in double precision. This is the reference the OpenGL renderer (render/renderer.hpp)
// is tested against; both compute exactly the formulas below.
//
// For vertex v with position p, unit normal n, albedo ρ, transfer c_T (channel c of an RGB
// transfer, or the single grey channel for every colour), and the light c_L (colour c):
//
//   E_c   = Σ_{i<K'} c_T,c^i · c_L,c^i                                   irradiance (W/m²-like)
//   L_D,c = ρ_c / π · E_c                                                 diffuse radiance
//   w     = normalize(eye − p)          view direction (toward the eye)
//   r     = 2 (n·w) n − w               reflection of the view direction about n
//   c_s   = the zonal Phong lobe of exponent s (sh/zonal.hpp, phong_lobe_zonal) rotated to r
//           in O(K) (rotate_zonal: c_s^{lm} = sqrt(4π/(2l+1)) z_l y_lm(r))
//   cos η = max(n·r, kMinCosEta) = max(n·w, kMinCosEta)    η: angle between lobe axis and n
//   L_S,c = (Σ c_s^i c_L,c^i) · (Σ c_T,c^i c_s^i) / cos η                 glossy radiance
//   L_c   = k · L_D,c + (1 − k) · L_S,c
//
// The first factor of L_S is the light seen through the lobe (the lobe integrates to 1, so for a
// narrow lobe it is the incident radiance from r); the second is the paper's self-shadowing
// estimate: the transfer (visibility × cosine) against the lobe is ≈ V(r)·cos η, hence the
// division. The glossy reflectance is white (albedo does not enter L_S), as in the paper.
//
// cos η is clamped from below at kMinCosEta (≈ 84°): at grazing views the estimate's ratio of two
// small, independently truncated quantities is unstable, and behind the surface (n·w < 0, seen
// when back faces are drawn) the transfer against the lobe is ≈ 0 anyway. No other clamping:
// negative values from SH ringing are returned as computed (images clamp when tone mapped).
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <vector>

namespace shprt {

// What is shown per vertex, texel or pixel (`--view`).
enum class ShadeView {
    radiance,    // L = k·L_D + (1−k)·L_S (the picture)
    irradiance,  // E
    transfer,    // transfer only, AO-like: E under a uniform white sky of radiance 1, divided by
                 // π (1 = unoccluded, 0 = fully blocked), grey; ignores light, albedo, k, K'
};

// Lower clamp of cos η in the glossy term's division (see above).
inline constexpr double kMinCosEta = 0.1;

struct ShadeOptions {
    double k = 1.0;                // diffuse share in [0, 1]; 1 = pure diffuse (L_S not computed)
    double gloss = kDefaultGloss;  // Phong exponent s ≥ 0 of the glossy lobe
    Vec3f eye{0, 0, 0};            // world-space eye position (only used when k < 1)
    int K_used = 0;                // use the first K' coefficients; 0 = all available
};

// The basis size actually used: min(transfer.K, light.K, K_used if > 0). Throws
// Error(invalid_argument) if K_used < 0 or the result is 0.
int effective_basis_size(const TransferSet& transfer, const ShLight& light, int K_used);

// Per-band factors g_l = sqrt(4π/(2l+1)) · z_l of the Phong lobe of exponent `gloss`, for
// l < bands, so that the lobe rotated to direction d has coefficients g_l · y_lm(d). The GL
// renderer uploads these; `shade_vertices` uses rotate_zonal directly.
std::vector<float> lobe_band_factors(int bands, double gloss);
// The same factors g_l = sqrt(4π/(2l+1)) · z_l of any zonal lobe z (sh/zonal.hpp convention).
std::vector<float> zonal_band_factors(const std::vector<double>& zonal);

struct ShadeResult {
    std::vector<Vec3f> irradiance;  // E, per vertex, input order
    std::vector<Vec3f> radiance;    // L = k·L_D + (1−k)·L_S, per vertex, input order
};

// Checks that `transfer` can shade `mesh`: transfer.check(mesh) (Error(invalid_argument) naming
// what is wrong), vertex receivers (Error(unsupported) for texel transfer: texel_shade.hpp), and a
// vector per receiver (Error(unsupported) for transfer matrices, which this shading model does not
// use). Shared by shade_vertices and the OpenGL renderer.
void check_shadable(const Mesh& mesh, const TransferSet& transfer);

// Shades every vertex (formulas above) on the CPU in double precision, in parallel (TBB); the
// result does not depend on the thread count. Preconditions, checked (Error(invalid_argument)):
// check_shadable(mesh, transfer), 0 ≤ k ≤ 1, gloss ≥ 0, light.coeffs.size() == 3·light.K.
ShadeResult shade_vertices(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                           const ShadeOptions& options);

}  // namespace shprt
