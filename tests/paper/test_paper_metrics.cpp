// The paper-table metrics (bench/paper/paper_metrics.hpp) on synthetic inputs with known answers.
#include "paper/paper_metrics.hpp"

#include "shprt/core/error.hpp"
#include "shprt/shade/shade.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace shprt::paper {
namespace {

constexpr double kTight = 1e-12;

TEST(PaperMetrics, LuminanceWeights) {
    EXPECT_NEAR(luminance(Vec3d{1, 1, 1}), 1.0, kTight);
    EXPECT_NEAR(luminance(Vec3d{1, 0, 0}), 0.2126, kTight);
    EXPECT_NEAR(luminance(Vec3d{0, 1, 0}), 0.7152, kTight);
    const std::vector<Vec3f> f = {{0, 0, 1}, {2, 2, 2}};
    const std::vector<double> y = luminance(std::span<const Vec3f>(f));
    EXPECT_NEAR(y[0], 0.0722, 1e-7);
    EXPECT_NEAR(y[1], 2.0, 1e-6);
}

TEST(PaperMetrics, RmseOfAConstantOffset) {
    // Ŝ = S + 0.25 everywhere: RMSE = max = bias = 0.25.
    std::vector<double> ref, est;
    for (int i = 0; i < 100; ++i) {
        ref.push_back(1.0 + 0.01 * i);
        est.push_back(ref.back() + 0.25);
    }
    const VertexError e = vertex_error(est, ref);
    EXPECT_EQ(e.count, 100u);
    EXPECT_NEAR(e.rmse, 0.25, kTight);
    EXPECT_NEAR(e.max_abs, 0.25, kTight);
    EXPECT_NEAR(e.bias, 0.25, kTight);
    EXPECT_NEAR(e.mean_reference, 1.495, kTight);
    EXPECT_NEAR(e.relative_rmse(), 0.25 / 1.495, kTight);
}

TEST(PaperMetrics, RmseOfAlternatingErrorsAndMask) {
    // Errors +1, −1, +3 (masked out), ...: RMSE over the selected = 1, bias 0, max 1.
    const std::vector<double> ref = {0, 0, 0, 0, 0, 0};
    const std::vector<double> est = {1, -1, 3, 1, -1, 3};
    const std::vector<std::uint8_t> mask = {1, 1, 0, 1, 1, 0};
    const VertexError e = vertex_error(est, ref, mask);
    EXPECT_EQ(e.count, 4u);
    EXPECT_NEAR(e.rmse, 1.0, kTight);
    EXPECT_NEAR(e.bias, 0.0, kTight);
    EXPECT_NEAR(e.max_abs, 1.0, kTight);
    const VertexError all = vertex_error(est, ref);
    EXPECT_NEAR(all.rmse, std::sqrt((1 + 1 + 9 + 1 + 1 + 9) / 6.0), kTight);
    EXPECT_NEAR(all.max_abs, 3.0, kTight);
}

TEST(PaperMetrics, NegativeFractionAndMostNegative) {
    const std::vector<double> ref = {1, 1, 1, 1, 2, 2, 2, 2};  // mean 1.5, max 2
    const std::vector<double> est = {-0.3, 0.5, -0.6, 1, 2, 2.5, 2, 3};
    const VertexRinging r = vertex_ringing(est, ref);
    EXPECT_EQ(r.count, 8u);
    EXPECT_NEAR(r.negative_fraction, 2.0 / 8.0, kTight);
    EXPECT_NEAR(r.most_negative, -0.6, kTight);
    EXPECT_NEAR(r.most_negative_relative, -0.6 / 1.5, kTight);
    EXPECT_NEAR(r.overshoot_fraction, 2.0 / 8.0, kTight);  // 2.5 and 3 exceed max S = 2
    // Nothing negative: most_negative is 0, not the smallest value.
    const VertexRinging none = vertex_ringing(ref, ref);
    EXPECT_EQ(none.negative_fraction, 0.0);
    EXPECT_EQ(none.most_negative, 0.0);
    EXPECT_EQ(none.overshoot_fraction, 0.0);
}

TEST(PaperMetrics, ShadowContrastOfAHalfFilledShadow) {
    // Reference: lit 10, shadow 2 (contrast 8). Estimate: lit 9, shadow 5 (contrast 4):
    // saturation 0.5; shadow errors +3 everywhere → fill error 3/8 of the true contrast.
    const std::vector<double> ref = {10, 10, 2, 2, 7};
    const std::vector<double> est = {9, 9, 5, 5, 0};
    const std::vector<std::uint8_t> lit = {1, 1, 0, 0, 0}, shadow = {0, 0, 1, 1, 0};
    const ShadowContrast c = shadow_contrast(est, ref, lit, shadow);
    EXPECT_EQ(c.lit_count, 2u);
    EXPECT_EQ(c.shadow_count, 2u);
    EXPECT_NEAR(c.saturation, 0.5, kTight);
    EXPECT_NEAR(c.shadow_fill_error, 3.0 / 8.0, kTight);
    EXPECT_NEAR(c.reference_lit, 10, kTight);
    EXPECT_NEAR(c.estimate_shadow, 5, kTight);
    // Perfect estimate: saturation 1, no fill error.
    const ShadowContrast p = shadow_contrast(ref, ref, lit, shadow);
    EXPECT_NEAR(p.saturation, 1.0, kTight);
    EXPECT_NEAR(p.shadow_fill_error, 0.0, kTight);
    // No contrast in the reference: an error, not a division by zero.
    EXPECT_THROW(shadow_contrast(est, ref, shadow, lit), Error);
    const std::vector<std::uint8_t> none(5, 0);
    EXPECT_THROW(shadow_contrast(est, ref, none, shadow), Error);
}

Profile ramp_profile(int n, double x0, double x1, double high, double low) {
    Profile p;
    for (int i = 0; i < n; ++i) {
        const double x = double(i) / (n - 1);
        const double t = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0);
        p.position.push_back(x);
        p.value.push_back(high + (low - high) * t);
    }
    return p;
}

TEST(PaperMetrics, EdgeWidthOfALinearRamp) {
    // A ramp from 5 to 1 over [0.4, 0.6]: 90 % at 0.42, 10 % at 0.58, width 0.16 (to the
    // interpolation of a 1001-sample profile, exact for a piecewise-linear ramp).
    constexpr double kTolerance = 1e-9;
    const EdgeMeasure e = measure_edge(ramp_profile(1001, 0.4, 0.6, 5, 1));
    ASSERT_TRUE(e.valid);
    EXPECT_NEAR(e.high, 5, kTolerance);
    EXPECT_NEAR(e.low, 1, kTolerance);
    EXPECT_NEAR(e.x90, 0.42, kTolerance);
    EXPECT_NEAR(e.x10, 0.58, kTolerance);
    EXPECT_NEAR(e.width, 0.16, kTolerance);
    EXPECT_EQ(e.overshoot, 0.0);
    EXPECT_EQ(e.undershoot, 0.0);
}

TEST(PaperMetrics, EdgeWidthOfAStepIsOneSampleOrLess) {
    Profile p = ramp_profile(101, 0.5, 0.5000001, 1, 0);
    const EdgeMeasure e = measure_edge(p);
    ASSERT_TRUE(e.valid);
    EXPECT_LE(e.width, 0.01 + 1e-12);
    EXPECT_GE(e.width, 0.0);
}

TEST(PaperMetrics, RingingWidensTheEdgeAndShowsAsOvershoot) {
    // The ramp plus a bump of +0.6·range just before it and a dip of −0.3·range after it.
    Profile p = ramp_profile(1001, 0.4, 0.6, 1, 0);
    for (std::size_t i = 0; i < p.value.size(); ++i) {
        const double x = p.position[i];
        if (x > 0.32 && x < 0.36) p.value[i] += 0.6;
        if (x > 0.66 && x < 0.70) p.value[i] -= 0.3;
    }
    const EdgeMeasure e = measure_edge(p);
    ASSERT_TRUE(e.valid);
    EXPECT_NEAR(e.overshoot, 0.6, 1e-9);
    EXPECT_NEAR(e.undershoot, 0.3, 1e-9);
    EXPECT_NEAR(e.x90, 0.42, 1e-9);           // the bump stays above 0.9: x90 unchanged
    EXPECT_NEAR(e.width, 0.58 - 0.42, 1e-9);  // the dip stays below 0.1: x10 unchanged
    // A dip inside the lit side that falls below 90 % moves x90 to it.
    for (std::size_t i = 0; i < p.value.size(); ++i)
        if (p.position[i] > 0.25 && p.position[i] < 0.27) p.value[i] = 0.5;
    const EdgeMeasure w = measure_edge(p);
    EXPECT_NEAR(w.x90, 0.25, 2e-3);
    EXPECT_GT(w.width, 0.3);
}

TEST(PaperMetrics, FlatOrInvertedProfileHasNoEdge) {
    EXPECT_FALSE(measure_edge(ramp_profile(100, 0.4, 0.6, 1, 1)).valid);
    EXPECT_FALSE(measure_edge(ramp_profile(100, 0.4, 0.6, 0, 1)).valid);
    EXPECT_THROW(measure_edge(ramp_profile(3, 0.4, 0.6, 1, 0)), Error);
    EXPECT_THROW(measure_edge(ramp_profile(100, 0.4, 0.6, 1, 0), 0.6), Error);
}

TEST(PaperMetrics, ImageProfileSamplesAlongTheProjectedSegment) {
    // A camera looking straight down at the plane y = 0 from (0, 2, 0); an image whose
    // luminance is its pixel column index. Points along x map to columns linearly, so the
    // profile is linear in position and increasing along +x (camera right = +x with up = −z).
    Camera cam;
    cam.eye = {0, 2, 0};
    cam.target = {0, 0, 0};
    cam.up = {0, 0, -1};
    cam.fov_y_deg = 60;
    const int w = 64, h = 64;
    Image img = Image::make(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) img.pixel(x, y)[c] = float(x);
    const Profile p = image_profile(img, cam, {-0.5f, 0, 0}, {0.5f, 0, 0}, 11);
    ASSERT_EQ(p.value.size(), 11u);
    EXPECT_NEAR(p.position.back(), 1.0, 1e-6);
    // Column of world x: (x / (2·tan30°) · 0.5 + 0.5)·64 (NDC x = x over the half-width
    // 2·tan30° seen at distance 2), value = column − 0.5 (pixel centres).
    for (std::size_t k = 0; k < p.value.size(); ++k) {
        const double x = -0.5 + 0.1 * double(k);
        const double column = (x / (2 * std::tan(30.0 * 3.14159265358979 / 180)) * 0.5 + 0.5) * w;
        EXPECT_NEAR(p.value[k], column - 0.5, 1e-3) << k;
    }
    // Outside the frustum: an error.
    EXPECT_THROW(image_profile(img, cam, {-5, 0, 0}, {0.5f, 0, 0}, 11), Error);
}

TEST(PaperMetrics, IrradianceTransferShowsTheGivenIrradiance) {
    // The K = 1, three-channel transfer under a constant white light of K = 1 shades to E.
    const std::vector<Vec3d> E = {{1, 2, 3}, {0.5, 0, 7}};
    const TransferSet t = irradiance_as_transfer(E);
    EXPECT_EQ(t.layout.K, 1);
    EXPECT_EQ(t.layout.channels, 3);
    EXPECT_EQ(t.receiver_count(), 2u);
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    m.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
    m.albedo = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
    m.triangles = {{0, 2, 1}};
    const std::vector<Vec3d> E3 = {{1, 2, 3}, {0.5, 0, 7}, {4, 4, 4}};
    const ShadeResult r =
        shade_vertices(m, irradiance_as_transfer(E3), constant_light({1, 1, 1}, 1), {});
    for (std::size_t v = 0; v < 3; ++v)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(r.irradiance[v][c], E3[v][c], 1e-5 * E3[v][c] + 1e-7);
}

}  // namespace
}  // namespace shprt::paper
