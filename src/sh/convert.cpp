// SH convention converters (see include/shprt/sh/convert.hpp for what each convention is and
// where that was read). References: P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC
// 2008 (the basis Unity uses); R. Ramamoorthi, P. Hanrahan 2001 (clamped-cosine factors).
#include "shprt/sh/convert.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/sh/basis.hpp"

#include <array>
#include <cmath>

namespace shprt {
namespace {

// (−1)^m for index i = l(l+1)+m.
double cs_sign(int i) {
    const int l = sh_band(i), m = i - sh_index(l, 0);
    return (m & 1) ? -1.0 : 1.0;
}

// Mirror x → −x: y_lm(−x, y, z) = s_lm y_lm(x, y, z) (cos mφ → (−1)^m cos mφ,
// sin mφ → −(−1)^m sin mφ under φ → π − φ).
double mirror_x_sign(int i) {
    const int l = sh_band(i), m = i - sh_index(l, 0);
    const double p = (m & 1) ? -1.0 : 1.0;
    return m >= 0 ? p : -p;
}

// Unity's stored form per index: basis constant with sign × clamped-cosine factor Â_l/π.
std::array<double, 9> unity_normalisation() {
    const double sp = std::sqrt(kPi);
    const double c0 = 1.0 / (2.0 * sp), c1 = std::sqrt(3.0) / (3.0 * sp);
    const double c2 = std::sqrt(15.0) / (8.0 * sp), c3 = std::sqrt(5.0) / (16.0 * sp);
    const double c4 = std::sqrt(15.0) / (16.0 * sp);
    return {c0, -c1, c1, -c1, c2, -c2, c3, -c2, c4};
}

void check_count(int K, const char* what) {
    SHPRT_CHECK(K >= 0, invalid_argument, "{}: negative basis size K={}", what, K);
}

}  // namespace

void to_no_condon_shortley(const double* in, double* out, int K) {
    check_count(K, "to_no_condon_shortley");
    for (int i = 0; i < K; ++i) out[i] = cs_sign(i) * in[i];
}

void from_no_condon_shortley(const double* in, double* out, int K) {
    check_count(K, "from_no_condon_shortley");
    for (int i = 0; i < K; ++i) out[i] = cs_sign(i) * in[i];
}

void to_threejs_l2(const double* in9, double* out9) { to_no_condon_shortley(in9, out9, 9); }
void from_threejs_l2(const double* in9, double* out9) { from_no_condon_shortley(in9, out9, 9); }

void to_unity_l2(const double* in9, double* out9) {
    for (int i = 0; i < 9; ++i) out9[i] = mirror_x_sign(i) * in9[i];
}

void from_unity_l2(const double* in9, double* out9) {
    for (int i = 0; i < 9; ++i) out9[i] = mirror_x_sign(i) * in9[i];  // an involution
}

void to_unity_probe_l2(const double* in9, double* out9) {
    const auto k = unity_normalisation();
    for (int i = 0; i < 9; ++i) out9[i] = mirror_x_sign(i) * in9[i] * k[i];
}

void from_unity_probe_l2(const double* in9, double* out9) {
    const auto k = unity_normalisation();
    for (int i = 0; i < 9; ++i) out9[i] = mirror_x_sign(i) * in9[i] / k[i];
}

}  // namespace shprt
