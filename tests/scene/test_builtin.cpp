// Built-in scenes and the MeshBuilder primitives they are made of; the inner corner's analytic
// occlusion against quadrature and against brute-force rays on the mesh itself.
#include "scene/geometry_checks.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace shprt {
namespace {

using test::brute_force_hit;
using test::expect_valid_generated;

TEST(SceneBuiltin, NamesAndUnknownName) {
    const auto names = builtin_scene_names();
    EXPECT_EQ(names, (std::vector<std::string>{"plane", "box_on_plane", "sphere", "corner", "room",
                                               "quad_box", "gloss_spheres", "leaky_room"}));
    try {
        make_builtin("nope");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        for (const auto& n : names) EXPECT_NE(std::string(e.what()).find(n), std::string::npos);
    }
}

TEST(SceneBuiltin, EachIsValidWithDocumentedCounts) {
    struct Expected {
        const char* name;
        std::size_t vertices, triangles;
        double area;
    };
    // box_on_plane: 33^2 plane vertices + 5 faces of 5^2; areas: plane, box sides + top.
    const Expected expected[] = {{"plane", 289, 512, 4.0},
                                 {"box_on_plane", 33 * 33 + 5 * 25, 2048 + 5 * 32, 16.0 + 5.0},
                                 {"sphere", 642, 1280, 0.0},
                                 {"corner", 2 * 21 * 41, 2 * 1600, 16.0},
                                 {"quad_box", 24, 12, 16.0 + 5.0}};
    for (const auto& e : expected) {
        SCOPED_TRACE(e.name);
        const Mesh m = make_builtin(e.name);
        expect_valid_generated(m);
        EXPECT_EQ(m.source, std::string("builtin:") + e.name);
        EXPECT_EQ(m.vertex_count(), e.vertices);
        EXPECT_EQ(m.triangle_count(), e.triangles);
        if (e.area > 0) {
            EXPECT_NEAR(mesh_surface_area(m), e.area, 1e-5);
        }
        for (const Vec3f& a : m.albedo)
            EXPECT_EQ(a, (Vec3f{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo}));
    }
}

TEST(SceneBuiltin, GlossSpheresGiveEachSphereItsBrdf) {
    const Mesh m = make_builtin("gloss_spheres");
    expect_valid_generated(m);
    const std::size_t floor = 29 * 57;  // 28 × 56 cells of 0.125 m
    ASSERT_EQ(m.vertex_count(), floor + 4 * 642u);
    EXPECT_EQ(m.triangle_count(), 2 * 28 * 56 + 4 * 1280u);
    ASSERT_EQ(m.brdfs.size(), 4u);
    EXPECT_EQ(m.brdfs[1], (Brdf{BrdfModel::ggx, 0.8, Vec3f{1.0f, 0.71f, 0.29f}}));  // gold
    EXPECT_EQ(m.brdfs[3], (Brdf{BrdfModel::ggx, 0.5}));
    ASSERT_EQ(m.brdf_index.size(), m.vertex_count());
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        SCOPED_TRACE(v);
        if (v < floor) {
            EXPECT_EQ(m.brdf_index[v], Mesh::kNoBrdf);
            EXPECT_EQ(m.positions[v].y, 0.0f);
            continue;
        }
        const std::uint32_t sphere = std::uint32_t((v - floor) / 642);
        EXPECT_EQ(m.brdf_index[v], sphere);
        // On sphere i, centred at x = -2.4 + 1.6 i.
        const Vec3f c{-2.4f + 1.6f * float(sphere), 0.65f, 0};
        EXPECT_NEAR(length(m.positions[v] - c), 0.65f, 1e-5f);
    }
}

TEST(SceneBuiltin, PlaneAndSphereGeometry) {
    const Mesh plane = make_builtin("plane");
    for (std::size_t v = 0; v < plane.vertex_count(); ++v) {
        EXPECT_EQ(plane.positions[v].y, 0.0f);
        EXPECT_EQ(plane.normals[v], (Vec3f{0, 1, 0}));
    }
    const Bounds b = mesh_bounds(plane);
    EXPECT_EQ(b.lo, (Vec3f{-1, 0, -1}));
    EXPECT_EQ(b.hi, (Vec3f{1, 0, 1}));

    const Mesh sphere = make_builtin("sphere");
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        EXPECT_NEAR(length(sphere.positions[v]), 1.0f, test::kUnitTol);
        EXPECT_GT(dot(sphere.normals[v], sphere.positions[v]), 1.0f - test::kUnitTol);  // outward
    }
    // An inscribed polyhedron: area below 4 pi, close to it at level 3.
    const double area = mesh_surface_area(sphere);
    EXPECT_LT(area, 4 * kPi);
    EXPECT_GT(area, 0.98 * 4 * kPi);
}

TEST(SceneBuiltin, BoxOnPlaneIsClosedAbove) {
    // From a plane vertex under the box every upward ray hits the box; beside it, straight up
    // escapes.
    const Mesh m = make_builtin("box_on_plane");
    test::TestRng rng(3);
    for (int i = 0; i < 200; ++i) {
        const double z = 2 * rng.next() - 1, phi = 2 * kPi * rng.next();
        const double r = std::sqrt(1 - z * z);
        const Vec3d dir{r * std::cos(phi), std::abs(z) + 1e-3, r * std::sin(phi)};
        EXPECT_TRUE(brute_force_hit(m, {0.125, 0.0, -0.25}, normalize(dir)).has_value());
    }
    EXPECT_FALSE(brute_force_hit(m, {1.0, 0.0, 1.0}, {0, 1, 0}).has_value());
    const auto top = brute_force_hit(m, {0.0, 0.5, 0.0}, {0, 1, 0});
    ASSERT_TRUE(top.has_value());
    EXPECT_NEAR(*top, 0.5, 1e-12);
}

// Slow reference for corner_occlusion: midpoint quadrature over the wall rectangle
// {0} x [0, 2] x [-2, 2] of the solid-angle and form-factor integrands.
CornerOcclusion corner_by_quadrature(double x, double z, int n) {
    double omega = 0.0, ff = 0.0;
    const double dy = 2.0 / n, dz = 4.0 / (2 * n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            const double wy = (i + 0.5) * dy, wz = -2.0 + (j + 0.5) * dz - z;
            const double r2 = x * x + wy * wy + wz * wz, r = std::sqrt(r2);
            omega += x / (r2 * r) * dy * dz;                  // cos at the wall / r^2
            ff += (wy / r) * (x / r) / (kPi * r2) * dy * dz;  // cos at the floor too
        }
    return {omega / (2 * kPi), ff};
}

TEST(SceneBuiltin, CornerOcclusionMatchesQuadrature) {
    constexpr double kQuadratureTol = 2e-5;
    for (const auto& [x, z] : {std::pair{0.1, 0.0}, std::pair{0.5, 0.3}, std::pair{1.5, -1.2}}) {
        const CornerOcclusion exact = corner_occlusion(x, z);
        const CornerOcclusion quad = corner_by_quadrature(x, z, 1500);
        EXPECT_NEAR(exact.solid_angle, quad.solid_angle, kQuadratureTol) << x << ", " << z;
        EXPECT_NEAR(exact.cosine, quad.cosine, kQuadratureTol) << x << ", " << z;
    }
    // Deep in the corner the wall hides nearly half of the hemisphere, by either measure.
    const CornerOcclusion deep = corner_occlusion(1e-6, 0.0);
    EXPECT_NEAR(deep.solid_angle, 0.5, 1e-3);
    EXPECT_NEAR(deep.cosine, 0.5, 1e-3);
    const CornerOcclusion probe = corner_occlusion(kCornerProbe.x, kCornerProbe.z);
    EXPECT_GT(probe.cosine, 0.45);
    EXPECT_LT(probe.cosine, 0.5);
    EXPECT_THROW(corner_occlusion(0.0, 0.0), Error);
}

TEST(SceneBuiltin, CornerMeshOccludesTheProbeAsComputed) {
    // Monte Carlo over the real mesh: uniform and cosine-weighted hemisphere directions from the
    // probe vertex, hit-tested against every triangle. 5 sigma of a 10 000-sample binomial.
    constexpr int kSamples = 10000;
    constexpr double kMcTol = 5.0 * 0.5 / 100.0;
    const Mesh m = make_builtin("corner");
    bool found = false;
    for (const Vec3f& p : m.positions) found = found || p == kCornerProbe;
    ASSERT_TRUE(found) << "the probe is a vertex";
    const Vec3d origin = cast<double>(kCornerProbe);
    test::TestRng rng(11);
    int uniform_hits = 0, cosine_hits = 0;
    for (int i = 0; i < kSamples; ++i) {
        const double u1 = rng.next(), u2 = 2 * kPi * rng.next();
        const double ru = std::sqrt(1 - u1 * u1);  // uniform: cos(theta) = u1
        if (brute_force_hit(m, origin, {ru * std::cos(u2), u1, ru * std::sin(u2)})) ++uniform_hits;
        const double rc = std::sqrt(u1), yc = std::sqrt(1 - u1);  // cosine-weighted
        if (brute_force_hit(m, origin, {rc * std::cos(u2), yc, rc * std::sin(u2)})) ++cosine_hits;
    }
    const CornerOcclusion exact = corner_occlusion(kCornerProbe.x, kCornerProbe.z);
    EXPECT_NEAR(uniform_hits / double(kSamples), exact.solid_angle, kMcTol);
    EXPECT_NEAR(cosine_hits / double(kSamples), exact.cosine, kMcTol);
}

TEST(SceneBuilder, CountingModeAgreesWithBuilding) {
    auto build = [](MeshBuilder& b) {
        const Rect2 holes[] = {{0.2, 0.5, 0.0, 0.7}, {0.8, 1.7, 0.9, 1.3}};
        b.set_placement({1, 2, 3}, 0.3);
        b.add_rect(Axis::z, 0.0, +1, {0, 2, 0, 1.5}, 0.07, {0.5f, 0.5f, 0.5f}, holes);
        b.add_box({0, 0, 0}, {0.3, 0.7, 0.11}, 0.05, {0.1f, 0.2f, 0.3f}, kBoxNoBottom);
        b.add_cylinder({0, 0, 0}, 0.2, 0.1, 0.5, 0.03, {0.3f, 0.3f, 0.3f}, true, true);
        b.add_cylinder({1, 0, 0}, 0.05, 0.05, 2.0, 0.03, {0.3f, 0.3f, 0.3f}, false, false);
        b.add_sphere({0, 1, 0}, 0.4, 0.05, {0.2f, 0.6f, 0.2f});
    };
    MeshBuilder counter(true), builder;
    build(counter);
    build(builder);
    EXPECT_EQ(counter.triangle_count(), builder.triangle_count());
    const Mesh m = builder.take_mesh("test");
    EXPECT_EQ(m.triangle_count(), counter.triangle_count());
    Mesh named = m;
    named.source = "builder";
    expect_valid_generated(named);
}

TEST(SceneBuilder, RectWithHolesHasTheRightArea) {
    MeshBuilder b;
    const Rect2 holes[] = {{0.25, 0.75, 0.0, 0.5}, {1.0, 1.5, 0.5, 0.75}};
    b.add_rect(Axis::y, 2.0, -1, {0, 2, 0, 1}, 0.1, {1, 1, 1}, holes);
    const Mesh m = b.take_mesh("rect");
    EXPECT_NEAR(mesh_surface_area(m), 2.0 - 0.25 - 0.125, 1e-6);
    for (const Vec3f& n : m.normals) EXPECT_EQ(n, (Vec3f{0, -1, 0}));
    // No vertex strictly inside a hole; y-axis rectangles have (a, b) = (z, x).
    for (const Vec3f& p : m.positions) {
        EXPECT_EQ(p.y, 2.0f);
        EXPECT_FALSE(p.z > 0.25f && p.z < 0.75f && p.x > 0.0f && p.x < 0.5f) << p.x << " " << p.z;
    }
    // Cells are at most 0.1 m per interval between cuts: along a the intervals 0.25, 0.5, 0.25,
    // 0.5, 0.5 take 3 + 5 + 3 + 5 + 5 = 21 cells, along b 0.5, 0.25, 0.25 take 5 + 3 + 3 = 11;
    // the holes cover 5 x 5 and 5 x 3 of them.
    EXPECT_EQ(m.triangle_count(), 2u * (21 * 11 - 25 - 15));
}

TEST(SceneBuilder, QuarterTurnsAreExactAndCylindersPointOutward) {
    MeshBuilder b;
    b.set_placement({0, 0, 0}, 0.5 * kPi);
    b.add_box({1, 0, -0.5}, {2, 1, 0.5}, 1.0, {1, 1, 1});
    const Mesh box = b.take_mesh("box");
    // +X turns to -Z exactly: the box occupies z in [-2, -1], x in [-0.5, 0.5].
    const Bounds bb = mesh_bounds(box);
    EXPECT_EQ(bb.lo, (Vec3f{-0.5f, 0, -2}));
    EXPECT_EQ(bb.hi, (Vec3f{0.5f, 1, -1}));

    MeshBuilder c;
    c.add_cylinder({0, 0, 0}, 0.5, 0.5, 1.0, 0.05, {1, 1, 1}, true, true);
    const Mesh cyl = c.take_mesh("cylinder");
    expect_valid_generated(cyl);
    for (std::size_t v = 0; v < cyl.vertex_count(); ++v) {
        const Vec3f p = cyl.positions[v], n = cyl.normals[v];
        if (n.y == 0.0f) {
            EXPECT_NEAR(std::hypot(p.x, p.z), 0.5, 1e-6);
            EXPECT_GT(n.x * p.x + n.z * p.z, 0.0f);
        }
    }
    // Polygonal approximation: area within 1 % of 2 pi r h + 2 pi r^2.
    EXPECT_NEAR(mesh_surface_area(cyl), 2 * kPi * 0.5 + 2 * kPi * 0.25, 0.01 * 1.5 * kPi);
}

}  // namespace
}  // namespace shprt
