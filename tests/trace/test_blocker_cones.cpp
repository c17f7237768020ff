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
#include "trace/blocker_cones.hpp"
#include "trace_test_util.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
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

// The ray loop's kernels (blocker_cones.hpp) answer alike, bit for bit: on random triangles'
// cones (a tenth of them empty) from a random origin and bundles of directions around them (a
// third through the triangles' edges, where a fused multiply-add would answer differently), of
// every length from one ray to past a group of sixteen, the SSE and AVX-512 kernels list the same
// rays to trace, in the same order, and mark the same rays occluded as the portable loop, and
// none touches a sample's answer. Kernels this CPU lacks are skipped, with a message.
TEST(BlockerCones, EveryKernelAnswersAsThePortableLoop) {
    using trace_detail::ConeKernel;
    std::mt19937 rng(20261207);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    auto unit = [&] {
        Vec3f d{u(rng), u(rng), u(rng)};
        return d * (1.0f / std::sqrt(dot(d, d) + 1e-12f));
    };
    for (const ConeKernel kernel : {ConeKernel::sse, ConeKernel::avx512, ConeKernel::automatic}) {
        if (!trace_detail::cone_kernel_available(kernel)) {
            std::printf("cone kernel %d: not on this CPU, skipped\n", int(kernel));
            continue;
        }
        std::size_t rays = 0, inside = 0;
        for (int trial = 0; trial < 400; ++trial) {
            const int count = 1 + trial % 75 + (trial % 7 == 0 ? 240 : 0);
            const int samples = (count + trace_detail::kConeStride - 1) / trace_detail::kConeStride;
            const auto rays_n = static_cast<std::size_t>(count);
            const Vec3f o{u(rng), u(rng), u(rng)};
            std::vector<TriangleCone> cone(static_cast<std::size_t>(samples));
            std::vector<std::array<Vec3f, 3>> corner(cone.size());
            for (std::size_t j = 0; j < cone.size(); ++j) {
                const Vec3f c = o + unit() * 2.0f;  // a triangle about two units out
                const float size = trial % 3 == 0 ? 1.5f : 0.3f;
                corner[j] = {c + unit() * size, c + unit() * size, c + unit() * size};
                cone[j] = rng() % 10 == 0
                              ? triangle_cone(o, o, o, o)
                              : triangle_cone(o, corner[j][0], corner[j][1], corner[j][2]);
            }
            // Directions toward points on and around the triangles of the two cones a ray is
            // tested against, and at random.
            std::uniform_real_distribution<float> bary(-0.1f, 1.0f);
            std::vector<Vec3f> dirs(rays_n);
            for (int i = 0; i < count; ++i) {
                const std::size_t j = std::min<std::size_t>(
                    std::size_t(i / trace_detail::kConeStride) + rng() % 2, cone.size() - 1);
                float a = bary(rng), b = bary(rng) * (1.0f - a);
                // A third on an edge: products that cancel to rounding, where a fused
                // multiply-add would round differently from the scalar test.
                if (rng() % 3 == 0) (rng() % 2 == 0 ? a : b) = 0.0f;
                const Vec3f p = corner[j][0] + (corner[j][1] - corner[j][0]) * a +
                                (corner[j][2] - corner[j][0]) * b;
                const Vec3f d = rng() % 4 == 0 ? unit() : p - o;
                dirs[std::size_t(i)] = d * (1.0f / std::sqrt(dot(d, d)));
            }
            std::vector<std::uint8_t> want(rays_n, 7), got(rays_n, 7);
            std::vector<std::uint32_t> want_list(rays_n), got_list(rays_n);
            const int n =
                trace_detail::test_cones(cone.data(), samples, dirs.data(), count, want.data(),
                                         want_list.data(), ConeKernel::portable);
            const int m = trace_detail::test_cones(cone.data(), samples, dirs.data(), count,
                                                   got.data(), got_list.data(), kernel);
            ASSERT_EQ(m, n) << "kernel " << int(kernel) << ", trial " << trial;
            for (int i = 0; i < n; ++i)
                ASSERT_EQ(got_list[std::size_t(i)], want_list[std::size_t(i)]);
            for (int i = 0; i < count; ++i) {
                ASSERT_EQ(got[std::size_t(i)], want[std::size_t(i)])
                    << "kernel " << int(kernel) << ", trial " << trial << ", ray " << i;
                if (i % trace_detail::kConeStride == 0) {
                    ASSERT_EQ(got[std::size_t(i)], 7) << "a sample's answer was touched";
                }
                inside += got[std::size_t(i)] == 1;
            }
            rays += rays_n;
        }
        std::printf("cone kernel %d: %zu rays, %zu inside a cone\n", int(kernel), rays, inside);
        EXPECT_GT(inside, rays / 10);
        EXPECT_LT(inside, rays - rays / 10);
    }
}

}  // namespace
}  // namespace shprt
