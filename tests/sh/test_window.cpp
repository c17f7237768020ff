// SH windowing: weight properties (range, w_0 = 1, monotone), the documented formulas, identity
// for none, less ringing on a truncated clamped cosine, apply on partial bases, bad input.
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/window.hpp"
#include "shprt/sh/zonal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace shprt {
namespace {

constexpr double kFormulaTol = 1e-15;

const WindowKind kAll[] = {WindowKind::none, WindowKind::hann, WindowKind::lanczos,
                           WindowKind::sloan};

TEST(Window, WeightsAreInUnitRangeStartAtOneAndNeverIncrease) {
    for (WindowKind kind : kAll)
        for (int bands : {1, 2, 3, 6, 16, 32, kMaxBands})
            for (double strength : {0.0, 0.001, 0.5, 3.0, 10.0}) {
                const std::vector<double> w = window_weights(kind, bands, strength);
                ASSERT_EQ(static_cast<int>(w.size()), bands);
                EXPECT_EQ(w[0], 1.0);
                for (int l = 0; l < bands; ++l) {
                    EXPECT_GE(w[l], 0.0) << to_string(kind) << " l=" << l;
                    EXPECT_LE(w[l], 1.0) << to_string(kind) << " l=" << l;
                    if (l > 0) {
                        EXPECT_LE(w[l], w[l - 1]) << to_string(kind) << " l=" << l;
                    }
                }
            }
}

TEST(Window, DocumentedFormulas) {
    const int n = 8;
    const auto none = window_weights(WindowKind::none, n);
    for (double w : none) EXPECT_EQ(w, 1.0);
    const auto hann = window_weights(WindowKind::hann, n);  // h = n
    const auto lanczos = window_weights(WindowKind::lanczos, n);
    for (int l = 0; l < n; ++l) {
        EXPECT_NEAR(hann[l], 0.5 * (1 + std::cos(kPi * l / n)), kFormulaTol);
        const double t = kPi * l / n;
        EXPECT_NEAR(lanczos[l], l == 0 ? 1.0 : std::sin(t) / t, kFormulaTol);
    }
    EXPECT_GT(hann[n - 1], 0.0);  // with the default width the last band survives
    // An explicit width h = 4 zeroes bands l ≥ 4.
    const auto hann4 = window_weights(WindowKind::hann, n, 4.0);
    EXPECT_NEAR(hann4[2], 0.5, kFormulaTol);
    for (int l = 4; l < n; ++l) EXPECT_EQ(hann4[l], 0.0);
    const auto lanczos4 = window_weights(WindowKind::lanczos, n, 4.0);
    EXPECT_NEAR(lanczos4[2], std::sin(kPi / 2) / (kPi / 2), kFormulaTol);
    for (int l = 4; l < n; ++l) EXPECT_EQ(lanczos4[l], 0.0);
    // Sloan: 1/(1 + λ l²(l+1)²); λ = 0 leaves the vector alone.
    const auto sloan = window_weights(WindowKind::sloan, n, 0.01);
    for (int l = 0; l < n; ++l)
        EXPECT_NEAR(sloan[l], 1.0 / (1.0 + 0.01 * l * l * (l + 1.0) * (l + 1.0)), kFormulaTol);
    for (double w : window_weights(WindowKind::sloan, n, 0.0)) EXPECT_EQ(w, 1.0);
}

TEST(Window, ApplyScalesEachBandAndNoneIsIdentity) {
    const int K = 30;  // partial last band: n = sh_bands_for(30) = 6
    std::vector<double> c(K), orig(K);
    for (int i = 0; i < K; ++i) orig[i] = c[i] = 0.1 * (i + 1) * (i % 2 ? -1 : 1);
    apply_window(WindowKind::none, c.data(), K);
    EXPECT_EQ(c, orig);
    const auto w = window_weights(WindowKind::hann, sh_bands_for(K));
    apply_window(WindowKind::hann, c.data(), K);
    for (int i = 0; i < K; ++i) EXPECT_DOUBLE_EQ(c[i], orig[i] * w[sh_band(i)]) << i;
    std::vector<float> f(orig.begin(), orig.end());
    apply_window(WindowKind::sloan, f.data(), K, 0.05);
    const auto ws = window_weights(WindowKind::sloan, 6, 0.05);
    for (int i = 0; i < K; ++i) EXPECT_NEAR(f[i], orig[i] * ws[sh_band(i)], 1e-6) << i;
    apply_window(WindowKind::hann, c.data(), 0);  // no-op, no throw
}

TEST(Window, WindowsReduceRingingOfATruncatedClampedCosine) {
    // The 8-band clamped cosine overshoots below zero on the back hemisphere; windows shrink it.
    const int bands = 8, K = sh_count(bands);
    std::vector<double> z = clamped_cosine_zonal(bands), c(K, 0.0), y(K);
    const auto most_negative = [&](const std::vector<double>& coeffs) {
        double lo = 0;
        for (int i = 0; i <= 720; ++i) {
            const double th = kPi * i / 720;
            sh_eval(bands, std::sin(th), 0.0, std::cos(th), y.data());
            double v = 0;
            for (int k = 0; k < K; ++k) v += coeffs[k] * y[k];
            lo = std::min(lo, v);
        }
        return lo;
    };
    for (int l = 0; l < bands; ++l) c[sh_index(l, 0)] = z[l];
    const double raw = most_negative(c);
    EXPECT_LT(raw, -1e-3);  // there is ringing to remove
    for (auto [kind, strength] : {std::pair{WindowKind::hann, 0.0},
                                  {WindowKind::lanczos, 0.0},
                                  {WindowKind::sloan, 1e-3}}) {
        std::vector<double> w = c;
        apply_window(kind, w.data(), K, strength);
        EXPECT_GT(most_negative(w), raw) << to_string(kind);
    }
}

TEST(Window, ParseAndBadInput) {
    for (WindowKind kind : kAll) EXPECT_EQ(parse_window_kind(to_string(kind)), kind);
    EXPECT_THROW(parse_window_kind("hamming"), Error);
    EXPECT_THROW(parse_window_kind(""), Error);
    EXPECT_THROW(window_weights(WindowKind::hann, 0), Error);
    EXPECT_THROW(window_weights(WindowKind::hann, kMaxBands + 1), Error);
    EXPECT_THROW(window_weights(WindowKind::sloan, 4, -0.1), Error);
    EXPECT_THROW(window_weights(WindowKind::lanczos, 4, NAN), Error);
    std::vector<double> c(9, 1.0);
    EXPECT_THROW(apply_window(WindowKind::hann, c.data(), -1), Error);
    EXPECT_THROW(apply_window(WindowKind::sloan, c.data(), 9, -2.0), Error);
}

}  // namespace
}  // namespace shprt
