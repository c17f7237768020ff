// Zonal harmonics: functions symmetric about +Z (the SH pole, see sh/basis.hpp), stored as one
// coefficient per band, z_l = the coefficient of y_l^0. A zonal function's full SH vector has
// only the m = 0 entries: c[l(l+1)] = z_l.
//
// Two identities make zonal functions cheap (Sloan, "Stupid Spherical Harmonics (SH) Tricks",
// GDC 2008; Ramamoorthi & Hanrahan 2001):
// * Rotation to a direction (addition theorem): rotating the pole of a zonal function h onto the
//   unit direction d gives g(ω) = h(R⁻¹ω) with R ẑ = d, whose coefficients are
//       c_lm = sqrt(4π/(2l+1)) · z_l · y_lm(d)                                — O(K).
// * Convolution (Funk–Hecke): ∫ f(ω') h(ω·ω') dω' has coefficients sqrt(4π/(2l+1)) · z_l · c_lm.
//   With the clamped cosine, Â_l = sqrt(4π/(2l+1)) z_l = π, 2π/3, π/4, 0, −π/24, ... and
//   convolving a radiance vector gives the irradiance vector (E = Σ Â_l L_lm y_lm).
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/sh/basis.hpp"

#include <cmath>
#include <functional>
#include <vector>

namespace shprt {

// z_l, l = 0..bands−1, of max(0, cos θ) in closed form:
//   z_0 = √π/2, z_1 = √(π/3), z_l = 0 for odd l ≥ 3, and for even l ≥ 2
//   z_l = √((2l+1)π) · a_l,  a_2 = 1/8,  a_{l+2} = −(l−1)/(l+4) · a_l
// (a_l = ∫₀¹ x P_l(x) dx; the ratio form never overflows). Throws Error for bands outside
// [1, kMaxBands].
std::vector<double> clamped_cosine_zonal(int bands);

// z_l of the normalised Phong-like lobe ((s+1)/(2π)) · max(0, cos θ)^s, which integrates to 1
// over the sphere (so the lobe's z_0 = 1/√(4π)). Closed form: z_l = √((2l+1)/(4π)) (s+1) I_l
// with I_l = ∫₀¹ x^s P_l(x) dx, I_0 = 1/(s+1), I_1 = 1/(s+2), I_l = (s−l+2)/(s+l+1) · I_{l−2}.
// s = 1 is the clamped cosine divided by π. Throws Error for s < 0, s not finite, or bands
// outside [1, kMaxBands].
std::vector<double> phong_lobe_zonal(int bands, double s);

// z_l, l = 0..bands−1, of the zonal function f(cos θ) by Gauss–Legendre quadrature in x = cos θ,
// z_l = 2π ∫ f(x) y_l^0(x) dx, integrating [−1, 0] and [0, 1] separately with `nodes` nodes each
// (so a lobe that is cut off at the horizon x = 0 is integrated exactly where it is smooth).
// Also returns ∫ f² dω in *norm2 (when non-null): the residual of the n-band fit is
// sqrt(norm2 − Σ z_l²) (Parseval; the projection is the L2-optimal zonal fit). Throws Error for
// bands outside [1, kMaxBands] or nodes < 1.
std::vector<double> project_zonal(const std::function<double(double)>& f, int bands,
                                  int nodes = 256, double* norm2 = nullptr);

// Rotates the zonal function `zonal` (z_l for every band touched by K, i.e. at least
// sh_bands_for(K) values) so that its pole points along `dir`, writing the first K coefficients:
//   out[l(l+1)+m] = sqrt(4π/(2l+1)) · z_l · y_lm(dir).
// Precondition: dir is a unit vector (not checked; host and device, no allocation). Equals
// ShRotation (any R with R ẑ = dir) applied to the zonal vector.
template <class T>
SHPRT_HD void rotate_zonal(const T* zonal, int K, Vec3<T> dir, T* out) {
    if (K <= 0) return;
    sh_eval_k(K, dir.x, dir.y, dir.z, out);
    constexpr T kFourPi = T(12.5663706143591729538505735331180115);
    for (int l = 0; l * l < K; ++l) {
        const T scale = std::sqrt(kFourPi / T(2 * l + 1)) * zonal[l];
        const int end = (l + 1) * (l + 1) < K ? (l + 1) * (l + 1) : K;
        for (int i = l * l; i < end; ++i) out[i] *= scale;
    }
}

// Funk–Hecke convolution in place: coeffs[l(l+1)+m] *= sqrt(4π/(2l+1)) · zonal[l] for the first
// K coefficients. Needs bands_zonal ≥ sh_bands_for(K) (a kernel with too few bands is an error,
// not a silent zero); throws Error(invalid_argument) otherwise or when K < 0.
void convolve_zonal(const double* zonal, int bands_zonal, double* coeffs, int K);
void convolve_zonal(const double* zonal, int bands_zonal, float* coeffs, int K);

// The zonal vector's full SH coefficients: out[l(l+1)] = z_l, every other of the first K = 0.
void zonal_to_coeffs(const double* zonal, int bands_zonal, double* out, int K);

}  // namespace shprt
