// Equirect maps: the DESIGN.md orientation, exact pixel solid angles, projection (fast
// separable path against the per-pixel reference, band-limited round trip with second-order
// convergence), the white furnace, and "rotating the light equals projecting the rotated map".
#include "shprt/core/math.hpp"
#include "shprt/light/equirect.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/light/light.hpp"
#include "shprt/sh/basis.hpp"

#include "light/light_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace shprt {
namespace {

using test_support::cosine_weights;
using test_support::expect_near;
using test_support::irradiance;
using test_support::max_abs_diff;

Image map_of(int W, int H, const std::function<Vec3d(Vec3d)>& f) {
    Image image = Image::make(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const Vec3d v = f(equirect_pixel_direction<double>(x, y, W, H));
            for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = static_cast<float>(v[c]);
        }
    return image;
}

TEST(Equirect, OrientationMatchesDesign) {
    expect_near(equirect_direction(0.5, 0.5), {0, 0, -1}, 1e-15);   // centre looks toward −Z
    expect_near(equirect_direction(0.75, 0.5), {1, 0, 0}, 1e-15);   // right of centre: +X
    expect_near(equirect_direction(0.25, 0.5), {-1, 0, 0}, 1e-15);  // left of centre: −X
    expect_near(equirect_direction(0.0, 0.5), {0, 0, 1}, 1e-15);    // both edges: +Z
    expect_near(equirect_direction(1.0, 0.5), {0, 0, 1}, 1e-15);
    expect_near(equirect_direction(0.3, 0.0), {0, 1, 0}, 1e-15);   // row 0: zenith +Y
    expect_near(equirect_direction(0.3, 1.0), {0, -1, 0}, 1e-15);  // bottom row: nadir −Y
    const Vec3f f = equirect_direction(0.75f, 0.5f);               // the float overload
    EXPECT_NEAR(f.x, 1.0f, 1e-6f);
    // The first pixel row's centre is within half a row of the zenith.
    EXPECT_GT(equirect_pixel_direction<double>(0, 0, 64, 32).y, std::cos(kPi / 32));
}

TEST(Equirect, UvInvertsDirection) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int i = 0; i < 1000; ++i) {
        const double u = u01(rng), v = 0.001 + 0.998 * u01(rng);
        double u2 = 0, v2 = 0;
        const Vec3d d = equirect_direction(u, v);
        EXPECT_NEAR(length(d), 1.0, 1e-14);
        equirect_uv(d, u2, v2);
        EXPECT_NEAR(u2, u, 1e-12);
        EXPECT_NEAR(v2, v, 1e-12);
        // The formula of DESIGN.md itself.
        EXPECT_NEAR(u2, 0.5 + std::atan2(d.x, -d.z) / (2 * kPi), 1e-15);
        EXPECT_NEAR(v2, std::acos(d.y) / kPi, 1e-15);
    }
}

TEST(Equirect, PixelSolidAnglesSumTo4Pi) {
    for (auto [W, H] : {std::pair{2, 1}, {16, 8}, {100, 50}, {2048, 1024}, {30, 7}}) {
        double sum = 0.0;
        for (int y = 0; y < H; ++y) sum += W * equirect_pixel_solid_angle(y, W, H);
        EXPECT_NEAR(sum, 4 * kPi, 1e-9) << W << "x" << H;
    }
    // Against the textbook form Δφ·(cos θ0 − cos θ1).
    for (int y = 0; y < 8; ++y)
        EXPECT_NEAR(equirect_pixel_solid_angle(y, 16, 8),
                    (2 * kPi / 16) * (std::cos(kPi * y / 8) - std::cos(kPi * (y + 1) / 8)), 1e-15);
}

TEST(Equirect, FastProjectionMatchesReference) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 5.0f);
    // The last case has fewer rows than bands·π: the per-row rules must still be exact.
    for (auto [K, W] : {std::pair{1, 48}, {4, 48}, {10, 48}, {49, 48}, {64, 48}, {256, 24}}) {
        Image map = Image::make(W, W / 2);
        for (float& v : map.rgb) v = u(rng);
        const ShLight fast = project_equirect(map, K);
        const ShLight ref = project_equirect_reference(map, K);
        ASSERT_EQ(fast.K, K);
        // Both accumulate in double; float output: agree to float rounding of |c| ≲ 2·sqrt(4π)·5.
        EXPECT_LT(max_abs_diff(fast, ref), 1e-5) << "K=" << K;
    }
}

TEST(Equirect, WhiteFurnace) {
    const Image map = map_of(64, 32, [](Vec3d) { return Vec3d{1, 1, 1}; });
    const ShLight light = project_equirect(map, 25);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(light.channel(c)[0], std::sqrt(4 * kPi), 1e-6);
        for (int i = 1; i < 25; ++i) EXPECT_NEAR(light.channel(c)[i], 0.0, 1e-6) << i;
        for (Vec3d n : {Vec3d{0, 1, 0}, Vec3d{1, 0, 0}, Vec3d{0.6, -0.8, 0}})
            EXPECT_NEAR(irradiance(light, c, n), kPi, 1e-5);
    }
}

TEST(Equirect, BrightTowardPlusXLightsPlusX) {
    const Image map = map_of(128, 64, [](Vec3d d) {
        return d.x > 0.9 ? Vec3d{5, 5, 5} : Vec3d{0, 0, 0};
    });
    const ShLight light = project_equirect(map, 16);
    const Vec3d axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const double e_px = irradiance(light, 0, axes[0]);
    EXPECT_GT(e_px, 0.1);
    for (int a = 1; a < 6; ++a) EXPECT_LT(irradiance(light, 0, axes[a]), 0.5 * e_px) << a;
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    for (int i = 0; i < 200; ++i) {
        const Vec3d n = normalize(Vec3d{g(rng), g(rng), g(rng)});
        EXPECT_LE(irradiance(light, 0, n), e_px + 1e-6);
    }
    // The map's pixels: bright at u = 0.75 (centre row), dark at the centre (−Z).
    EXPECT_GT(map.pixel(96, 32)[0], 1.0f);
    EXPECT_EQ(map.pixel(64, 32)[0], 0.0f);
}

// Reprojecting a map sampled from a band-limited function returns its coefficients, to a
// midpoint-rule error that falls with the square of the row height.
TEST(Equirect, BandLimitedRoundTripConverges) {
    const int bands = 6, K = bands * bands;
    std::mt19937 rng(11);
    std::normal_distribution<double> g;
    std::vector<double> c(3 * K);
    for (double& v : c) v = g(rng);
    const auto f = [&](Vec3d d) {
        std::vector<double> y(K);
        sh_eval_k(K, d.x, d.y, d.z, y.data());
        Vec3d out{0, 0, 0};
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < K; ++i) out[ch] += c[ch * K + i] * y[i];
        return out;
    };
    double err[2] = {0, 0};
    const int heights[2] = {64, 128};
    for (int r = 0; r < 2; ++r) {
        const ShLight light = project_equirect(map_of(2 * heights[r], heights[r], f), K);
        for (int i = 0; i < 3 * K; ++i)
            err[r] = std::max(err[r], std::abs(double(light.coeffs[i]) - c[i]));
    }
    // Error model: a map of point samples read as constant pixels blurs band l by about
    // h²·l(l+1)/24 relative (h the pixel size, Δθ here); bound with a ×3 margin. Measured:
    // 6.8e-3 at 128×64 and 1.7e-3 at 256×128, against the bound 2.9e-2.
    double cmax = 0.0;
    for (double v : c) cmax = std::max(cmax, std::abs(v));
    const double dtheta = kPi / heights[0], lmax = bands - 1;
    EXPECT_LT(err[0], 3.0 * dtheta * dtheta * lmax * (lmax + 1) / 24.0 * cmax) << err[0];
    EXPECT_GT(err[0] / err[1], 3.5)
        << err[0] << " " << err[1];  // second order: halving Δθ divides the error by ~4
    EXPECT_LT(err[0] / err[1], 4.5);
}

// Rotating the projected light by R equals projecting the map of f(R⁻¹ d).
TEST(Equirect, RotatingTheLightEqualsProjectingTheRotatedMap) {
    const Vec3d a = normalize(Vec3d{0.3, 0.5, -0.8}), b = normalize(Vec3d{-0.7, 0.1, 0.2});
    const auto f = [&](Vec3d d) {
        return Vec3d{2.0, 1.0, 0.5} * std::exp(6.0 * (dot(d, a) - 1.0)) +
               Vec3d{0.2, 0.6, 1.0} * std::exp(3.0 * (dot(d, b) - 1.0)) + Vec3d{0.1, 0.1, 0.1};
    };
    const Mat3d R = matrix_from_yaw_pitch_roll_deg(70.0, -25.0, 40.0);
    const Mat3d Rt = transpose(R);
    const int K = 25, W = 512, H = 256;
    ShLight rotated = project_equirect(map_of(W, H, f), K);
    rotate_light(rotated, R);
    const ShLight direct = project_equirect(map_of(W, H, [&](Vec3d d) { return f(Rt * d); }), K);
    // Both are projections of the same function on different pixel grids: they differ by the
    // grid's quadrature error, ~ (l Δθ)² relative; the coefficients are O(0.5).
    const double diff = max_abs_diff(rotated, direct);
    EXPECT_LT(diff, 2e-3) << diff;
    // The test is not vacuous: the rotation moves the coefficients far more than that.
    const ShLight unrotated = project_equirect(map_of(W, H, f), K);
    EXPECT_GT(max_abs_diff(unrotated, direct), 0.05);
}

TEST(Equirect, ProjectionRejectsBadInput) {
    EXPECT_THROW(project_equirect(Image{}, 9), Error);
    EXPECT_THROW(project_equirect(Image::make(4, 2), 0), Error);
    EXPECT_THROW(project_equirect(Image::make(4, 2), kMaxLightK + 1), Error);
    Image bad = Image::make(4, 2);
    bad.rgb.resize(5);
    EXPECT_THROW(project_equirect(bad, 9), Error);
    EXPECT_THROW(project_equirect_reference(bad, 9), Error);
}

}  // namespace
}  // namespace shprt
