// Zonal harmonics: clamped cosine and Phong lobe against exact quadrature and known values; the
// O(K) zonal rotation against the general rotation; Funk–Hecke convolution against a direct
// hemisphere integral; bad input.
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/sh/zonal.hpp"

#include "common/gauss_legendre.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace shprt {
namespace {

using test_support::gauss_legendre;

constexpr double kQuadTol = 1e-12;   // closed form vs exact quadrature (double rounding)
constexpr double kTightTol = 1e-12;  // identities that hold to rounding
constexpr double kFloatTol = 2e-5;   // float evaluation

// z_l = 2π ∫₀¹ h(μ) y_l0(μ) dμ for a zonal h(μ), μ = cos θ, with Gauss–Legendre on [0, 1]
// (exact when h is a polynomial in μ on [0, 1], as max(0, μ)^s for integer s is).
std::vector<double> zonal_by_quadrature(int bands, double (*h)(double, double), double s) {
    std::vector<double> gx, gw, y(sh_count(bands));
    gauss_legendre(bands + 40, gx, gw);
    std::vector<double> z(bands, 0.0);
    for (std::size_t i = 0; i < gx.size(); ++i) {
        const double mu = 0.5 * (gx[i] + 1), w = 0.5 * gw[i];
        sh_eval(bands, std::sqrt(1 - mu * mu), 0.0, mu, y.data());
        for (int l = 0; l < bands; ++l) z[l] += 2 * kPi * w * h(mu, s) * y[sh_index(l, 0)];
    }
    return z;
}

double clamped_cosine(double mu, double) { return mu; }
double phong(double mu, double s) { return (s + 1) / (2 * kPi) * std::pow(mu, s); }

TEST(Zonal, ClampedCosineKnownValues) {
    const std::vector<double> z = clamped_cosine_zonal(12);
    EXPECT_NEAR(z[0], std::sqrt(kPi) / 2, 1e-15);
    EXPECT_NEAR(z[1], std::sqrt(kPi / 3), 1e-15);
    EXPECT_NEAR(z[2], std::sqrt(5 * kPi) / 8, 1e-15);
    for (int l = 3; l < 12; l += 2) EXPECT_EQ(z[l], 0.0) << l;
    // The irradiance factors Â_l = sqrt(4π/(2l+1)) z_l of Ramamoorthi & Hanrahan.
    const double a[5] = {kPi, 2 * kPi / 3, kPi / 4, 0, -kPi / 24};
    for (int l = 0; l < 5; ++l) EXPECT_NEAR(std::sqrt(4 * kPi / (2 * l + 1)) * z[l], a[l], 1e-14);
}

TEST(Zonal, ClampedCosineMatchesQuadrature) {
    const int bands = 40;
    const std::vector<double> z = clamped_cosine_zonal(bands);
    const std::vector<double> q = zonal_by_quadrature(bands, clamped_cosine, 1);
    for (int l = 0; l < bands; ++l) EXPECT_NEAR(z[l], q[l], kQuadTol) << "l=" << l;
}

TEST(Zonal, PhongLobeIntegratesToOneAndMatchesQuadrature) {
    for (double s : {0.0, 1.0, 2.0, 7.0, 32.0}) {
        const int bands = 24;
        const std::vector<double> z = phong_lobe_zonal(bands, s);
        EXPECT_NEAR(std::sqrt(4 * kPi) * z[0], 1.0, 1e-14) << "s=" << s;  // ∫ lobe dω = 1
        const std::vector<double> q = zonal_by_quadrature(bands, phong, s);
        for (int l = 0; l < bands; ++l)
            EXPECT_NEAR(z[l], q[l], kQuadTol) << "s=" << s << " l=" << l;
    }
    // s = 1 is the clamped cosine divided by π.
    const std::vector<double> p = phong_lobe_zonal(10, 1.0), c = clamped_cosine_zonal(10);
    for (int l = 0; l < 10; ++l) EXPECT_NEAR(p[l], c[l] / kPi, 1e-15);
    // A non-integer exponent still integrates to one.
    EXPECT_NEAR(std::sqrt(4 * kPi) * phong_lobe_zonal(3, 12.5)[0], 1.0, 1e-14);
}

TEST(Zonal, FastRotationEqualsGeneralRotation) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> n(0, 1);
    const int bands = 12, K = sh_count(bands);
    const std::vector<double> z = phong_lobe_zonal(bands, 9.0);
    std::vector<double> full(K), general(K), fast(K);
    zonal_to_coeffs(z.data(), bands, full.data(), K);
    for (int t = 0; t < 20; ++t) {
        const Vec3d d = normalize(Vec3d{n(rng), n(rng), n(rng)});
        // Any rotation with R ẑ = d: an arbitrary spin about the pole first must not matter.
        const Mat3d R = rotation_z_to(d) * rotation_z(n(rng));
        ShRotation::from_matrix(R, bands).apply(full.data(), general.data(), K);
        rotate_zonal(z.data(), K, d, fast.data());
        for (int i = 0; i < K; ++i) EXPECT_NEAR(fast[i], general[i], kTightTol) << i;
        // Float path (the one CUDA kernels use).
        std::vector<float> zf(z.begin(), z.end()), out(K);
        rotate_zonal(zf.data(), K, cast<float>(d), out.data());
        for (int i = 0; i < K; ++i) EXPECT_NEAR(out[i], general[i], kFloatTol) << i;
        // Partial basis sizes write exactly K values, equal to the full ones.
        std::vector<double> part(30 + 1, -7.0);
        rotate_zonal(z.data(), 30, d, part.data());
        for (int i = 0; i < 30; ++i) EXPECT_NEAR(part[i], general[i], kTightTol);
        EXPECT_EQ(part[30], -7.0);
    }
    // The rotated lobe peaks at d: evaluating there gives the lobe's value on its axis.
    const Vec3d d = normalize(Vec3d{1, 2, -0.5});
    rotate_zonal(z.data(), K, d, fast.data());
    std::vector<double> y(K);
    sh_eval(bands, d.x, d.y, d.z, y.data());
    double at_d = 0, at_pole = 0;
    for (int i = 0; i < K; ++i) at_d += fast[i] * y[i];
    sh_eval(bands, 0.0, 0.0, 1.0, y.data());
    for (int i = 0; i < K; ++i) at_pole += full[i] * y[i];
    EXPECT_NEAR(at_d, at_pole, kTightTol);
}

TEST(Zonal, ConvolutionIsFunkHecke) {
    // ∫ y_lm(ω) max(0, d·ω) dω = Â_l y_lm(d), checked by an exact hemisphere quadrature around d:
    // ω = μ d + √(1−μ²)(cos p u + sin p v), μ ∈ [0, 1] Gauss–Legendre, p uniform.
    const int bands = 8, K = sh_count(bands);
    const std::vector<double> z = clamped_cosine_zonal(bands);
    const Vec3d d = normalize(Vec3d{0.3, -0.8, 0.5});
    const Vec3d u = normalize(cross(d, Vec3d{1, 0, 0})), v = cross(d, u);
    std::vector<double> gx, gw, y(K), integral(K, 0.0);
    gauss_legendre(bands + 2, gx, gw);
    const int n_p = 2 * bands + 2;
    for (std::size_t i = 0; i < gx.size(); ++i) {
        const double mu = 0.5 * (gx[i] + 1), w = 0.5 * gw[i], st = std::sqrt(1 - mu * mu);
        for (int j = 0; j < n_p; ++j) {
            const double p = 2 * kPi * j / n_p;
            const Vec3d om = d * mu + u * (st * std::cos(p)) + v * (st * std::sin(p));
            sh_eval(bands, om.x, om.y, om.z, y.data());
            for (int k = 0; k < K; ++k) integral[k] += w * (2 * kPi / n_p) * mu * y[k];
        }
    }
    std::vector<double> yd(K);
    sh_eval(bands, d.x, d.y, d.z, yd.data());
    std::vector<double> conv = yd;  // convolving the vector (y_i(d))_i gives (Â_l y_i(d))_i
    convolve_zonal(z.data(), bands, conv.data(), K);
    for (int k = 0; k < K; ++k) EXPECT_NEAR(conv[k], integral[k], kQuadTol) << k;

    // White furnace: constant radiance 1 (c_00 = √(4π)) gives irradiance π everywhere.
    std::vector<double> white(K, 0.0);
    white[0] = std::sqrt(4 * kPi);
    convolve_zonal(z.data(), bands, white.data(), K);
    EXPECT_NEAR(white[0] * yd[0], kPi, 1e-14);
    // Float overload.
    std::vector<float> f(yd.begin(), yd.end());
    convolve_zonal(z.data(), bands, f.data(), K);
    for (int k = 0; k < K; ++k) EXPECT_NEAR(f[k], conv[k], kFloatTol);
}

TEST(Zonal, BadInputThrows) {
    EXPECT_THROW(clamped_cosine_zonal(0), Error);
    EXPECT_THROW(clamped_cosine_zonal(kMaxBands + 1), Error);
    EXPECT_THROW(phong_lobe_zonal(4, -1.0), Error);
    EXPECT_THROW(phong_lobe_zonal(4, NAN), Error);
    EXPECT_THROW(phong_lobe_zonal(4, INFINITY), Error);
    const std::vector<double> z = clamped_cosine_zonal(3);
    std::vector<double> c(16, 1.0);
    EXPECT_THROW(convolve_zonal(z.data(), 3, c.data(), 10), Error);  // needs 4 bands
    EXPECT_THROW(convolve_zonal(z.data(), 3, c.data(), -1), Error);
    EXPECT_NO_THROW(convolve_zonal(z.data(), 3, c.data(), 9));
    EXPECT_THROW(zonal_to_coeffs(z.data(), 3, c.data(), 16), Error);
}

}  // namespace
}  // namespace shprt
