// Helpers shared by the light tests: an independent clamped-cosine convolution (irradiance from a
// light vector) and comparisons of light vectors.
#pragma once

#include "shprt/core/math.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"
#include "shprt/sh/basis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace shprt::test_support {

// Â_l of the clamped cosine (Ramamoorthi & Hanrahan 2001): π, 2π/3, then the even-l recurrence;
// zero for odd l > 1.
inline std::vector<double> cosine_weights(int bands) {
    std::vector<double> A(bands, 0.0);
    A[0] = kPi;
    if (bands > 1) A[1] = 2.0 * kPi / 3.0;
    double a = 1.0 / 8.0;
    for (int l = 2; l < bands; l += 2) {
        A[l] = 2.0 * kPi * a;
        a *= -(l - 1.0) / (l + 4.0);
    }
    return A;
}

// Irradiance of channel c for surface normal n: E = Σ Â_l L_lm y_lm(n).
inline double irradiance(const ShLight& light, int c, Vec3d n) {
    const std::vector<double> A = cosine_weights(sh_bands_for(light.K));
    std::vector<double> y(light.K);
    sh_eval_k(light.K, n.x, n.y, n.z, y.data());
    double e = 0.0;
    for (int i = 0; i < light.K; ++i) e += A[sh_band(i)] * light.channel(c)[i] * y[i];
    return e;
}

inline double max_abs_diff(const ShLight& a, const ShLight& b) {
    double m = 0.0;
    for (std::size_t i = 0; i < a.coeffs.size(); ++i)
        m = std::max(m, std::abs(double(a.coeffs[i]) - double(b.coeffs[i])));
    return m;
}

inline void expect_near(Vec3d a, Vec3d b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

}  // namespace shprt::test_support
