// Zonal harmonics: clamped cosine and Phong-like lobes in closed form, Funk–Hecke convolution.
// References: R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance
// Environment Maps", SIGGRAPH 2001 (clamped-cosine coefficients); P.-P. Sloan, "Stupid
// Spherical Harmonics (SH) Tricks", GDC 2008 (zonal rotation and convolution, Phong lobes).
#include "shprt/sh/zonal.hpp"

#include "sh/quadrature.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"

#include <cmath>

namespace shprt {
namespace {

void check_bands(int bands, const char* what) {
    SHPRT_CHECK(bands >= 1 && bands <= kMaxBands, invalid_argument,
                "{}: bands must be in [1, {}], got {}", what, kMaxBands, bands);
}

template <class T>
void convolve_impl(const double* zonal, int bands_zonal, T* coeffs, int K) {
    SHPRT_CHECK(K >= 0, invalid_argument, "convolve_zonal: negative basis size K={}", K);
    if (K == 0) return;
    SHPRT_CHECK(zonal != nullptr && coeffs != nullptr, invalid_argument,
                "convolve_zonal: null pointer");
    SHPRT_CHECK(bands_zonal >= sh_bands_for(K), invalid_argument,
                "convolve_zonal: kernel has {} bands but K={} needs {}", bands_zonal, K,
                sh_bands_for(K));
    for (int l = 0; l * l < K; ++l) {
        const double scale = std::sqrt(4.0 * kPi / (2 * l + 1)) * zonal[l];
        const int end = (l + 1) * (l + 1) < K ? (l + 1) * (l + 1) : K;
        for (int i = l * l; i < end; ++i) coeffs[i] = static_cast<T>(coeffs[i] * scale);
    }
}

}  // namespace

std::vector<double> clamped_cosine_zonal(int bands) {
    check_bands(bands, "clamped_cosine_zonal");
    std::vector<double> z(bands, 0.0);
    z[0] = std::sqrt(kPi) / 2.0;
    if (bands > 1) z[1] = std::sqrt(kPi / 3.0);
    double a = 1.0 / 8.0;  // a_l = ∫₀¹ x P_l(x) dx for even l, starting at l = 2
    for (int l = 2; l < bands; l += 2) {
        z[l] = std::sqrt((2.0 * l + 1.0) * kPi) * a;
        a *= -(l - 1.0) / (l + 4.0);
    }
    return z;
}

std::vector<double> phong_lobe_zonal(int bands, double s) {
    check_bands(bands, "phong_lobe_zonal");
    SHPRT_CHECK(std::isfinite(s) && s >= 0.0, invalid_argument,
                "phong_lobe_zonal: exponent s must be finite and >= 0, got {}", s);
    std::vector<double> z(bands, 0.0);
    // I_l = ∫₀¹ x^s P_l(x) dx by the two-step recurrence (from x P_l = ((l+1)P_{l+1} + l P_{l−1})
    // /(2l+1) and integration by parts); it is exact, with no cancellation.
    double i_even = 1.0 / (s + 1.0), i_odd = 1.0 / (s + 2.0);
    for (int l = 0; l < bands; ++l) {
        double& i_l = (l % 2 == 0) ? i_even : i_odd;
        if (l >= 2) i_l *= (s - l + 2.0) / (s + l + 1.0);
        z[l] = std::sqrt((2.0 * l + 1.0) / (4.0 * kPi)) * (s + 1.0) * i_l;
    }
    return z;
}

std::vector<double> project_zonal(const std::function<double(double)>& f, int bands, int nodes,
                                  double* norm2) {
    check_bands(bands, "project_zonal");
    SHPRT_CHECK(nodes >= 1, invalid_argument, "project_zonal: nodes = {} must be ≥ 1", nodes);
    std::vector<double> x, w;
    detail::gauss_legendre(nodes, x, w);
    std::vector<double> z(bands, 0.0), p(bands);
    double n2 = 0;
    for (int half = 0; half < 2; ++half) {
        for (int q = 0; q < nodes; ++q) {
            // [−1, 1] → [0, 1] (half 0) or [−1, 0] (half 1); the Jacobian is 1/2.
            const double t = half == 0 ? 0.5 * (x[q] + 1) : 0.5 * (x[q] - 1);
            const double weight = 2 * kPi * 0.5 * w[q];
            const double v = f(t);
            // Legendre P_l(t) by the three-term recurrence; y_l^0 = sqrt((2l+1)/(4π)) P_l.
            p[0] = 1;
            if (bands > 1) p[1] = t;
            for (int l = 2; l < bands; ++l)
                p[l] = ((2 * l - 1) * t * p[l - 1] - (l - 1) * p[l - 2]) / l;
            for (int l = 0; l < bands; ++l)
                z[l] += weight * v * std::sqrt((2 * l + 1) / (4 * kPi)) * p[l];
            n2 += weight * v * v;
        }
    }
    if (norm2) *norm2 = n2;
    return z;
}

void convolve_zonal(const double* zonal, int bands_zonal, double* coeffs, int K) {
    convolve_impl(zonal, bands_zonal, coeffs, K);
}

void convolve_zonal(const double* zonal, int bands_zonal, float* coeffs, int K) {
    convolve_impl(zonal, bands_zonal, coeffs, K);
}

void zonal_to_coeffs(const double* zonal, int bands_zonal, double* out, int K) {
    SHPRT_CHECK(K >= 0, invalid_argument, "zonal_to_coeffs: negative basis size K={}", K);
    SHPRT_CHECK(bands_zonal >= sh_bands_for(K), invalid_argument,
                "zonal_to_coeffs: kernel has {} bands but K={} needs {}", bands_zonal, K,
                sh_bands_for(K));
    for (int i = 0; i < K; ++i) out[i] = 0.0;
    for (int l = 0; sh_index(l, 0) < K; ++l) out[sh_index(l, 0)] = zonal[l];
}

}  // namespace shprt
