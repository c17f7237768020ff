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

// A triangle's cone from o holds exactly the directions whose rays hit the triangle at t > 0:
// checked against the double-precision reference on random triangles, origins and directions,
// away from the edges (margin) where float answers may differ, far from the world's origin (where
// float differences lose bits). A cone thinner than 2^-10 (a sliver, a triangle seen edge-on) may
// be empty, but no cone may ever hold a direction that misses: slivers, whose float cross
// products point anywhere, are tested for that.
TEST(TriangleCone, HoldsTheDirectionsThatHitTheTriangle) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f);
    int hits = 0, misses = 0, thin = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const Vec3f shift{100.0f, 0.0f, 0.0f};
        const Vec3f a = Vec3f{pos(rng), pos(rng), pos(rng)} + shift,
                    b = Vec3f{pos(rng), pos(rng), pos(rng)} + shift;
        const Vec3f c = trial % 4 == 0 ? a + (b - a) * 0.5f + Vec3f{1e-4f, -2e-4f, 1e-4f}
                                       // a sliver
                                       : Vec3f{pos(rng), pos(rng), pos(rng)} + shift;
        const Vec3f o = Vec3f{pos(rng), pos(rng), pos(rng)} * 4.0f + shift;
        const Vec3d A = cast<double>(a) - cast<double>(o), B = cast<double>(b) - cast<double>(o),
                    C = cast<double>(c) - cast<double>(o);
        const bool may_be_empty = std::fabs(dot(A, cross(B, C))) <=
                                  std::pow(2.0, -9) * std::sqrt(dot(A, A) * dot(B, B) * dot(C, C));
        thin += may_be_empty ? 1 : 0;
        const TriangleCone cone = triangle_cone(o, a, b, c);
        for (int k = 0; k < 16; ++k) {
            float s = 1.5f * pos(rng) + 0.25f, r = 1.5f * pos(rng);  // around the triangle
            if (k % 4 < 2) {                                         // in it
                s = 0.5f + 0.5f * pos(rng), r = 0.5f + 0.5f * pos(rng);
                if (s + r > 1.0f) s = 1.0f - s, r = 1.0f - r;
            }
            const Vec3f target = a + (b - a) * s + (c - a) * r;
            const Vec3f d = k % 2 ? target - o : o - target;  // even: pointing away
            double t, u, v, margin;
            const bool want =
                reference_intersect(cast<double>(o), cast<double>(d), cast<double>(a),
                                    cast<double>(b), cast<double>(c), t, u, v, margin);
            if (std::fabs(margin) < 1e-3) continue;  // an edge: either answer is float rounding
            const bool inside = in_triangle_cone(cone, d);
            if (inside) ASSERT_TRUE(want) << "trial " << trial << " k " << k;
            if (!may_be_empty) ASSERT_EQ(inside, want) << "trial " << trial << " k " << k;
            (want ? hits : misses) += 1;
        }
    }
    std::printf("triangle cones: %d hits, %d misses compared; %d of 4000 cones thin\n", hits,
                misses, thin);
    EXPECT_GT(hits, 10000);
    EXPECT_GT(misses, 20000);
    EXPECT_LT(thin, 1500);  // the slivers (1000) and a few seen edge-on
}

// The crease rule: an origin in the triangle's plane, to float precision, starts its rays on that
// surface and they never hit it (tracer.hpp), so the cone is empty — also an origin a few units
// in the last place off a large triangle far from the world's origin (an offset ray origin at a
// crease), where the exact distance is below what float positions resolve.
TEST(TriangleCone, IsEmptyForAnOriginInThePlane) {
    const Vec3f a{0, 0, 0}, b{4, 0, 0}, c{0, 4, 0};
    std::mt19937 rng(23);
    for (const Vec3f o : {Vec3f{6, 1, 0}, Vec3f{1, 1, 0}, Vec3f{-2, -3, 0}}) {
        const TriangleCone cone = triangle_cone(o, a, b, c);
        for (int k = 0; k < 1000; ++k) {
            const Vec3f d = test::random_direction(rng);
            EXPECT_FALSE(in_triangle_cone(cone, d));
        }
        EXPECT_FALSE(in_triangle_cone(cone, Vec3f{-1, 0, 0}));  // along the plane, at an edge
    }
    // 172 units from the origin a float's unit in the last place is 1.5e-5; 7e-8 off the plane.
    const Vec3f far_a{172, 0, 10}, far_b{192, 0, 10}, far_c{172, 20, 10};
    const Vec3f o{175, 3, std::nextafter(10.0f, 11.0f)};
    const TriangleCone cone = triangle_cone(o, far_a, far_b, far_c);
    EXPECT_FALSE(in_triangle_cone(cone, Vec3f{1, 0.5f, -0.1f}));
    // Off the plane by more than that, the same direction does hit it.
    const TriangleCone above = triangle_cone(Vec3f{175, 3, 10.5f}, far_a, far_b, far_c);
    EXPECT_TRUE(in_triangle_cone(above, Vec3f{1, 0.5f, -0.1f}));
    // A small triangle there (0.02 across: its cone from 6 units in the last place off its plane
    // is not thin) still counts that origin as in its plane: within 2^-20 of 172.
    const float z = 172.0f, ulp = std::nextafter(z, 200.0f) - z;
    const Vec3f sa{172, 1, z}, sb{172.02f, 1, z}, sc{172, 1.02f, z};
    const Vec3f down{0.004f, 0.004f, -1.0f};
    EXPECT_FALSE(in_triangle_cone(triangle_cone(Vec3f{172.002f, 1.002f, z + 6 * ulp}, sa, sb, sc),
                                  down * (6 * ulp)));
    EXPECT_TRUE(in_triangle_cone(triangle_cone(Vec3f{172.002f, 1.002f, z + 30 * ulp}, sa, sb, sc),
                                 down * (30 * ulp)));
}

}  // namespace
}  // namespace shprt
