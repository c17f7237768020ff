// The interreflected ground truth, path_trace_irradiance (bake/ground_truth.hpp), against closed
// forms, and the exact tracer it runs on in tests (common/brute_force_tracer.hpp) against Embree:
//   * an open plane: E_0 = π·L under a constant sky, exactly (every ray escapes), and the clamped
//     cosine's SH convolution under a linear one; no bounces;
//   * the spherical cavity: E_b = π·L·f·(ρ(1 − f))^b per channel, with its faces turned in and
//     out (the path tracer is two-sided like a renderer: the same light either way);
//   * the same bits for any thread count and for a vertex alone or among others;
//   * standard errors that match the spread of estimates over seeds;
//   * the brute-force tracer's hits are Embree's (hit or miss, t, the point its barycentrics give)
//     on random rays through builtin:leaky_room;
//   * bad input and cancelling.
#include "bake_test_util.hpp"

#include "shprt/bake/ground_truth.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace shprt {
namespace {

using test::BruteForceTracer;

// A plane y = 0 facing +Y, n × n cells over [−1, 1]².
Mesh open_plane(int n) {
    MeshBuilder b;
    b.add_rect(Axis::y, 0.0, +1, {-1, 1, -1, 1}, 2.0 / n, {0.5f, 0.5f, 0.5f});
    return b.take_mesh("test:plane");
}

PathTraceOptions options(int bounces, std::uint32_t paths) {
    PathTraceOptions o;
    o.bounces = bounces;
    o.paths = paths;
    o.seed = 5;
    o.threads = 2;
    return o;
}

std::vector<std::uint32_t> all_vertices(const Mesh& m) {
    std::vector<std::uint32_t> v(m.vertex_count());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t(i);
    return v;
}

TEST(PathTrace, OpenPlaneUnderAConstantSkyIsPiL) {
    const Mesh plane = open_plane(4);
    const BruteForceTracer tracer(plane);
    const std::vector<double> light = {1.0, 0.5, 2.0};  // K = 1: L_c = light_c·y_0
    const auto vertices = all_vertices(plane);
    const PathTraceIrradiance e =
        path_trace_irradiance(plane, vertices, 1, light, options(3, 64), tracer);
    ASSERT_EQ(e.receivers, vertices.size());
    ASSERT_EQ(e.mean.size(), vertices.size() * 4 * 3);
    const double y0 = 0.5 / std::sqrt(kPi);
    for (std::size_t r = 0; r < e.receivers; ++r)
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(e.mean[e.index(r, 0, c)], kPi * light[c] * y0, 1e-12);
            EXPECT_NEAR(e.std_error[e.index(r, 0, c)], 0.0, 1e-12);
            for (int b = 1; b <= 3; ++b) EXPECT_EQ(e.mean[e.index(r, b, c)], 0.0) << b;
            EXPECT_EQ(e.indirect_std_error[e.index(r, 3, c)], 0.0);
        }
    // Every path: M light rays and one continuation that escapes.
    EXPECT_EQ(e.rays_cast, vertices.size() * 64 * 5);
}

// A linear sky: E = Σ_i Â_l(i)·L_i·y_i(n) with Â_0 = π, Â_1 = 2π/3 (sh/zonal.hpp).
TEST(PathTrace, OpenPlaneUnderALinearSkyIsTheCosineConvolution) {
    const Mesh plane = open_plane(2);
    const BruteForceTracer tracer(plane);
    const std::vector<double> light = {3.0, 0.8,  -0.5, 0.3,    // R
                                       2.0, -0.4, 0.6,  0.2,    // G
                                       1.0, 0.3,  0.2,  -0.6};  // B
    double y[4];
    sh_eval_k<double>(4, 0.0, 1.0, 0.0, y);
    const double A[4] = {kPi, 2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3};
    const std::vector<std::uint32_t> vertices = {0, 4, 8};
    const PathTraceIrradiance e =
        path_trace_irradiance(plane, vertices, 4, light, options(1, 20000), tracer);
    for (std::size_t r = 0; r < vertices.size(); ++r)
        for (int c = 0; c < 3; ++c) {
            double expect = 0;
            for (int i = 0; i < 4; ++i) expect += A[i] * light[c * 4 + i] * y[i];
            const double sigma = e.std_error[e.index(r, 0, c)];
            EXPECT_GT(sigma, 0.0);
            EXPECT_LT(sigma, 0.01 * expect);
            EXPECT_NEAR(e.mean[e.index(r, 0, c)], expect, 4 * sigma) << r << " " << c;
            EXPECT_EQ(e.mean[e.index(r, 1, c)], 0.0);
        }
}

// The cavity's closed form per bounce and channel, with its faces turned into the cavity and out
// of it. The mesh is a faceted sphere with a jagged rim, so f is taken per receiver from its own
// E_0 (as tests/bake/test_interreflect.cpp does) and each bounce is compared with E_0·(ρ(1 − f))^b
// within 4 standard errors of the path tracer plus kFacets of the value; and the mean relative
// deviation over the receivers, within 4 of its standard errors plus kFacetsMean.
TEST(PathTrace, SphericalCavityMatchesTheClosedForm) {
    // Named tolerances: the level-4 icosphere's flat faces and jagged cut make f vary over the
    // cavity. Measured with 65 536 paths of 16 light rays (standard errors 0.28 %): deviations
    // up to 1.1 % per receiver (2.9 standard errors), at most 0.11 % on average over them.
    constexpr double kFacets = 0.01;
    constexpr double kFacetsMean = 0.003;
    const Vec3f rho{0.3f, 0.6f, 0.9f};
    constexpr int N = 3;
    const std::vector<double> light = {2 * std::sqrt(kPi), 2 * std::sqrt(kPi),
                                       2 * std::sqrt(kPi)};  // L = 1
    for (const bool front_inside : {true, false}) {
        SCOPED_TRACE(front_inside ? "faces into the cavity" : "faces out of it");
        const Mesh cavity = test::spherical_cavity(4, 0.5, rho, front_inside);
        const auto tracer = make_embree_tracer(cavity);
        std::vector<std::uint32_t> vertices;
        for (std::size_t v = 0; v < cavity.vertex_count(); v += cavity.vertex_count() / 12)
            vertices.push_back(std::uint32_t(v));
        const std::size_t R = vertices.size();
        const PathTraceIrradiance e =
            path_trace_irradiance(cavity, vertices, 1, light, options(N, 16384), *tracer);
        for (int c = 0; c < 3; ++c)
            for (int b = 1; b <= N; ++b) {
                double mean_deviation = 0, mean_variance = 0;
                for (std::size_t r = 0; r < R; ++r) {
                    const double E0 = e.mean[e.index(r, 0, 0)];
                    const double f = E0 / kPi;
                    EXPECT_NEAR(f, 0.25, 0.03) << r;
                    const double expect = E0 * std::pow(double(rho[c]) * (1 - f), b);
                    const double got = e.mean[e.index(r, b, c)];
                    const double sigma = e.std_error[e.index(r, b, c)];
                    EXPECT_LT(sigma, 0.02 * expect);
                    EXPECT_NEAR(got, expect, 4 * sigma + kFacets * expect)
                        << "receiver " << r << " bounce " << b << " channel " << c;
                    mean_deviation += (got - expect) / expect / double(R);
                    mean_variance += sigma * sigma / (expect * expect) / double(R * R);
                }
                EXPECT_LT(std::abs(mean_deviation), 4 * std::sqrt(mean_variance) + kFacetsMean)
                    << "bounce " << b << " channel " << c;
            }
    }
}

TEST(PathTrace, SameBitsForAnyThreadCountAndReceiverSet) {
    const Mesh cavity = test::spherical_cavity(3, 0.5, {0.8f, 0.5f, 0.2f});
    const auto tracer = make_embree_tracer(cavity);
    const std::vector<double> light = {3.0, 0.5, 1.0, 0.2, 2.0, 0.1, 0.4, 0.3, 1.0, 0.2, 0.2, 0.1};
    const std::vector<std::uint32_t> vertices = {3, 50, 100, 150, 200, 250, 300};
    PathTraceOptions one = options(2, 256);
    one.threads = 1;
    const PathTraceIrradiance a = path_trace_irradiance(cavity, vertices, 4, light, one, *tracer);
    const PathTraceIrradiance b =
        path_trace_irradiance(cavity, vertices, 4, light, options(2, 256), *tracer);
    ASSERT_EQ(a.mean.size(), b.mean.size());
    EXPECT_EQ(std::memcmp(a.mean.data(), b.mean.data(), a.mean.size() * 8), 0);
    EXPECT_EQ(std::memcmp(a.std_error.data(), b.std_error.data(), a.mean.size() * 8), 0);
    EXPECT_EQ(a.rays_cast, b.rays_cast);
    // Vertex 150 alone: the same numbers as among the others.
    const std::vector<std::uint32_t> alone = {150};
    const PathTraceIrradiance c = path_trace_irradiance(cavity, alone, 4, light, one, *tracer);
    for (int bounce = 0; bounce <= 2; ++bounce)
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_EQ(c.mean[c.index(0, bounce, ch)], a.mean[a.index(3, bounce, ch)]);
    // Another seed: other numbers.
    PathTraceOptions other = one;
    other.seed = 6;
    const PathTraceIrradiance d = path_trace_irradiance(cavity, vertices, 4, light, other, *tracer);
    EXPECT_NE(std::memcmp(a.mean.data(), d.mean.data(), a.mean.size() * 8), 0);
}

// The standard errors are what they claim: over independent runs (other seeds), the spread of a
// receiver's estimates matches the standard error each run reports, for each bounce and for the
// partial sums, in a cavity where every bounce and all the randomisation (Sobol at depth 0,
// Philox deeper) matter.
TEST(PathTrace, StandardErrorsMatchTheSpreadOverSeeds) {
    const Mesh cavity = test::spherical_cavity(3, 0.5, {0.8f, 0.6f, 0.4f});
    const auto tracer = make_embree_tracer(cavity);
    const std::vector<double> light = {3.0, 0.5, 1.0, 0.2, 2.0, 0.1, 0.4, 0.3, 1.0, 0.2, 0.2, 0.1};
    std::vector<std::uint32_t> vertices;
    for (std::uint32_t v = 0; v < cavity.vertex_count(); v += 23) vertices.push_back(v);
    constexpr int kRuns = 12, N = 2;
    std::vector<PathTraceIrradiance> runs;
    for (int s = 0; s < kRuns; ++s) {
        PathTraceOptions o = options(N, 128);
        o.seed = 100 + std::uint64_t(s);
        runs.push_back(path_trace_irradiance(cavity, vertices, 4, light, o, *tracer));
    }
    // Per quantity: Σ over receivers and channels of the variance over the runs, and of the mean
    // reported variance; their ratio is 1 for honest standard errors (here within ±30 %: about
    // 60 independent receivers × 11 degrees of freedom, the channels correlated).
    const auto ratio = [&](auto value, auto error) {
        double spread = 0, reported = 0;
        for (std::size_t r = 0; r < vertices.size(); ++r)
            for (int c = 0; c < 3; ++c) {
                double m = 0, m2 = 0, se2 = 0;
                for (const PathTraceIrradiance& e : runs) {
                    const double x = value(e, r, c);
                    m += x / kRuns;
                    m2 += x * x / kRuns;
                    se2 += error(e, r, c) * error(e, r, c) / kRuns;
                }
                spread += (m2 - m * m) * kRuns / (kRuns - 1);
                reported += se2;
            }
        return spread / reported;
    };
    for (int b = 0; b <= N; ++b) {
        SCOPED_TRACE("bounce " + std::to_string(b));
        const double per_bounce = ratio([&](const PathTraceIrradiance& e, std::size_t r,
                                            int c) { return e.mean[e.index(r, b, c)]; },
                                        [&](const PathTraceIrradiance& e, std::size_t r, int c) {
                                            return e.std_error[e.index(r, b, c)];
                                        });
        const double total = ratio(
            [&](const PathTraceIrradiance& e, std::size_t r, int c) { return e.sum(r, 0, b, c); },
            [&](const PathTraceIrradiance& e, std::size_t r, int c) {
                return e.total_std_error[e.index(r, b, c)];
            });
        EXPECT_NEAR(per_bounce, 1.0, 0.3);
        EXPECT_NEAR(total, 1.0, 0.3);
        if (b == 0) continue;
        const double indirect = ratio(
            [&](const PathTraceIrradiance& e, std::size_t r, int c) { return e.sum(r, 1, b, c); },
            [&](const PathTraceIrradiance& e, std::size_t r, int c) {
                return e.indirect_std_error[e.index(r, b, c)];
            });
        EXPECT_NEAR(indirect, 1.0, 0.3);
    }
}

// The brute-force tracer against Embree on builtin:leaky_room (overlapping, coplanar and
// interpenetrating faces): random rays from points in and around the room. They must agree on
// hit or miss and on t, and each one's barycentrics must give the point o + t·d on the triangle it
// reports (Embree's convention: (1 − u − v, u, v) for the triangle's vertices in order). Where
// coplanar faces overlap the two may report different triangles at the same t.
TEST(PathTrace, BruteForceTracerAgreesWithEmbree) {
    const Mesh room = make_builtin("leaky_room");
    const BruteForceTracer brute(room);
    const auto embree = make_embree_tracer(room);
    EXPECT_STREQ(brute.name(), "brute-force");
    EXPECT_GT(brute.memory_bytes(), 0u);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr int kRays = 20000;
    int hits = 0, other_triangle = 0, disagree = 0;
    for (int i = 0; i < kRays; ++i) {
        const Vec3f o{2.3f * u(rng), 1.2f + 1.4f * u(rng), 2.3f * u(rng)};
        Vec3f d{u(rng), u(rng), u(rng)};
        if (length(d) < 0.1f) continue;
        d = normalize(d);
        const Hit a = brute.intersect(o, d, 0.0f, kInf);
        const Hit b = embree->intersect(o, d, 0.0f, kInf);
        std::uint8_t occ_a = 0, occ_b = 0;
        brute.occluded(o, &d, 1, 0.0f, kInf, &occ_a);
        embree->occluded(o, &d, 1, 0.0f, kInf, &occ_b);
        EXPECT_EQ(occ_a, a.hit ? 1 : 0);
        if (a.hit != b.hit || occ_a != occ_b) {
            ++disagree;
            continue;
        }
        if (!a.hit) continue;
        ++hits;
        EXPECT_NEAR(a.t, b.t, 1e-5f * (1 + b.t)) << i;
        if (a.triangle != b.triangle) {
            // A tie: the other triangle lies in the same plane through the same point, or the
            // point is on an edge the two share.
            ++other_triangle;
            const auto& ta = room.triangles[a.triangle];
            const auto& tb = room.triangles[b.triangle];
            const Vec3f na = normalize(cross(room.positions[ta[1]] - room.positions[ta[0]],
                                             room.positions[ta[2]] - room.positions[ta[0]]));
            const Vec3f p = o + d * b.t;
            const bool coplanar =
                std::abs(dot(na, p - room.positions[tb[0]])) < 1e-5f &&
                std::abs(dot(na, room.positions[tb[1]] - room.positions[tb[0]])) < 1e-5f &&
                std::abs(dot(na, room.positions[tb[2]] - room.positions[tb[0]])) < 1e-5f;
            const bool on_edge = std::min({a.u, a.v, 1 - a.u - a.v}) < 1e-4f;
            EXPECT_TRUE(coplanar || on_edge) << i;
        }
        for (const Hit& h : {a, b}) {
            const auto& tri = room.triangles[h.triangle];
            const Vec3f p = room.positions[tri[0]] * (1 - h.u - h.v) +
                            room.positions[tri[1]] * h.u + room.positions[tri[2]] * h.v;
            EXPECT_LT(length(p - (o + d * h.t)), 1e-4f) << i;
        }
        if (a.triangle == b.triangle) {
            EXPECT_NEAR(a.u, b.u, 1e-4f) << i;
            EXPECT_NEAR(a.v, b.v, 1e-4f) << i;
        }
    }
    EXPECT_GT(hits, kRays / 2);
    EXPECT_EQ(disagree, 0);  // no ray grazes an edge closely enough to differ in float
    EXPECT_LT(other_triangle, hits / 20);  // the slabs' overlap and their edges
    // Limits: the hit must lie inside (tnear, tfar).
    const Hit far = brute.intersect({0, 1, 0}, {0, -1, 0}, 0.0f, 0.5f);
    EXPECT_FALSE(far.hit);
    const Hit floor = brute.intersect({0, 1, 0}, {0, -1, 0}, 0.0f, 1.5f);
    ASSERT_TRUE(floor.hit);
    EXPECT_FLOAT_EQ(floor.t, 1.0f);
}

TEST(PathTrace, RejectsBadInput) {
    const Mesh plane = open_plane(2);
    const BruteForceTracer tracer(plane);
    const std::vector<double> light(3, 1.0);
    const std::vector<std::uint32_t> ok = {0};
    const auto run = [&](const Mesh& m, std::vector<std::uint32_t> v, int K,
                         const std::vector<double>& l, const PathTraceOptions& o) {
        return path_trace_irradiance(m, v, K, l, o, tracer);
    };
    EXPECT_NO_THROW(run(plane, ok, 1, light, options(1, 32)));
    EXPECT_THROW(run(plane, {9}, 1, light, options(1, 32)), Error);
    EXPECT_THROW(run(plane, ok, 0, {}, options(1, 32)), Error);
    EXPECT_THROW(run(plane, ok, 4, light, options(1, 32)), Error);
    EXPECT_THROW(run(plane, ok, 1, {1.0, std::nan(""), 1.0}, options(1, 32)), Error);
    EXPECT_THROW(run(plane, ok, 1, light, options(-1, 32)), Error);
    EXPECT_THROW(run(plane, ok, 1, light, options(kMaxPathTraceBounces + 1, 32)), Error);
    EXPECT_THROW(run(plane, ok, 1, light, options(1, 0)), Error);
    EXPECT_THROW(run(plane, ok, 1, light, options(1, 16)), Error);  // under two replicates
    EXPECT_THROW(run(plane, ok, 1, light, options(1, 40)), Error);  // not a multiple of 16
    const std::vector<std::vector<double>> none;
    EXPECT_THROW(path_trace_irradiance(plane, ok, 1, none, options(1, 32), tracer), Error);
    PathTraceOptions o = options(1, 32);
    o.escape_rays = 0;
    EXPECT_THROW(run(plane, ok, 1, light, o), Error);
    o.escape_rays = kMaxPathTraceEscapeRays + 1;
    EXPECT_THROW(run(plane, ok, 1, light, o), Error);
    Mesh no_albedo = plane;
    no_albedo.albedo.pop_back();
    EXPECT_THROW(run(no_albedo, ok, 1, light, options(1, 32)), Error);
    // Cancelling.
    o = options(1, 32);
    o.progress = [](const ProgressInfo&) { return false; };
    try {
        run(plane, ok, 1, light, o);
        FAIL() << "not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::cancelled);
    }
}

}  // namespace
}  // namespace shprt
