// The viewer's camera control, as math: orbit keeps the target and the distance, fly keeps the
// eye and moves along the view direction, switching mode keeps the view, pitch stays clamped.
#include "camera_controller.hpp"

#include "shprt/core/math.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace shprt::viewer {
namespace {

constexpr float kTol = 1e-5f;  // relative, float rounding of a few trig calls

const Bounds kBounds{{-2, 0, -2}, {2, 3, 2}};

Camera start_camera() {
    Camera c;
    c.eye = {3, 2, 4};
    c.target = {0, 0.5f, 0};
    c.fov_y_deg = 50;
    return c;
}

void expect_near(Vec3f a, Vec3f b, float tol, const char* what) {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

TEST(CameraController, StartsAtTheGivenView) {
    const Camera start = start_camera();
    const CameraController c(start, kBounds);
    const float d = length(start.target - start.eye);
    EXPECT_NEAR(c.distance(), d, kTol * d);
    expect_near(c.eye(), start.eye, kTol * d, "eye");
    expect_near(c.target(), start.target, kTol * d, "target");
    const Camera cam = c.camera();
    EXPECT_EQ(cam.up, (Vec3f{0, 1, 0}));
    EXPECT_EQ(cam.fov_y_deg, 50.0f);
    EXPECT_GT(cam.near_plane, 0.0f);
    EXPECT_GT(cam.far_plane, cam.near_plane);
    // The axes are orthonormal and right-handed: right × up = −forward (OpenGL's eye space).
    expect_near(cross(c.right(), c.up()), -c.forward(), kTol, "right × up");
    EXPECT_NEAR(length(c.forward()), 1.0f, kTol);
}

TEST(CameraController, OrbitKeepsTheTargetAndTheDistance) {
    const Camera start = start_camera();
    CameraController c(start, kBounds);
    const float d = c.distance();
    const Vec3f target = c.target();
    const float drags[][2] = {{40, 0}, {0, -25}, {-130, 60}, {7, 3}, {500, -400}};
    for (const auto& drag : drags) {
        c.rotate(drag[0], drag[1]);
        EXPECT_NEAR(length(c.target() - c.eye()), d, kTol * d);
        expect_near(c.target(), target, kTol * d, "target after orbit");
    }
    // The eye did move.
    EXPECT_GT(length(c.eye() - start.eye), 0.1f);
}

TEST(CameraController, OrbitDirectionFollowsTheMouse) {
    CameraController c(start_camera(), kBounds);
    const Vec3f right = c.right(), eye = c.eye();
    const float yaw = c.yaw(), pitch = c.pitch();
    c.rotate(10, 0);  // drag right: yaw grows, the eye goes left around the target
    EXPECT_NEAR(c.yaw() - yaw, 10 * kCameraRadiansPerPixel, 1e-6f);
    EXPECT_LT(dot(c.eye() - eye, right), 0.0f);
    c.rotate(0, 10);  // drag down: the view tilts down, the eye goes up
    EXPECT_NEAR(c.pitch() - pitch, -10 * kCameraRadiansPerPixel, 1e-6f);
}

TEST(CameraController, FlyTurnsInPlaceAndMovesAlongTheViewDirection) {
    CameraController c(start_camera(), kBounds);
    c.set_mode(CameraMode::fly);
    const Vec3f eye = c.eye();
    c.rotate(80, -30);
    expect_near(c.eye(), eye, 0.0f, "fly rotation keeps the eye");

    const Vec3f f = c.forward();
    const Vec3f before = c.eye(), target_before = c.target();
    c.move({0, 0, 1}, 0.5f);
    const Vec3f delta = c.eye() - before;
    const float want = c.speed() * 0.5f;
    EXPECT_NEAR(length(delta), want, kTol * want);
    EXPECT_NEAR(dot(delta, f), want, kTol * want) << "moved along the view direction";
    expect_near(c.target() - target_before, delta, kTol * want, "target moves with the eye");

    // Strafing moves along right only.
    const Vec3f r = c.right(), at = c.eye();
    c.move({-1, 0, 0}, 1.0f);
    EXPECT_NEAR(dot(c.eye() - at, r), -c.speed(), kTol * c.speed());
    EXPECT_NEAR(dot(c.eye() - at, f), 0.0f, kTol * c.speed());

    // The wheel moves forward in fly mode.
    const Vec3f w0 = c.eye();
    c.zoom(2);
    const Vec3f dw = c.eye() - w0;
    EXPECT_GT(dot(dw, c.forward()), 0.0f);
    EXPECT_NEAR(length(cross(dw, c.forward())), 0.0f, 1e-4f);
}

TEST(CameraController, ZoomScalesTheOrbitDistanceOnly) {
    CameraController c(start_camera(), kBounds);
    const Vec3f target = c.target();
    const float d = c.distance();
    c.zoom(3);
    EXPECT_NEAR(c.distance(), d * std::pow(0.85f, 3.0f), kTol * d);
    expect_near(c.target(), target, kTol * d, "zoom keeps the target");
    // Clamped: never through the target, never beyond 10 diagonals.
    c.zoom(1000);
    EXPECT_GT(c.distance(), 0.0f);
    c.zoom(-1000);
    EXPECT_LE(c.distance(), 10.0f * length(kBounds.hi - kBounds.lo) * (1 + kTol));
}

TEST(CameraController, PanMovesEyeAndTargetTogetherInTheViewPlane) {
    CameraController c(start_camera(), kBounds);
    const Vec3f eye = c.eye(), target = c.target(), f = c.forward();
    c.pan(30, -12, 720);
    const Vec3f de = c.eye() - eye, dt = c.target() - target;
    expect_near(de, dt, 1e-5f, "eye and target move together");
    EXPECT_NEAR(dot(de, f), 0.0f, 1e-5f) << "in the view plane";
    // The scene follows the cursor: the camera moves left for a drag to the right. At the
    // target's distance one pixel is 2·d·tan(fov/2)/height world units.
    const float per_pixel = 2 * c.distance() * std::tan(50.0f * kPiF / 360.0f) / 720.0f;
    EXPECT_NEAR(dot(de, c.right()), -30 * per_pixel, 1e-5f);
    EXPECT_NEAR(dot(de, c.up()), -12 * per_pixel, 1e-5f);
}

TEST(CameraController, SwitchingModeKeepsTheView) {
    CameraController c(start_camera(), kBounds);
    c.rotate(33, 12);
    const Vec3f eye = c.eye(), target = c.target();
    c.set_mode(CameraMode::fly);
    expect_near(c.eye(), eye, 0.0f, "eye");
    expect_near(c.target(), target, 0.0f, "target");
    c.set_mode(CameraMode::orbit);
    expect_near(c.eye(), eye, 0.0f, "eye");
}

TEST(CameraController, PitchIsClampedSoUpNeverAlignsWithTheView) {
    CameraController c(start_camera(), kBounds);
    c.rotate(0, -100000);  // far past straight up
    EXPECT_NEAR(c.pitch(), kMaxPitchDeg * kPiF / 180.0f, 1e-6f);
    c.rotate(0, 100000);
    EXPECT_NEAR(c.pitch(), -kMaxPitchDeg * kPiF / 180.0f, 1e-6f);
    // A start looking straight down is tilted to the clamp, not rejected.
    Camera down;
    down.eye = {0, 5, 0};
    down.target = {0, 0, 0};
    const CameraController d(down, kBounds);
    EXPECT_NEAR(d.pitch(), -kMaxPitchDeg * kPiF / 180.0f, 1e-6f);
    EXPECT_GT(length(cross(d.forward(), Vec3f{0, 1, 0})), 0.01f);
}

TEST(CameraController, AFullOrbitReturnsToTheStart) {
    CameraController c(start_camera(), kBounds);
    const Vec3f eye = c.eye();
    for (int i = 0; i < 100; ++i) c.orbit_by(2 * kPiF / 100);
    expect_near(c.eye(), eye, 1e-4f, "after 2π");
}

}  // namespace
}  // namespace shprt::viewer
