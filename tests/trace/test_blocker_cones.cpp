// Blocker cones (tracer.hpp): the Embree tracer answers most blocked rays of a bundle from the
// cones of triangles that stopped their neighbours. The answers must be the tracer's own: checked
// on the bake's rays (a local Sobol set in its coherent order) over rooms built like real assets
// and a slotted roof whose gaps lie between blocked neighbours, against the tracer without cones
// and the watertight flat BVH; on a real asset, where they differ from Embree, against the flat
// BVH alone.
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/sh/direction_order.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/tracer.hpp"
#include "trace_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace shprt {
namespace {

// The set's directions in the order a bake traces them (coherent_order), in the local frame.
std::vector<Vec3f> bake_directions(std::uint32_t samples) {
    const DirectionSet set =
        make_local_direction_set(SamplerKind::sobol, 1, samples, HemisphereDensity::cosine);
    std::vector<Vec3f> dirs;
    for (const std::uint32_t i : coherent_order(set))
        dirs.push_back(Vec3f{set.dirs[3 * i], set.dirs[3 * i + 1], set.dirs[3 * i + 2]});
    return dirs;
}

struct Count {
    std::size_t rays = 0, blocked = 0;
    std::size_t cones_vs_embree = 0;  // answers of the tracer with cones and without that differ
    std::size_t cones_vs_flat = 0;    // … with cones and the flat BVH
    std::size_t sided_with_flat = 0;  // of the first, those where the flat BVH answers as the cones
};

// Every `stride`-th vertex's bundle of the first `vertices` (all: 0), as a bake casts it, on the
// three tracers.
Count compare(const Mesh& m, std::size_t stride, std::uint32_t samples, std::size_t vertices = 0) {
    EmbreeTracerOptions with, without;
    with.closest_hits = without.closest_hits = false;
    without.blocker_cones = false;
    const auto cones = make_embree_tracer(m, with), plain = make_embree_tracer(m, without);
    const auto flat = make_flat_bvh_tracer(merged_mesh(m));
    const std::vector<Vec3f> local = bake_directions(samples);
    std::vector<Vec3f> dirs(local.size());
    std::vector<std::uint8_t> a(local.size()), b(local.size()), c(local.size());
    Count n;
    const std::size_t end = vertices ? vertices : m.vertex_count();
    for (std::size_t v = 0; v < end; v += stride) {
        const LocalFrame f = local_frame(m.normals[v]);
        for (std::size_t i = 0; i < local.size(); ++i) dirs[i] = to_world(f, local[i]);
        const Vec3f o = offset_ray_origin(m.positions[v], m.normals[v]);
        const int count = int(dirs.size());
        cones->occluded(o, dirs.data(), count, 0.0f, INFINITY, a.data());
        plain->occluded(o, dirs.data(), count, 0.0f, INFINITY, b.data());
        flat->occluded(o, dirs.data(), count, 0.0f, INFINITY, c.data());
        for (std::size_t i = 0; i < dirs.size(); ++i) {
            n.blocked += a[i];
            n.cones_vs_embree += a[i] != b[i];
            n.cones_vs_flat += a[i] != c[i];
            n.sided_with_flat += a[i] != b[i] && a[i] == c[i];
        }
        n.rays += dirs.size();
    }
    return n;
}

TEST(BlockerCones, AnswerAsTheTracerDoesOnRoomsBuiltLikeRealAssets) {
    for (const char* name : {"room", "leaky_room", "box_on_plane", "corner"}) {
        const Count n = compare(make_builtin(name), 5, 256);
        std::printf(
            "%s: %zu rays, %zu blocked; cones differ from Embree on %zu, from the flat "
            "BVH on %zu\n",
            name, n.rays, n.blocked, n.cones_vs_embree, n.cones_vs_flat);
        EXPECT_GT(n.blocked, n.rays / 10) << name;
        EXPECT_EQ(n.cones_vs_embree, 0u) << name;
        EXPECT_EQ(n.cones_vs_flat, 0u) << name;
    }
}

// A roof of separate strips above a floor, with slots between them narrower than the bundle's
// spacing: many rays through a slot have blocked neighbours on both sides, stopped by two
// different strips, and must stay visible.
TEST(BlockerCones, NeverCloseAGapBetweenBlockers) {
    Mesh m;
    test::add_grid(m, {-4, -4, 0}, {8, 0, 0}, {0, 8, 0}, {0, 0, 1}, 8);  // the floor
    for (int s = 0; s < 40; ++s) {                                       // strips at z = 1
        const float x0 = -10.0f + 0.5f * float(s), x1 = x0 + 0.47f;      // slots 0.03 wide
        test::add_grid(m, {x0, -10, 1}, {x1 - x0, 0, 0}, {0, 20, 0}, {0, 0, -1}, 1);
    }
    const Count n = compare(m, 1, 1024, 81);  // the floor's vertices
    std::printf(
        "slotted roof: %zu rays, %zu blocked; cones differ from Embree on %zu, from the "
        "flat BVH on %zu\n",
        n.rays, n.blocked, n.cones_vs_embree, n.cones_vs_flat);
    EXPECT_GT(n.blocked, n.rays / 2);
    EXPECT_LT(n.blocked, n.rays - n.rays / 50) << "some rays pass the slots";
    EXPECT_EQ(n.cones_vs_embree, 0u);
    EXPECT_EQ(n.cones_vs_flat, 0u);
}

// A real asset (Assimp's IFC house: walls and slabs of large triangles beside fine detail): where
// the cones and Embree answer differently, the watertight flat BVH answers as the cones — rays
// that Embree's own test lets through at tiny t next to creases.
TEST(BlockerCones, WhereTheyDifferFromEmbreeTheWatertightTestAgrees) {
    const std::string path = "/usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " (assimp-testmodels) missing";
    const Count n = compare(load_scene(path), 3, 256);
    std::printf(
        "IFC house: %zu rays, %zu blocked; cones differ from Embree on %zu (the flat BVH "
        "sides with the cones on %zu)\n",
        n.rays, n.blocked, n.cones_vs_embree, n.sided_with_flat);
    EXPECT_GT(n.blocked, n.rays / 4);
    EXPECT_EQ(n.sided_with_flat, n.cones_vs_embree);
    EXPECT_LT(n.cones_vs_embree, n.rays / 10000);
}

}  // namespace
}  // namespace shprt
