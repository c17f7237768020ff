// Mesh operations: angle- and area-weighted normals against hand-computed weights, validation,
// bounds, and the sRGB conversions.
#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace shprt {
namespace {

constexpr float kNormalTol = 1e-6f;

void expect_near(Vec3f a, Vec3f b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

// Triangle A = (0, 1, 2) faces +Y with a 90-degree corner at the origin (area 1/2); triangle
// B = (0, 3, 4) faces +X with a 45-degree corner at the origin (area 1/2). Vertex 4 sits where
// vertex 1 does (a hard edge if grouped by index); vertex 5 is unused.
Mesh hinge() {
    Mesh m;
    m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 1}, {0, 0, 1}, {5, 5, 5}};
    m.triangles = {{0, 1, 2}, {0, 3, 4}};
    return m;
}

TEST(SceneNormals, AreaAndAngleWeightsByIndex) {
    Mesh m = hinge();
    compute_vertex_normals(m);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    // Origin: weights 2 * area * angle = pi/2 on +Y (A) and pi/4 on +X (B): direction (1, 2, 0).
    const float s = 1.0f / std::sqrt(5.0f);
    expect_near(m.normals[0], {s, 2 * s, 0}, kNormalTol);
    expect_near(m.normals[1], {0, 1, 0}, kNormalTol);  // only in A
    expect_near(m.normals[4], {1, 0, 0}, kNormalTol);  // only in B
    EXPECT_EQ(m.normals[5], (Vec3f{0, 1, 0}));         // unused: +Y by convention
}

TEST(SceneNormals, ByPositionWeldsCoincidentVertices) {
    Mesh m = hinge();
    compute_vertex_normals_by_position(m);
    // At (0, 0, 1): A's corner is 45 degrees (weight pi/4 on +Y), B's is 90 degrees (pi/2 on +X).
    const float s = 1.0f / std::sqrt(5.0f);
    expect_near(m.normals[1], {2 * s, s, 0}, kNormalTol);
    EXPECT_EQ(m.normals[1], m.normals[4]);
    expect_near(m.normals[0], {s, 2 * s, 0}, kNormalTol);
    EXPECT_EQ(m.vertex_count(), 6u);  // nothing welded in the mesh itself
}

TEST(SceneNormals, FlatSquareNormalsAlongTheFaceNormal) {
    // A unit square tilted about the x axis, as two triangles sharing a diagonal.
    const float c = std::cos(0.3f), s = std::sin(0.3f);
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, s, -c}, {0, s, -c}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    compute_vertex_normals(m);
    const Vec3f expected =
        normalize(cross(m.positions[1] - m.positions[0], m.positions[3] - m.positions[0]));
    for (const Vec3f& n : m.normals) expect_near(n, expected, kNormalTol);
}

TEST(SceneValidate, RejectsEmptyNonFiniteAndOutOfRange) {
    const std::string name = "test.ply";
    auto expect_error = [&](Mesh m, const std::string& what) {
        try {
            validate_mesh(m, name);
            ADD_FAILURE() << "no error for: " << what;
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.rfind(name + ": ", 0), 0u) << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << msg;
        }
    };
    expect_error(Mesh{}, "no vertices");
    Mesh ok = hinge();
    Mesh no_tris = ok;
    no_tris.triangles.clear();
    expect_error(no_tris, "no triangles");
    Mesh nan = ok;
    nan.positions[2].y = std::numeric_limits<float>::quiet_NaN();
    expect_error(nan, "vertex 2 has a non-finite coordinate");
    Mesh inf = ok;
    inf.positions[3].z = -std::numeric_limits<float>::infinity();
    expect_error(inf, "vertex 3 has a non-finite coordinate");
    Mesh range = ok;
    range.triangles[1][2] = 6;
    expect_error(range, "triangle 1 has vertex index 6 out of range");
    Mesh sizes = ok;
    sizes.albedo.resize(2);
    expect_error(sizes, "2 albedo values for 6 vertices");
    Mesh bad_normal = ok;
    bad_normal.normals.assign(6, Vec3f{0, 1, 0});
    bad_normal.normals[4].x = std::numeric_limits<float>::quiet_NaN();
    expect_error(bad_normal, "vertex 4 has a non-finite normal");
    Mesh all_degenerate = ok;
    all_degenerate.triangles = {{0, 0, 1}};
    expect_error(all_degenerate, "all 1 triangles are degenerate");
}

TEST(SceneValidate, DropsDegenerateTrianglesAndClampsAlbedo) {
    Mesh m = hinge();
    m.triangles.push_back({1, 4, 2});  // 1 and 4 coincide: zero area
    m.triangles.push_back({2, 2, 3});  // repeated index
    m.albedo.assign(6, Vec3f{0.5f, 1.5f, -0.25f});
    std::vector<std::string> warnings;
    set_log_sink([&](LogLevel level, std::string_view msg) {
        if (level == LogLevel::warn) warnings.emplace_back(msg);
    });
    validate_mesh(m, "hinge");
    set_log_sink(nullptr);
    ASSERT_EQ(m.triangle_count(), 2u);
    EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 3, 4}));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], "hinge: dropped 2 degenerate triangles (of 4)");
    EXPECT_EQ(m.albedo[0], (Vec3f{0.5f, 1.0f, 0.0f}));
}

TEST(SceneBounds, BoundsAndArea) {
    const Mesh m = hinge();
    const Bounds b = mesh_bounds(m);
    EXPECT_EQ(b.lo, (Vec3f{0, 0, 0}));
    EXPECT_EQ(b.hi, (Vec3f{5, 5, 5}));  // unused vertices count
    EXPECT_DOUBLE_EQ(mesh_surface_area(m), 1.0);
    const Bounds e = mesh_bounds(Mesh{});
    EXPECT_EQ(e.lo, (Vec3f{0, 0, 0}));
    EXPECT_EQ(e.hi, (Vec3f{0, 0, 0}));
}

}  // namespace
}  // namespace shprt
