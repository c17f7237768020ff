// Light rotation by drag: the drag matrix, its composition with --rotate, and that the rig's
// light is the SH rotation of the source (equal to prepare_light when there is no drag).
#include "light_rig.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace shprt::viewer {
namespace {

constexpr double kMatTol = 1e-12;   // products of a few rotation matrices in double
constexpr double kLightTol = 2e-5;  // relative to the largest coefficient: float SH rotation

void expect_mat_near(const Mat3d& a, const Mat3d& b, double tol) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << i << "," << j;
}

double max_abs(const ShLight& l) {
    double m = 0;
    for (float c : l.coeffs) m = std::max(m, double(std::abs(c)));
    return m;
}

void expect_light_near(const ShLight& a, const ShLight& b) {
    ASSERT_EQ(a.K, b.K);
    ASSERT_EQ(a.coeffs.size(), b.coeffs.size());
    const double tol = kLightTol * std::max(max_abs(a), 1e-30);
    for (std::size_t i = 0; i < a.coeffs.size(); ++i)
        ASSERT_NEAR(a.coeffs[i], b.coeffs[i], tol) << "coefficient " << i;
}

// prepare_light's steps by hand, with an arbitrary rotation: full bands, window, rotate, truncate.
ShLight reference_light(LightSetup setup, const Mat3d& R, int K) {
    setup.yaw_pitch_roll_deg = {0, 0, 0};
    ShLight full = prepare_light(setup, sh_count(sh_bands_for(K)));
    rotate_light(full, R);
    ShLight out = ShLight::zero(K);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < K; ++i) out.channel(c)[i] = full.channel(c)[i];
    return out;
}

TEST(LightDrag, HorizontalIsAYawVerticalIsAPitchAboutRight) {
    const Vec3d right = normalize(Vec3d{1, 0, 1});
    expect_mat_near(light_drag_rotation(30, 0, right), rotation_y(30 * kLightRadiansPerPixel),
                    kMatTol);
    const Mat3d pitch = matrix_from_quat(quat_from_axis_angle(right, -20 * kLightRadiansPerPixel));
    expect_mat_near(light_drag_rotation(0, -20, right), pitch, kMatTol);
    // Both: pitch after yaw.
    expect_mat_near(light_drag_rotation(30, -20, right * 3.0),
                    pitch * rotation_y(30 * kLightRadiansPerPixel), kMatTol);
    EXPECT_TRUE(is_rotation(light_drag_rotation(123, -45, {0.3, 0.1, -2})));
    // The pitch axis is a fixed point of a vertical drag.
    const Vec3d moved = light_drag_rotation(0, 77, right) * right;
    EXPECT_NEAR(length(moved - right), 0.0, 1e-12);
}

TEST(LightRig, WithoutDragItIsPrepareLight) {
    for (int K : {16, 20}) {  // a full band and a partial one
        LightSetup setup;
        setup.specs = {"builtin"};
        setup.window = WindowKind::hann;
        setup.yaw_pitch_roll_deg = {40, -15, 5};
        LightRig rig(K);
        EXPECT_FALSE(rig.has_source());
        rig.set_source(setup);
        EXPECT_TRUE(rig.has_source());
        expect_mat_near(rig.rotation(), matrix_from_yaw_pitch_roll_deg(40, -15, 5), kMatTol);
        const ShLight want = prepare_light(setup, K);
        const ShLight got = rig.light();
        ASSERT_EQ(got.K, K);
        // The same operations in the same order: the same floats.
        EXPECT_EQ(got.coeffs, want.coeffs) << "K=" << K;
    }
}

TEST(LightRig, DragsPreMultiplyTheBaseRotation) {
    LightSetup setup;
    setup.specs = {"sun:1,1,0.5,8"};
    setup.yaw_pitch_roll_deg = {25, 10, 0};
    const int K = 25;
    LightRig rig(K);
    rig.set_source(setup);
    const Vec3d right1{1, 0, 0}, right2 = normalize(Vec3d{0.6, 0, -0.8});
    rig.drag(40, 10, right1);
    rig.drag(-15, 30, right2);
    const Mat3d B = matrix_from_yaw_pitch_roll_deg(25, 10, 0);
    const Mat3d want =
        light_drag_rotation(-15, 30, right2) * light_drag_rotation(40, 10, right1) * B;
    expect_mat_near(rig.rotation(), want, 1e-12);
    EXPECT_TRUE(is_rotation(rig.rotation(), 1e-12));
    // The light is the source rotated once by the composition (SH rotation, not re-projection).
    expect_light_near(rig.light(), reference_light(setup, want, K));
}

TEST(LightRig, OppositeDragsCancelAndManyDragsStayARotation) {
    LightSetup setup;
    setup.specs = {"builtin"};
    LightRig rig(16);
    rig.set_source(setup);
    const ShLight original = rig.light();
    rig.drag(50, 0, {1, 0, 0});
    rig.drag(-50, 0, {1, 0, 0});
    expect_mat_near(rig.drag_rotation(), Mat3d::identity(), 1e-12);
    expect_light_near(rig.light(), original);
    for (int i = 0; i < 5000; ++i) rig.drag(1.3, -0.7, {std::cos(i * 0.01), 0, std::sin(i * 0.01)});
    EXPECT_TRUE(is_rotation(rig.drag_rotation(), 1e-12)) << "no drift after 5000 drags";
    rig.reset_drag();
    expect_mat_near(rig.rotation(), Mat3d::identity(), 0);
    EXPECT_EQ(rig.light().coeffs, original.coeffs);
}

TEST(LightRig, AHorizontalDragTurnsTheSunAboutTheVertical) {
    // Band 1 of a zonal lobe about s is z_1·sqrt(4π/3)·(y_{1,-1}, y_{1,0}, y_{1,1})(s), and those
    // three are ±sqrt(3/4π)·(y, z, x) (signs from the Condon–Shortley phase, read off the basis):
    // the sun's direction comes back from coefficients 1..3.
    auto sign_at = [](int i, Vec3d d) {
        double y[4];
        sh_eval_k(4, d.x, d.y, d.z, y);
        return y[i] > 0 ? 1.0 : -1.0;
    };
    const double sx = sign_at(3, {1, 0, 0}), sy = sign_at(1, {0, 1, 0}), sz = sign_at(2, {0, 0, 1});
    auto sun_direction = [&](const ShLight& l) {
        const float* c = l.channel(0);
        return normalize(Vec3d{sx * c[3], sy * c[1], sz * c[2]});
    };
    const Vec3d s = normalize(Vec3d{1, 1, 0.5});
    LightSetup setup;
    setup.specs = {"sun:1,1,0.5,5"};
    LightRig rig(16);
    rig.set_source(setup);
    EXPECT_NEAR(length(sun_direction(rig.light()) - s), 0.0, 1e-5);
    rig.drag(60, 0, {0, 0, 1});
    const Vec3d turned = sun_direction(rig.light());
    EXPECT_NEAR(turned.y, s.y, 1e-5) << "same elevation";
    EXPECT_NEAR(length(turned - rotation_y(60 * kLightRadiansPerPixel) * s), 0.0, 1e-5);
}

TEST(LightRig, ABadSourceThrowsAndKeepsTheOldOne) {
    LightRig rig(9);
    LightSetup good;
    good.specs = {"constant:2"};
    rig.set_source(good);
    const ShLight before = rig.light();
    LightSetup bad;
    bad.specs = {"/nonexistent/sky.hdr"};
    EXPECT_THROW(rig.set_source(bad), Error);
    LightSetup typo;
    typo.specs = {"sunn:1,2,3"};
    EXPECT_THROW(rig.set_source(typo), Error);
    EXPECT_EQ(rig.light().coeffs, before.coeffs);
    EXPECT_EQ(rig.setup().specs, good.specs);
    EXPECT_THROW(LightRig(0), Error);
    EXPECT_THROW(LightRig(kMaxLightK + 1), Error);
    EXPECT_THROW(LightRig(4).light(), Error) << "no source yet";
}

}  // namespace
}  // namespace shprt::viewer
