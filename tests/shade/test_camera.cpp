// Camera matrices and default framing: projection and pixel rays are inverse to each other, the
// target lands at the image centre, default cameras see the scene, parsers reject bad text.
#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/shade/camera.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace shprt {
namespace {

constexpr float kPixelTolerance = 1e-3f;  // pixels, float matrices at 1000-pixel scale

TEST(Camera, TargetProjectsToTheImageCentreAndRaysInvertProjection) {
    Camera cam;
    cam.eye = {3, 2, 5};
    cam.target = {0.5f, 0.2f, -0.3f};
    cam.fov_y_deg = 50;
    cam.near_plane = 0.1f;
    cam.far_plane = 50;
    const int w = 800, h = 500;
    float x, y, depth;
    ASSERT_TRUE(project_to_pixel(cam, w, h, cam.target, x, y, depth));
    EXPECT_NEAR(x, w / 2.0f, kPixelTolerance);
    EXPECT_NEAR(y, h / 2.0f, kPixelTolerance);
    EXPECT_GT(depth, 0.0f);
    EXPECT_LT(depth, 1.0f);
    for (const Vec3f p : {Vec3f{1, 0, 0}, Vec3f{-0.5f, 1.5f, 0.2f}, Vec3f{0.3f, -0.4f, 1}}) {
        ASSERT_TRUE(project_to_pixel(cam, w, h, p, x, y, depth));
        Vec3f o, d;
        pixel_ray(cam, w, h, x, y, o, d);
        // p lies on the ray through its own pixel.
        const Vec3f to_p = p - o;
        const Vec3f off = to_p - d * dot(to_p, d);
        EXPECT_LT(length(off), 1e-4f * length(to_p));
        EXPECT_NEAR(length(d), 1.0f, 1e-6f);
    }
    // Up in the world is up in the image (row 0 at the top), right is right.
    float x_up, y_up, x_right, y_right;
    ASSERT_TRUE(project_to_pixel(cam, w, h, cam.target + Vec3f{0, 0.3f, 0}, x_up, y_up, depth));
    EXPECT_LT(y_up, h / 2.0f);
    const Vec3f right = normalize(cross(cam.target - cam.eye, cam.up));
    ASSERT_TRUE(project_to_pixel(cam, w, h, cam.target + right * 0.3f, x_right, y_right, depth));
    EXPECT_GT(x_right, w / 2.0f);
    // Behind the eye: not projected.
    EXPECT_FALSE(project_to_pixel(cam, w, h, cam.eye + (cam.eye - cam.target), x, y, depth));
}

TEST(Camera, LookAtCameraKeepsUpAndFitsTheClipPlanes) {
    const Bounds bounds{{-1, 0, -2}, {3, 2, 1}};
    const Camera cam = look_at_camera({4, 3, 5}, {0.5f, 1, -0.5f}, 45, bounds);
    EXPECT_EQ(cam.eye, (Vec3f{4, 3, 5}));
    EXPECT_EQ(cam.target, (Vec3f{0.5f, 1, -0.5f}));
    EXPECT_EQ(cam.up, (Vec3f{0, 1, 0}));
    EXPECT_EQ(cam.fov_y_deg, 45.0f);
    Camera fitted = cam;
    fit_clip_planes(fitted, bounds);
    EXPECT_EQ(cam.near_plane, fitted.near_plane);
    EXPECT_EQ(cam.far_plane, fitted.far_plane);
    // Straight down (and up): +Y would be parallel to the view, so up turns to −Z and the view
    // matrix exists.
    for (const float dy : {-2.0f, 2.0f}) {
        const Camera vertical = look_at_camera({1, 1, 0}, {1, 1 + dy, 0}, 60, bounds);
        EXPECT_EQ(vertical.up, (Vec3f{0, 0, -1}));
        EXPECT_NO_THROW(view_matrix(vertical));
    }
    EXPECT_THROW(look_at_camera({1, 2, 3}, {1, 2, 3}, 60, bounds), Error);
}

TEST(Camera, DefaultCameraFramesAnObjectFromOutside) {
    const Mesh sphere = make_builtin("sphere");
    for (float aspect : {16.0f / 9.0f, 1.0f, 0.5f}) {
        const Camera cam = default_camera(sphere, aspect);
        EXPECT_GT(length(cam.eye), 1.5f);  // outside the unit sphere
        EXPECT_GT(cam.eye.y, 0.0f);        // raised
        const int h = 400, w = int(h * aspect);
        for (const Vec3f& p : sphere.positions) {
            float x, y, depth;
            ASSERT_TRUE(project_to_pixel(cam, w, h, p, x, y, depth)) << "aspect " << aspect;
            EXPECT_GE(x, 0);
            EXPECT_LE(x, w);
        }
    }
}

TEST(Camera, DefaultCameraForTheRoomIsInsideNearARaisedCornerLookingDown) {
    const Mesh room = generate_room({});
    const Camera cam = default_camera(room, 16.0f / 9.0f);
    EXPECT_LT(std::abs(cam.eye.x), kRoomHalfWidth);
    EXPECT_LT(std::abs(cam.eye.z), kRoomHalfDepth);
    EXPECT_GT(cam.eye.y, 0.5f * kRoomWallHeight);
    EXPECT_LT(cam.eye.y, kRoomWallHeight);
    EXPECT_LT(cam.target.y, cam.eye.y);  // looking down
    // The room's centre is in view.
    float x, y, depth;
    EXPECT_TRUE(project_to_pixel(cam, 1280, 720, Vec3f{0, 0.5f, 0}, x, y, depth));
    EXPECT_LT(cam.near_plane, 0.2f);
    EXPECT_GT(cam.far_plane, 7.0f);
}

// Found by fuzz_value_parse (tests/fuzz/corpus/value_parse/camera-float-overflow): a finite
// double beyond float's range became an infinite eye, and eye and target at ±3e38 an infinite
// view direction.
TEST(Camera, ParsersRejectNumbersBeyondFloat) {
    Camera cam;
    EXPECT_THROW(parse_camera("0,1,4e81,0,1,5", cam), Error);
    EXPECT_THROW(parse_camera("0,0,-1e39,0,0,0", cam), Error);
    EXPECT_THROW(parse_camera("0,0,-3e38,0,0,3e38", cam), Error);
    parse_camera("0,0,-1e38,0,0,1e38", cam);  // far apart, but the direction fits a float
    EXPECT_EQ(cam.eye.z, -1e38f);
    EXPECT_THROW(parse_vec3("1e39,0,0", "--eye"), Error);
    EXPECT_EQ(parse_vec3("3e38,0,0", "--eye").x, 3e38f);
}

TEST(Camera, ParsersAcceptGoodTextAndRejectBad) {
    Camera cam;
    parse_camera("1,2,3,4,5,6.5", cam);
    EXPECT_EQ(cam.eye, (Vec3f{1, 2, 3}));
    EXPECT_EQ(cam.target, (Vec3f{4, 5, 6.5f}));
    EXPECT_THROW(parse_camera("1,2,3,4,5", cam), Error);
    EXPECT_THROW(parse_camera("1,2,3,1,2,3", cam), Error);  // eye == target
    EXPECT_THROW(parse_camera("1,2,x,4,5,6", cam), Error);
    EXPECT_THROW(parse_camera("1,2,nan,4,5,6", cam), Error);
    int w = 0, h = 0;
    parse_size("640x480", w, h);
    EXPECT_EQ(w, 640);
    EXPECT_EQ(h, 480);
    EXPECT_THROW(parse_size("640", w, h), Error);
    EXPECT_THROW(parse_size("0x10", w, h), Error);
    EXPECT_THROW(parse_size("10x-5", w, h), Error);
    EXPECT_THROW(parse_size("99999x10", w, h), Error);
    EXPECT_EQ(parse_vec3("0.5,-1,2", "eye"), (Vec3f{0.5f, -1, 2}));
    EXPECT_THROW(parse_vec3("0.5,-1", "eye"), Error);
    Camera bad;
    bad.eye = bad.target = {1, 1, 1};
    EXPECT_THROW(view_matrix(bad), Error);
    bad.fov_y_deg = 180;
    bad.eye = {0, 0, 1};
    EXPECT_THROW(projection_matrix(bad, 1.0f), Error);
}

}  // namespace
}  // namespace shprt
