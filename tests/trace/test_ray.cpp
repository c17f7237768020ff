// Ray/triangle (watertight), ray/box (conservative) and ray-origin offsetting, against double
// precision references.
#include "shprt/trace/ray.hpp"

#include "trace/trace_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace shprt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Double-precision Möller–Trumbore: the reference for hit/miss, t and barycentrics.
bool reference_intersect(Vec3d o, Vec3d d, Vec3d a, Vec3d b, Vec3d c, double& t, double& u,
                         double& v, double& margin) {
    const Vec3d e1 = b - a, e2 = c - a;
    const Vec3d p = cross(d, e2);
    const double det = dot(e1, p);
    margin = 0.0;  // parallel: call it borderline
    if (det == 0.0) return false;
    const Vec3d s = o - a;
    u = dot(s, p) / det;
    const Vec3d q = cross(s, e1);
    v = dot(d, q) / det;
    t = dot(e2, q) / det;
    margin = std::min({u, v, 1.0 - u - v});  // distance inside the triangle, barycentric units
    return margin >= 0.0 && t > 0.0;
}

TEST(Ray, TriangleMatchesDoubleReference) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f);
    constexpr int kTrials = 200000;
    constexpr double kEdgeMargin = 1e-4;  // rays this close to an edge may go either way
    constexpr double kTolT = 1e-4, kTolBary = 1e-4;
    int compared = 0, hits = 0, disagreements = 0;
    for (int i = 0; i < kTrials; ++i) {
        const Vec3f a{pos(rng), pos(rng), pos(rng)}, b{pos(rng), pos(rng), pos(rng)},
            c{pos(rng), pos(rng), pos(rng)};
        const Vec3f o = Vec3f{pos(rng), pos(rng), pos(rng)} * 3.0f;
        // Aim near the triangle so that about half the rays hit.
        const Vec3f target =
            (a + b + c) * (1.0f / 3.0f) + Vec3f{pos(rng), pos(rng), pos(rng)} * 0.4f;
        const Vec3f d = target - o;
        float t, u, v;
        const bool hit = intersect_triangle(o, d, a, b, c, 0.0f, kInf, t, u, v);
        double rt, ru, rv, margin;
        const bool ref = reference_intersect(cast<double>(o), cast<double>(d), cast<double>(a),
                                             cast<double>(b), cast<double>(c), rt, ru, rv, margin);
        if (std::fabs(margin) < kEdgeMargin) continue;
        ++compared;
        if (hit != ref) {
            ++disagreements;
            continue;
        }
        if (!hit) continue;
        ++hits;
        EXPECT_NEAR(t, rt, kTolT * std::max(1.0, std::fabs(rt)));
        EXPECT_NEAR(u, ru, kTolBary);
        EXPECT_NEAR(v, rv, kTolBary);
    }
    std::printf("triangle test: %d rays compared, %d hits, %d disagreements\n", compared, hits,
                disagreements);
    EXPECT_GT(hits, compared / 5);
    EXPECT_EQ(disagreements, 0);
}

TEST(Ray, BarycentricsReproduceHitPoint) {
    std::mt19937 rng(11);
    constexpr float kTol = 2e-6f, kTolAlong = 1e-4f;  // scene scale ~1 (origins at distance 4)
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3f a = test::random_direction(rng), b = test::random_direction(rng),
                    c = test::random_direction(rng);
        const Vec3f o = test::random_direction(rng) * 4.0f;
        const Vec3f d = (a + b + c) * (1.0f / 3.0f) - o + test::random_direction(rng) * 0.2f;
        float t, u, v;
        if (!intersect_triangle(o, d, a, b, c, 0.0f, kInf, t, u, v)) continue;
        ++hits;
        // Across the ray: barycentric point on the ray line; along it: at parameter t (looser,
        // grazing hits amplify t's rounding).
        const Vec3d q = cast<double>(a) * (1.0 - u - v) + cast<double>(b) * double(u) +
                        cast<double>(c) * double(v);
        const Vec3d dn = normalize(cast<double>(d)), rel = q - cast<double>(o);
        const double along = dot(rel, dn);
        EXPECT_LT(length(rel - dn * along), kTol) << "ray " << i;
        EXPECT_LT(std::fabs(along - double(t) * length(cast<double>(d))), kTolAlong) << "ray " << i;
        EXPECT_GE(u, -kTol);
        EXPECT_GE(v, -kTol);
        EXPECT_LE(u + v, 1.0f + kTol);
    }
    EXPECT_GT(hits, 5000);
}

// Rays through the shared vertices and edges of a tessellated (closed) quad must hit at least
// one triangle: no ray leaks through a crack. Grid coordinates are exact in float.
TEST(Ray, WatertightOnSharedEdgesAndVertices) {
    Mesh grid;
    test::add_grid(grid, {0, 0, 0}, {8, 0, 0}, {0, 8, 0}, {0, 0, 1}, 8);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> jitter(-3.0f, 3.0f);
    int rays = 0, leaks = 0;
    for (int j = 1; j < 8; ++j)
        for (int i = 1; i < 8; ++i)
            for (int k = 0; k < 300; ++k) {
                // Target: the interior vertex (i, j), or the midpoint of one of its edges.
                const float dx = (k % 3 == 1) ? 0.5f : 0.0f, dy = (k % 3 == 2) ? 0.5f : 0.0f;
                const Vec3f target{static_cast<float>(i) + dx, static_cast<float>(j) + dy, 0.0f};
                const Vec3f o{target.x + jitter(rng), target.y + jitter(rng), 5.0f + jitter(rng)};
                const Vec3f d = target - o;
                ++rays;
                if (!test::brute_force_intersect(grid, o, d, 0.0f, kInf).hit) ++leaks;
            }
    std::printf("watertight: %d rays through vertices/edges, %d leaks\n", rays, leaks);
    EXPECT_EQ(leaks, 0);
}

TEST(Ray, TwoSidedAndOpenInterval) {
    const Vec3f a{-1, -1, 2}, b{1, -1, 2}, c{0, 1, 2};
    float t, u, v;
    // From the front and from the back.
    ASSERT_TRUE(intersect_triangle({0, 0, 0}, {0, 0, 1}, a, b, c, 0.0f, kInf, t, u, v));
    EXPECT_EQ(t, 2.0f);
    ASSERT_TRUE(intersect_triangle({0, 0, 4}, {0, 0, -1}, a, b, c, 0.0f, kInf, t, u, v));
    EXPECT_EQ(t, 2.0f);
    // tmin < t < tmax: a hit exactly at an endpoint does not count.
    EXPECT_FALSE(intersect_triangle({0, 0, 0}, {0, 0, 1}, a, b, c, 0.0f, 2.0f, t, u, v));
    EXPECT_TRUE(intersect_triangle({0, 0, 0}, {0, 0, 1}, a, b, c, 0.0f, std::nextafter(2.0f, kInf),
                                   t, u, v));
    EXPECT_FALSE(intersect_triangle({0, 0, 0}, {0, 0, 1}, a, b, c, 2.0f, kInf, t, u, v));
    // Behind the origin.
    EXPECT_FALSE(intersect_triangle({0, 0, 3}, {0, 0, 1}, a, b, c, 0.0f, kInf, t, u, v));
    // Unnormalised direction: t in units of |d|.
    ASSERT_TRUE(intersect_triangle({0, 0, 0}, {0, 0, 4}, a, b, c, 0.0f, kInf, t, u, v));
    EXPECT_EQ(t, 0.5f);
}

TEST(Ray, DegenerateTrianglesNeverHit) {
    std::mt19937 rng(5);
    for (int i = 0; i < 10000; ++i) {
        const Vec3f a = test::random_direction(rng), b = test::random_direction(rng);
        const Vec3f o = test::random_direction(rng) * 3.0f;
        float t, u, v;
        // Collinear (c on segment ab, exactly: the midpoint of a and a) and repeated vertices.
        EXPECT_FALSE(intersect_triangle(o, a - o, a, a, b, 0.0f, kInf, t, u, v));
        EXPECT_FALSE(intersect_triangle(o, a - o, a, a, a, 0.0f, kInf, t, u, v));
    }
}

TEST(Ray, OffsetMovesToTheNormalSideByABoundedAmount) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> exponent(-12.0f, 12.0f);
    for (int i = 0; i < 100000; ++i) {
        const Vec3f dir = test::random_direction(rng);
        const Vec3f p = dir * std::exp2(exponent(rng));
        const Vec3f n = test::random_direction(rng);
        const Vec3f q = offset_ray_origin(p, n);
        const Vec3d delta = cast<double>(q) - cast<double>(p);
        // Strictly into n's half-space.
        ASSERT_GT(dot(delta, cast<double>(n)), 0.0) << "i=" << i;
        // Per axis: at most 256 ulps (about 256·2^-23·|p_i|... plus one rounding) or 1/65536.
        for (int k = 0; k < 3; ++k) {
            const double bound =
                std::max(1.0 / 65536.0, 257.0 * std::ldexp(1.0, -23) * std::fabs(p[k]));
            ASSERT_LE(std::fabs(delta[k]), bound) << "i=" << i << " axis " << k;
        }
    }
    // Near the origin the offset is the absolute n/65536.
    const Vec3f q = offset_ray_origin({0, 0, 0}, {0, 1, 0});
    EXPECT_EQ(q.x, 0.0f);
    EXPECT_EQ(q.y, 1.0f / 65536.0f);
    EXPECT_EQ(q.z, 0.0f);
    // −0.0 (bits INT32_MIN) with a normal pointing to −x: the ulp step would overflow the
    // integer, undefined behaviour that UBSan found on Assimp's corpus (LWO models); the absolute
    // offset applies there.
    const Vec3f z = offset_ray_origin({-0.0f, -0.0f, 1.0f}, {-0.6f, -0.8f, 0.0f});
    EXPECT_EQ(z.x, -0.6f / 65536.0f);
    EXPECT_EQ(z.y, -0.8f / 65536.0f);
    EXPECT_EQ(z.z, 1.0f);
}

// Slab test: hits whenever the exact segment enters the box, including flat (zero-thickness)
// boxes and axis-parallel rays; misses when the exact ray clearly passes by.
TEST(Ray, BoxTestIsConservative) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> pos(-2.0f, 2.0f);
    int exact_hits = 0;
    for (int i = 0; i < 200000; ++i) {
        Vec3f lo{pos(rng), pos(rng), pos(rng)}, hi{pos(rng), pos(rng), pos(rng)};
        Aabb box{vmin(lo, hi), vmax(lo, hi)};
        if (i % 4 == 0) box.hi.y = box.lo.y;  // flat box
        const Vec3f o = Vec3f{pos(rng), pos(rng), pos(rng)} * 2.0f;
        Vec3f d = test::random_direction(rng);
        if (i % 2 == 0) {  // aim at a point of the box
            std::uniform_real_distribution<float> s(0.0f, 1.0f);
            d = Vec3f{box.lo.x + (box.hi.x - box.lo.x) * s(rng),
                      box.lo.y + (box.hi.y - box.lo.y) * s(rng),
                      box.lo.z + (box.hi.z - box.lo.z) * s(rng)} -
                o;
        }
        if (i % 5 == 0) d.x = 0.0f;  // axis-parallel components
        if (i % 7 == 0) d.z = 0.0f;
        if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) continue;
        float tnear;
        const bool hit = intersect_box(make_slab_ray(o, d), box, 0.0f, kInf, tnear);
        // Exact (double) slab test on the same float inputs.
        double t0 = 0.0, t1 = 1e300;
        bool exact = true;
        for (int k = 0; k < 3; ++k) {
            const double ok = o[k], dk = d[k], l = box.lo[k], h = box.hi[k];
            if (dk == 0.0) {
                if (ok < l || ok > h) exact = false;
                continue;
            }
            double a = (l - ok) / dk, b = (h - ok) / dk;
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
        }
        exact = exact && t0 <= t1;
        if (exact) {
            ++exact_hits;
            ASSERT_TRUE(hit) << "conservative test culled a box the ray enters, i=" << i;
            EXPECT_LE(tnear, t0 * (1.0 + 1e-5) + 1e-6);
        } else if (t0 > t1 * 1.001 + 1e-3) {
            EXPECT_FALSE(hit) << "i=" << i;
        }
    }
    EXPECT_GT(exact_hits, 50000);
}

}  // namespace
}  // namespace shprt
