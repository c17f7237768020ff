// merge_coplanar (trace/coplanar_merge.hpp) and the Embree tracer's visibility on its triangles:
// fewer triangles, the same area, and the same answer for every ray, on clean shapes and on rooms
// built like real assets (overlapping panels, interpenetrating furniture, split vertices).
#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/tracer.hpp"
#include "trace_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace shprt {
namespace {

using test::add_grid;
using test::add_vertex;

double area(const std::vector<Vec3f>& p, const std::vector<std::array<std::uint32_t, 3>>& tris) {
    double sum = 0;
    for (const auto& t : tris) {
        const Vec3d a = cast<double>(p[t[0]]), b = cast<double>(p[t[1]]), c = cast<double>(p[t[2]]);
        sum += 0.5 * length(cross(b - a, c - a));
    }
    return sum;
}

// Merges and checks the area; returns the merged triangle count.
std::size_t merged_count(const Mesh& m) {
    const MergedTriangles merged = merge_coplanar(m);
    EXPECT_FALSE(merged.area_check_failed);
    const double before = area(m.positions, m.triangles),
                 after = area(merged.positions, merged.triangles);
    EXPECT_NEAR(after, before, 1e-6 * before);
    return merged.triangles.size();
}

// The visibility of `rays_per_vertex` hemisphere rays from every `stride`-th vertex, as a bake
// casts them, and of as many rays between random points of the scene's box: on the mesh's own
// triangles (Embree) and on the merged ones (Embree, and the flat BVH the GPU bake traverses).
// Returns how many of the rays disagree.
std::size_t disagreements(const Mesh& m, std::size_t stride, int rays_per_vertex,
                          std::size_t& rays) {
    EmbreeTracerOptions own, merged;
    own.merge_coplanar = false;
    merged.closest_hits = false;
    const auto a = make_embree_tracer(m, own), b = make_embree_tracer(m, merged);
    const auto c = make_flat_bvh_tracer(merged_mesh(m));  // the GPU bake's visibility BVH
    std::size_t differ = 0;
    rays = 0;
    std::vector<std::uint8_t> oa, ob, oc;
    auto compare = [&](Vec3f origin, const std::vector<Vec3f>& dirs, float tfar) {
        oa.resize(dirs.size());
        ob.resize(dirs.size());
        oc.resize(dirs.size());
        a->occluded(origin, dirs.data(), int(dirs.size()), 0.0f, tfar, oa.data());
        b->occluded(origin, dirs.data(), int(dirs.size()), 0.0f, tfar, ob.data());
        c->occluded(origin, dirs.data(), int(dirs.size()), 0.0f, tfar, oc.data());
        for (std::size_t i = 0; i < dirs.size(); ++i) differ += oa[i] != ob[i] || oa[i] != oc[i];
        rays += dirs.size();
    };
    for (std::size_t v = 0; v < m.vertex_count(); v += stride)
        compare(offset_ray_origin(m.positions[v], m.normals[v]),
                test::hemisphere_directions(m.normals[v], rays_per_vertex, std::uint32_t(v)),
                INFINITY);
    Vec3f lo = m.positions[0], hi = lo;
    for (const Vec3f& p : m.positions) lo = vmin(lo, p), hi = vmax(hi, p);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0, 1);
    auto point = [&] {
        return Vec3f{lo.x + (hi.x - lo.x) * u(rng), lo.y + (hi.y - lo.y) * u(rng),
                     lo.z + (hi.z - lo.z) * u(rng)};
    };
    const std::size_t segments = rays;
    for (std::size_t i = 0; i < segments; ++i) {  // segments between two points: tfar = 1
        const Vec3f from = point();
        compare(from, {point() - from}, 1.0f);
    }
    return differ;
}

TEST(CoplanarMerge, ATessellatedPlaneBecomesTwoTriangles) {
    Mesh m = test::make_plane(24, 2.0f, 0.0f);
    EXPECT_EQ(m.triangles.size(), 2u * 24 * 24);
    EXPECT_EQ(merged_count(m), 2u);
    Vec3f normal{};
    Mesh tilted = test::make_tilted_plane(16, normal);  // planar only to float rounding
    EXPECT_EQ(merged_count(tilted), 2u);
}

TEST(CoplanarMerge, SplitVerticesAtASeamWeld) {
    // Two grids side by side, each with its own copy of the shared column of vertices (a UV seam).
    Mesh m;
    m.source = "test:seam";
    add_grid(m, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 4);
    add_grid(m, {1, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 4);
    EXPECT_EQ(merged_count(m), 2u);
}

TEST(CoplanarMerge, AHoleLeavesTheCellsAroundIt) {
    // A 6×6 grid without its middle 2×2 cells: the ring merges into four rectangles.
    Mesh m;
    m.source = "test:frame";
    add_grid(m, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 6);
    std::vector<std::array<std::uint32_t, 3>> kept;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const std::size_t cell = t / 2, i = cell % 6, j = cell / 6;
        if (!(i >= 2 && i < 4 && j >= 2 && j < 4)) kept.push_back(m.triangles[t]);
    }
    m.triangles = kept;
    EXPECT_EQ(merged_count(m), 8u);
    std::size_t rays = 0;
    EXPECT_EQ(disagreements(m, 1, 64, rays), 0u);
}

TEST(CoplanarMerge, LeavesWhatIsNotOneFlatConvexPiece) {
    // A roof ridge: two grids meeting at an angle merge each to two triangles, never across.
    Mesh ridge;
    ridge.source = "test:ridge";
    add_grid(ridge, {0, 0, 0}, {1, 0, 0}, {0, 0.5f, -1}, {0, 0.89f, 0.45f}, 3);
    add_grid(ridge, {0, 0.5f, -1}, {1, 0, 0}, {0, -0.5f, -1}, {0, 0.89f, -0.45f}, 3);
    EXPECT_EQ(merged_count(ridge), 4u);

    // Opposite windings on one plane (a face flipped by an exporter) do not pair or merge.
    Mesh flipped;
    flipped.source = "test:flipped";
    add_grid(flipped, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1);
    add_grid(flipped, {1, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, 1);  // the next cell, wound back
    EXPECT_EQ(merged_count(flipped), 4u);

    // An L of three cells: the corner cell merges with one arm only, never into a non-convex piece.
    Mesh ell;
    ell.source = "test:ell";
    add_grid(ell, {0, 0, 2}, {2, 0, 0}, {0, 0, -2}, {0, 1, 0}, 2);
    ell.triangles.erase(ell.triangles.begin() + 6, ell.triangles.end());  // drop the cell (1, 1)
    EXPECT_EQ(merged_count(ell), 4u);

    // T-junctions: one cell beside two smaller ones of different widths along its side. Nothing
    // shares a whole side, so nothing merges: three quads.
    Mesh tee;
    tee.source = "test:tee";
    add_grid(tee, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1);
    auto cell = [&](float x1, float z0, float z1) {  // x in [1, x1], z in [z0, z1], facing +Y
        const std::uint32_t v00 = add_vertex(tee, {1, 0, z1}, {0, 1, 0});
        const std::uint32_t v10 = add_vertex(tee, {x1, 0, z1}, {0, 1, 0});
        const std::uint32_t v01 = add_vertex(tee, {1, 0, z0}, {0, 1, 0});
        const std::uint32_t v11 = add_vertex(tee, {x1, 0, z0}, {0, 1, 0});
        tee.triangles.push_back({v00, v11, v01});
        tee.triangles.push_back({v00, v10, v11});
    };
    cell(2.0f, 0.5f, 1.0f);
    cell(1.5f, 0.0f, 0.5f);
    EXPECT_EQ(merged_count(tee), 6u);
    // Of equal widths the two small cells merge, the T is gone, and all three become one.
    tee.triangles.resize(4);
    cell(2.0f, 0.0f, 0.5f);
    EXPECT_EQ(merged_count(tee), 2u);

    // A curved surface: nothing to merge.
    const Mesh sphere = make_builtin("sphere");
    EXPECT_EQ(merged_count(sphere), sphere.triangles.size());
}

TEST(CoplanarMerge, DuplicateAndOverlappingFacesStay) {
    Mesh m;
    m.source = "test:overlaps";
    add_grid(m, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 4);
    add_grid(m, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 4);        // the same grid again
    add_grid(m, {0.4f, 0, 1.3f}, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 4);  // overlapping it
    const MergedTriangles merged = merge_coplanar(m);
    EXPECT_FALSE(merged.area_check_failed);
    // The duplicated grid's edges have four triangles each, so those cells stay apart; the
    // overlapping grid shares no vertex with them and merges alone.
    EXPECT_EQ(merged.triangles.size(), 2u * 2 * 16 + 2u);
    std::size_t rays = 0;
    EXPECT_EQ(disagreements(m, 1, 64, rays), 0u);
}

// The rooms built like real assets: fewer triangles, and the same visibility for every ray.
TEST(CoplanarMerge, RoomsSeeTheSameThroughFewerTriangles) {
    for (const char* name : {"room", "leaky_room", "box_on_plane", "corner"}) {
        const Mesh m = make_builtin(name);
        const std::size_t merged = merged_count(m);
        std::size_t rays = 0;
        const std::size_t differ = disagreements(m, 7, 128, rays);
        std::printf("%s: %zu -> %zu triangles; %zu of %zu rays disagree\n", name,
                    m.triangles.size(), merged, differ, rays);
        EXPECT_LT(merged, m.triangles.size() / 2) << name;
        EXPECT_EQ(differ, 0u) << name;
    }
}

TEST(CoplanarMerge, ABadMeshIsOneErrorNamingIt) {
    Mesh m = test::make_plane(2, 1.0f, 0.0f);
    m.source = "bad.obj";
    m.triangles.push_back({0, 1, 99});  // an index past the 9 vertices
    try {
        merge_coplanar(m);
        FAIL() << "merge_coplanar followed an index out of range";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.obj"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("99"), std::string::npos) << e.what();
    }
    m.triangles.pop_back();
    m.positions[4].y = NAN;
    EXPECT_THROW(merged_mesh(m), Error);
}

TEST(CoplanarMerge, TheTracerTracesTheMergeAndAnswersHitsOnTheMesh) {
    const Mesh m = test::make_plane(8, 2.0f, 0.0f);
    const auto both = make_embree_tracer(m);  // defaults: merged visibility, the mesh's hits
    const Hit hit = both->intersect({0.3f, 1.0f, 0.4f}, {0, -1, 0}, 0.0f, INFINITY);
    ASSERT_TRUE(hit.hit);
    EXPECT_LT(hit.triangle, m.triangles.size());
    EmbreeTracerOptions visibility_only;
    visibility_only.closest_hits = false;
    const auto vis = make_embree_tracer(m, visibility_only);
    const Vec3f down{0, -1, 0};
    std::uint8_t blocked = 0;
    vis->occluded({0.3f, 1.0f, 0.4f}, &down, 1, 0.0f, INFINITY, &blocked);
    EXPECT_EQ(blocked, 1);
    EXPECT_THROW(vis->intersect({0.3f, 1.0f, 0.4f}, down, 0.0f, INFINITY), Error);
}

}  // namespace
}  // namespace shprt
