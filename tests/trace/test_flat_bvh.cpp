// The flat BVH: structure (validate_flat_bvh), exact agreement of the SHPRT_HD traversal with a
// brute-force loop over all triangles, and agreement with Embree on random rays.
#include "shprt/core/error.hpp"
#include "shprt/trace/bvh_build.hpp"
#include "shprt/trace/flat_bvh.hpp"
#include "shprt/trace/tracer.hpp"

#include "trace/trace_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace shprt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Random rays over a mesh's bounding box: origins in the box (slightly enlarged), random
// directions; a third of them start on a random triangle, offset along its normal, as a bake's do.
struct RaySet {
    std::vector<Vec3f> origins, dirs;
};

RaySet random_rays(const Mesh& m, int count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    Vec3f lo = m.positions[0], hi = m.positions[0];
    for (const Vec3f& p : m.positions) {
        lo = vmin(lo, p);
        hi = vmax(hi, p);
    }
    const Vec3f pad = (hi - lo) * 0.1f;
    lo = lo - pad;
    hi = hi + pad;
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::uniform_int_distribution<std::size_t> pick(0, m.triangles.size() - 1);
    RaySet rays;
    for (int i = 0; i < count; ++i) {
        Vec3f d = test::random_direction(rng);
        Vec3f o;
        if (i % 3 == 0) {
            const auto& tri = m.triangles[pick(rng)];
            const Vec3f a = m.positions[tri[0]], b = m.positions[tri[1]], c = m.positions[tri[2]];
            float s = u(rng), t = u(rng);
            if (s + t > 1.0f) {
                s = 1.0f - s;
                t = 1.0f - t;
            }
            const Vec3f p = a + (b - a) * s + (c - a) * t;
            const Vec3f cr = cross(b - a, c - a);
            const float len = length(cr);
            if (!(len > 0.0f)) {
                --i;
                continue;
            }
            Vec3f n = cr / len;
            if (dot(n, d) < 0.0f) n = -n;
            o = offset_ray_origin(p, n);
        } else {
            o = {lo.x + (hi.x - lo.x) * u(rng), lo.y + (hi.y - lo.y) * u(rng),
                 lo.z + (hi.z - lo.z) * u(rng)};
        }
        rays.origins.push_back(o);
        rays.dirs.push_back(d);
    }
    return rays;
}

// The traversal must find exactly what the brute-force loop finds: the same triangle test, so
// the same t bit for bit (ties between triangles at the same t may resolve to either).
void expect_matches_brute_force(const Mesh& m, const FlatBvh& bvh, int count, std::uint32_t seed) {
    constexpr float kTmaxMargin = 1e-4f;
    const RaySet rays = random_rays(m, count, seed);
    const FlatBvhView view = bvh.view();
    int hits = 0;
    for (int i = 0; i < count; ++i) {
        const Vec3f o = rays.origins[i], d = rays.dirs[i];
        const Hit ref = test::brute_force_intersect(m, o, d, 0.0f, kInf);
        const Hit got = bvh_intersect(view, o, d, 0.0f, kInf);
        ASSERT_EQ(got.hit, ref.hit) << "ray " << i;
        ASSERT_EQ(bvh_occluded(view, o, d, 0.0f, kInf), ref.hit) << "ray " << i;
        if (!ref.hit) continue;
        ++hits;
        ASSERT_EQ(got.t, ref.t) << "ray " << i;
        if (got.triangle != ref.triangle) continue;  // an exact tie
        EXPECT_EQ(got.u, ref.u);
        EXPECT_EQ(got.v, ref.v);
        // A finite tmax just beyond / before the hit. (Not one ulp: the box test's slack bounds
        // its own rounding, not the triangle test's, so hits within a few ulps of tmax may be
        // culled.)
        EXPECT_TRUE(bvh_occluded(view, o, d, 0.0f, ref.t * (1.0f + kTmaxMargin)));
        EXPECT_FALSE(bvh_occluded(view, o, d, 0.0f, ref.t * (1.0f - kTmaxMargin)));
    }
    EXPECT_GT(hits, count / 10);
}

TEST(FlatBvh, LayoutIsFourVectorWords) {
    EXPECT_EQ(sizeof(FlatBvhNode), 64u);
    EXPECT_EQ(alignof(FlatBvhNode), 16u);
    const std::uint32_t ref = flat_bvh_make_leaf(kFlatBvhMaxPrimRefs - 1, kFlatBvhMaxLeafSize);
    EXPECT_TRUE(flat_bvh_is_leaf(ref));
    EXPECT_EQ(flat_bvh_leaf_first(ref), kFlatBvhMaxPrimRefs - 1);
    EXPECT_EQ(flat_bvh_leaf_count(ref), static_cast<std::uint32_t>(kFlatBvhMaxLeafSize));
    EXPECT_EQ(flat_bvh_leaf_count(flat_bvh_make_leaf(0, 1)), 1u);
    EXPECT_FALSE(flat_bvh_is_leaf(kFlatBvhLeafBit - 1));
}

TEST(FlatBvh, StructureIsValidForEveryOption) {
    const Mesh soup = test::make_triangle_soup(3000, 0.08f, 1);
    const Mesh scene = test::make_box_on_plane();
    for (const Mesh* m : {&soup, &scene})
        for (bool high : {true, false})
            for (int leaf : {1, 4, 16}) {
                FlatBvhBuildOptions options;
                options.high_quality = high;
                options.spatial_split_budget = 1.5f;
                options.max_leaf_size = leaf;
                const FlatBvh bvh = build_flat_bvh(*m, options);
                SCOPED_TRACE(m->source + (high ? " high" : " medium") + " leaf " +
                             std::to_string(leaf));
                EXPECT_NO_THROW(validate_flat_bvh(bvh, *m));
                EXPECT_EQ(bvh.stats.triangles, m->triangles.size());
                EXPECT_GE(bvh.stats.references, bvh.stats.triangles);
                if (!high) {
                    EXPECT_EQ(bvh.stats.references, bvh.stats.triangles);
                }
                EXPECT_LE(bvh.stats.max_depth, static_cast<std::uint32_t>(kFlatBvhStackSize));
                EXPECT_EQ(bvh.nodes.size() + 1, bvh.stats.leaves);  // a binary tree
                EXPECT_GT(bvh.stats.sah_cost, 0.0);
            }
}

TEST(FlatBvh, SpatialSplitsAddReferences) {
    // Long slivers across the box make splitting worthwhile.
    const Mesh soup = test::make_triangle_soup(4000, 0.5f, 2);
    FlatBvhBuildOptions high, medium;
    high.spatial_split_budget = 1.5f;
    medium.high_quality = false;
    const FlatBvh a = build_flat_bvh(soup, high), b = build_flat_bvh(soup, medium);
    std::printf("soup of 4000 long triangles: HIGH %u references, SAH %.2f; MEDIUM SAH %.2f\n",
                a.stats.references, a.stats.sah_cost, b.stats.sah_cost);
    EXPECT_GT(a.stats.references, a.stats.triangles);
    EXPECT_LE(a.stats.references, static_cast<std::uint32_t>(std::ceil(1.5 * a.stats.triangles)));
    EXPECT_LT(a.stats.sah_cost, b.stats.sah_cost);
}

TEST(FlatBvh, MatchesBruteForceOnSoup) {
    const Mesh soup = test::make_triangle_soup(2000, 0.3f, 3);
    for (bool high : {true, false})
        for (int leaf : {1, 4, 16}) {
            FlatBvhBuildOptions options;
            options.high_quality = high;
            options.spatial_split_budget = 1.5f;  // ignored by MEDIUM
            options.max_leaf_size = leaf;
            SCOPED_TRACE(std::string(high ? "high" : "medium") + " leaf " + std::to_string(leaf));
            expect_matches_brute_force(soup, build_flat_bvh(soup, options), 4000, 17);
        }
}

TEST(FlatBvh, MatchesBruteForceOnBoxOnPlane) {
    const Mesh scene = test::make_box_on_plane();
    expect_matches_brute_force(scene, build_flat_bvh(scene), 6000, 19);
}

TEST(FlatBvh, SingleTriangleTree) {
    Mesh m;
    m.source = "test:one";
    test::add_vertex(m, {0, 0, 0}, {0, 0, 1});
    test::add_vertex(m, {1, 0, 0}, {0, 0, 1});
    test::add_vertex(m, {0, 1, 0}, {0, 0, 1});
    m.triangles.push_back({0, 1, 2});
    const FlatBvh bvh = build_flat_bvh(m);
    ASSERT_EQ(bvh.nodes.size(), 1u);  // a root whose children are the one leaf
    EXPECT_NO_THROW(validate_flat_bvh(bvh, m));
    const Hit h = bvh_intersect(bvh.view(), {0.25f, 0.25f, 1}, {0, 0, -1}, 0.0f, kInf);
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.triangle, 0u);
    EXPECT_EQ(h.t, 1.0f);
    EXPECT_FLOAT_EQ(h.u, 0.25f);
    EXPECT_FLOAT_EQ(h.v, 0.25f);
    EXPECT_FALSE(bvh_occluded(bvh.view(), {0.75f, 0.75f, 1}, {0, 0, -1}, 0.0f, kInf));
}

TEST(FlatBvh, DegenerateTrianglesAreLeftOut) {
    Mesh m = test::make_plane(4, 1.0f, 0.0f);
    const auto good = m.triangles.size();
    m.triangles.push_back({0, 0, 1});  // repeated index
    m.triangles.push_back({0, 1, 2});  // collinear: three grid vertices on one row
    const FlatBvh bvh = build_flat_bvh(m);
    EXPECT_EQ(bvh.stats.triangles, good);
    EXPECT_NO_THROW(validate_flat_bvh(bvh, m));
}

TEST(FlatBvh, EmptyView) {
    const FlatBvhView empty{nullptr, nullptr, nullptr, 0, 0};
    EXPECT_FALSE(bvh_occluded(empty, {0, 0, 0}, {0, 0, 1}, 0.0f, kInf));
    EXPECT_FALSE(bvh_intersect(empty, {0, 0, 0}, {0, 0, 1}, 0.0f, kInf).hit);
}

TEST(FlatBvh, BadOptionsThrow) {
    const Mesh m = test::make_plane(2, 1.0f, 0.0f);
    FlatBvhBuildOptions o;
    o.max_leaf_size = 0;
    EXPECT_THROW(build_flat_bvh(m, o), Error);
    o.max_leaf_size = kFlatBvhMaxLeafSize + 1;
    EXPECT_THROW(build_flat_bvh(m, o), Error);
    o = {};
    o.spatial_split_budget = 0.5f;
    EXPECT_THROW(build_flat_bvh(m, o), Error);
    o = {};
    o.intersection_cost = 0.0f;
    EXPECT_THROW(build_flat_bvh(m, o), Error);
}

// Embree and the flat BVH on the same random rays: occlusion and closest hit (same triangle, t
// within kTolT relative) must agree on at least kMinAgreement of rays.
void expect_agrees_with_embree(const Mesh& m, int count, std::uint32_t seed) {
    constexpr double kMinAgreement = 0.999;
    constexpr float kTolT = 1e-4f;
    const auto embree = make_embree_tracer(m);
    const FlatBvh bvh = build_flat_bvh(m);
    const FlatBvhView view = bvh.view();
    const RaySet rays = random_rays(m, count, seed);
    int occlusion_diff = 0, hit_diff = 0, hits = 0;
    for (int i = 0; i < count; ++i) {
        const Vec3f o = rays.origins[i], d = rays.dirs[i];
        std::uint8_t occ = 0;
        embree->occluded(o, &d, 1, 0.0f, kInf, &occ);
        if ((occ != 0) != bvh_occluded(view, o, d, 0.0f, kInf)) ++occlusion_diff;
        const Hit e = embree->intersect(o, d, 0.0f, kInf);
        const Hit f = bvh_intersect(view, o, d, 0.0f, kInf);
        hits += e.hit ? 1 : 0;
        const bool same =
            e.hit == f.hit && (!e.hit || (e.triangle == f.triangle &&
                                          std::fabs(e.t - f.t) <= kTolT * std::max(1.0f, e.t)));
        if (!same) ++hit_diff;
    }
    const double occ_rate = static_cast<double>(occlusion_diff) / count;
    const double hit_rate = static_cast<double>(hit_diff) / count;
    std::printf(
        "%s: %d rays (%d hits): occlusion disagreement %.5f %%, closest-hit "
        "disagreement %.5f %%\n",
        m.source.c_str(), count, hits, 100.0 * occ_rate, 100.0 * hit_rate);
    EXPECT_GT(hits, count / 10);
    EXPECT_LE(occ_rate, 1.0 - kMinAgreement);
    EXPECT_LE(hit_rate, 1.0 - kMinAgreement);
}

TEST(FlatBvh, AgreesWithEmbreeOnSoup) {
    expect_agrees_with_embree(test::make_triangle_soup(20000, 0.05f, 4), 200000, 23);
}

TEST(FlatBvh, AgreesWithEmbreeOnBoxOnPlane) {
    expect_agrees_with_embree(test::make_box_on_plane(), 200000, 29);
}

}  // namespace
}  // namespace shprt
