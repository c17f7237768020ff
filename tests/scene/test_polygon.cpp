// Polygon triangulation: convex polygons give the fan from the first corner, concave ones are
// covered exactly by counter-clockwise triangles, degenerate ones do not crash.
#include "shprt/core/math.hpp"
#include "shprt/scene/polygon.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace shprt {
namespace {

using Tri = std::array<std::uint32_t, 3>;

// Signed area of a triangle seen along +Z (positive when counter-clockwise).
double signed_area_z(const std::vector<Vec3f>& p, const Tri& t) {
    const Vec3d a = cast<double>(p[t[0]]), b = cast<double>(p[t[1]]), c = cast<double>(p[t[2]]);
    return 0.5 * cross(b - a, c - a).z;
}

TEST(ScenePolygon, ConvexPolygonIsTheFan) {
    std::vector<Vec3f> p;
    for (int i = 0; i < 5; ++i) {
        const float a = 2.0f * kPiF * static_cast<float>(i) / 5.0f;
        p.push_back({std::cos(a), std::sin(a), 0.0f});
    }
    const std::vector<std::uint32_t> poly = {0, 1, 2, 3, 4};
    std::vector<Tri> out;
    triangulate_polygon(p, poly, out);
    EXPECT_EQ(out, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

TEST(ScenePolygon, ConcavePolygonsAreCoveredByFrontFacingTriangles) {
    // A dart whose fan from corner 0 would fold over (corner 1 is reflex), and an L shape.
    const std::vector<Vec3f> dart = {{2, 0, 0}, {1, 0.5f, 0}, {1, 2, 0}, {0, 0, 0}};
    const std::vector<Vec3f> ell = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0},
                                    {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    for (const auto& [p, area] : {std::pair{dart, 1.25}, std::pair{ell, 3.0}}) {
        std::vector<std::uint32_t> poly(p.size());
        for (std::uint32_t i = 0; i < poly.size(); ++i) poly[i] = i;
        std::vector<Tri> out;
        triangulate_polygon(p, poly, out);
        ASSERT_EQ(out.size(), p.size() - 2);
        double total = 0.0;
        for (const Tri& t : out) {
            EXPECT_GT(signed_area_z(p, t), 0.0);
            total += signed_area_z(p, t);
        }
        EXPECT_NEAR(total, area, 1e-6);
    }
}

TEST(ScenePolygon, ClockwisePolygonsStayClockwise) {
    // The same L listed clockwise (it faces -Z): every triangle keeps that winding.
    const std::vector<Vec3f> p = {{0, 2, 0}, {1, 2, 0}, {1, 1, 0}, {2, 1, 0}, {2, 0, 0}, {0, 0, 0}};
    const std::vector<std::uint32_t> poly = {0, 1, 2, 3, 4, 5};
    std::vector<Tri> out;
    triangulate_polygon(p, poly, out);
    ASSERT_EQ(out.size(), 4u);
    double total = 0.0;
    for (const Tri& t : out) {
        EXPECT_LT(signed_area_z(p, t), 0.0);
        total += signed_area_z(p, t);
    }
    EXPECT_NEAR(total, -3.0, 1e-6);
}

TEST(ScenePolygon, DegenerateInputDoesNotCrash) {
    const std::vector<Vec3f> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    const std::vector<std::uint32_t> poly = {0, 1, 2, 3};
    std::vector<Tri> out;
    triangulate_polygon(line, poly, out);
    EXPECT_EQ(out.size(), 2u);  // the fan; validate_mesh drops such zero-area triangles
    out.clear();
    const std::vector<std::uint32_t> two = {0, 1};
    triangulate_polygon(line, two, out);
    EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace shprt
