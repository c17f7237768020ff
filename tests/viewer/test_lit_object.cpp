// The probe-lit object's moves in the viewer (lit_object.hpp, object_step): the arrow keys, Page
// Up/Down and G+drag carry it over the floor along the camera's right and forward, kept
// horizontal and unit, and up along +Y, whatever the camera's pitch.
#include "lit_object.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace shprt::viewer {
namespace {

void expect_vec_near(Vec3f a, Vec3f b, float tol = 1e-6f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(LitObject, StepsStayOverTheFloorWhateverTheCameraPitch) {
    // A camera looking 60° down towards −Z: forward has a large vertical part.
    const float c = std::cos(1.0472f), s = std::sin(1.0472f);
    const Vec3f right{1, 0, 0}, forward{0, -s, -c};
    expect_vec_near(object_step(right, forward, 0, 2, 0),
                    {0, 0, -2});  // 2 m away, not into the floor
    expect_vec_near(object_step(right, forward, -0.5f, 0, 0), {-0.5f, 0, 0});
    expect_vec_near(object_step(right, forward, 0, 0, 0.25f), {0, 0.25f, 0});
    expect_vec_near(object_step(right, forward, 1, 1, 1), {1, 1, -1});
}

TEST(LitObject, UnnormalisedAndTiltedAxesAreNormalisedAndStraightDownMovesNothingAhead) {
    // A rolled camera (right tilted up) at a 45° yaw: the horizontal parts, unit length.
    const float h = std::sqrt(0.5f);
    const Vec3f right{3 * h, 2, -3 * h}, forward{0, -1, 0};  // looking straight down
    expect_vec_near(object_step(right, forward, 2, 0, 0), {2 * h, 0, -2 * h});
    const Vec3f ahead = object_step(right, forward, 0, 5, 0);
    expect_vec_near(ahead, {0, 0, 0});
    EXPECT_FALSE(std::isnan(ahead.x) || std::isnan(ahead.z));
}

}  // namespace
}  // namespace shprt::viewer
