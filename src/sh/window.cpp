// SH windowing: Hann, Lanczos (sinc) and Sloan's Laplacian-regularised window.
// Reference: P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008 (windowing to reduce
// ringing; the Laplacian-based roughness penalty).
#include "shprt/sh/window.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/names.hpp"
#include "shprt/sh/basis.hpp"

#include <cmath>

namespace shprt {
namespace {

template <class T>
void apply_impl(WindowKind kind, T* coeffs, int K, double strength) {
    SHPRT_CHECK(K >= 0 && K <= sh_count(kMaxBands), invalid_argument,
                "apply_window: basis size K={} outside [0, {}]", K, sh_count(kMaxBands));
    if (K == 0) return;
    SHPRT_CHECK(coeffs != nullptr, invalid_argument, "apply_window: null coefficient pointer");
    const std::vector<double> w = window_weights(kind, sh_bands_for(K), strength);
    for (int i = 0; i < K; ++i) coeffs[i] = static_cast<T>(coeffs[i] * w[sh_band(i)]);
}

}  // namespace

namespace {
constexpr Named<WindowKind> kWindowNames[] = {{WindowKind::none, "none"},
                                              {WindowKind::hann, "hann"},
                                              {WindowKind::lanczos, "lanczos"},
                                              {WindowKind::sloan, "sloan"}};
}  // namespace

const char* to_string(WindowKind kind) { return name_of(kWindowNames, kind); }
WindowKind parse_window_kind(const std::string& name) {
    return parse_named(kWindowNames, name, "SH window");
}

std::vector<double> window_weights(WindowKind kind, int bands, double strength) {
    SHPRT_CHECK(bands >= 1 && bands <= kMaxBands, invalid_argument,
                "window_weights: bands must be in [1, {}], got {}", kMaxBands, bands);
    SHPRT_CHECK(std::isfinite(strength) && strength >= 0, invalid_argument,
                "window_weights: strength must be finite and >= 0, got {}", strength);
    std::vector<double> w(bands, 1.0);
    const double h = strength > 0 ? strength : static_cast<double>(bands);
    for (int l = 1; l < bands; ++l) {
        const double t = l / h;  // fraction of the window width
        switch (kind) {
            case WindowKind::none:
                break;
            case WindowKind::hann:
                w[l] = t < 1 ? 0.5 * (1.0 + std::cos(kPi * t)) : 0.0;
                break;
            case WindowKind::lanczos:
                w[l] = t < 1 ? std::sin(kPi * t) / (kPi * t) : 0.0;
                break;
            case WindowKind::sloan: {
                const double ll = static_cast<double>(l) * (l + 1);
                w[l] = 1.0 / (1.0 + strength * ll * ll);
                break;
            }
        }
    }
    return w;
}

void apply_window(WindowKind kind, double* coeffs, int K, double strength) {
    apply_impl(kind, coeffs, K, strength);
}

void apply_window(WindowKind kind, float* coeffs, int K, double strength) {
    apply_impl(kind, coeffs, K, strength);
}

}  // namespace shprt
