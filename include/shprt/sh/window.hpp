// Windowing (ringing control) of SH vectors: every coefficient of band l is multiplied by a
// weight w_l ∈ [0, 1], w_0 = 1, non-increasing in l. Windows trade sharpness for less ringing
// (Gibbs overshoot, negative lobes) of truncated SH reconstructions. With n = number of bands
// and h = the window width (h = strength when strength > 0, else h = n):
//
//   none     w_l = 1
//   hann     w_l = (1 + cos(π l / h)) / 2   for l < h, 0 beyond      (zero at l = h)
//   lanczos  w_l = sinc(π l / h) = sin(π l/h) / (π l/h), w_0 = 1, for l < h; 0 beyond
//   sloan    w_l = 1 / (1 + λ l²(l+1)²),  λ = strength ≥ 0  (λ = 0: no change)
//
// Sloan's window (P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008, §
// "Windowing"/"ringing") is the minimiser of ‖g − f‖² + λ ∫ (Δg)² dω: the Laplacian of band l
// has eigenvalue −l(l+1), so ∫ (Δg)² = Σ l²(l+1)² g_lm² and each band shrinks by
// 1/(1 + λ l²(l+1)²). Hann and Lanczos are the classic signal windows over band index (Sloan
// 2008 discusses both). For a basis size K that is not a square, n = sh_bands_for(K).
#pragma once

#include <string>
#include <vector>

namespace shprt {

enum class WindowKind { none, hann, lanczos, sloan };

const char* to_string(WindowKind kind);
// "none", "hann", "lanczos" or "sloan"; throws Error(invalid_argument) naming the value.
WindowKind parse_window_kind(const std::string& name);

// The weights w_0..w_{bands−1} (see above). Throws Error(invalid_argument) for bands outside
// [1, kMaxBands] or strength negative or not finite.
std::vector<double> window_weights(WindowKind kind, int bands, double strength = 0);

// Multiplies the first K coefficients by their band's weight (n = sh_bands_for(K)); in place.
// K = 0 is a no-op; K < 0 or K > kMaxBands² throws.
void apply_window(WindowKind kind, double* coeffs, int K, double strength = 0);
void apply_window(WindowKind kind, float* coeffs, int K, double strength = 0);

}  // namespace shprt
