// The bake against closed forms: an unoccluded plane and a sphere (transfer = the clamped cosine
// rotated to the normal), and a vertex deep in an inner 90° corner (the occluded part of its
// cosine-weighted hemisphere is the form factor of the walls, Lambert's polygon formula).
#include "bake/bake_test_util.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/sh/zonal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace shprt {
namespace {

// A bake with a quadrature set against `project` of the same function on the same set: only
// float rounding separates them (W and Y in float, an S-term float dot product).
constexpr double kQuadratureTolerance = 1e-5;
// Monte Carlo estimates must lie within this many standard deviations of the truth.
constexpr double kSigmas = 5.0;

double clamped_cosine(const Vec3d& n, const Vec3d& w) { return std::max(0.0, dot(n, w)); }

// Checks every vertex of `mesh` against project(max(0, n·w)) on the same quadrature set.
void expect_clamped_cosine_projection(const Mesh& mesh, const TransferSet& t,
                                      const DirectionSet& set) {
    ASSERT_EQ(t.receiver_count(), mesh.vertex_count());
    int failures = 0;
    for (std::size_t v = 0; v < mesh.vertex_count() && failures < 5; ++v) {
        const Vec3d n = cast<double>(mesh.normals[v]);
        const std::vector<double> expected =
            project([&](const Vec3d& w) { return clamped_cosine(n, w); }, t.layout.K, set);
        for (int i = 0; i < t.layout.K; ++i) {
            if (std::fabs(t.receiver(v)[i] - expected[i]) > kQuadratureTolerance) {
                ADD_FAILURE() << "vertex " << v << " coefficient " << i << ": " << t.receiver(v)[i]
                              << " vs " << expected[i];
                ++failures;
            }
        }
    }
}

TEST(BakePlane, QuadratureSetGivesTheProjectedClampedCosine) {
    const Mesh plane = make_builtin("plane");
    const DirectionSet set = quadrature_set_for_bands(12);
    for (TransferKind kind : {TransferKind::shadowed, TransferKind::unshadowed}) {
        SCOPED_TRACE(to_string(kind));
        BakeOptions options;
        options.K = 16;
        options.transfer = kind;
        const TransferSet t = bake(plane, options, set);
        EXPECT_EQ(t.layout.K, 16);
        EXPECT_EQ(t.samples, int(set.size()));
        expect_clamped_cosine_projection(plane, t, set);
    }
}

TEST(BakePlane, UniformMonteCarloIsWithinStatisticalErrorOfTheAnalyticTransfer) {
    const Mesh plane = make_builtin("plane");
    constexpr int kBands = 4, K = kBands * kBands;
    constexpr std::uint32_t S = 4096;
    BakeOptions options;
    options.K = K;
    options.samples = S;
    options.sampler = SamplerKind::uniform;
    options.seed = 7;
    const TransferSet t = bake(plane, options);
    EXPECT_EQ(t.samples, int(S));

    const std::vector<double> zonal = clamped_cosine_zonal(kBands);
    // The per-sample variance of (4π)·f·y_i, from a dense quadrature of f²·y_i² (f² is C¹).
    const DirectionSetD dense = quadrature_set_for_bands_d(96);
    const Vec3d n = cast<double>(plane.normals[0]);
    std::vector<double> exact(K), second_moment(K, 0.0), y(K);
    rotate_zonal(zonal.data(), K, n, exact.data());
    for (std::size_t s = 0; s < dense.size(); ++s) {
        const Vec3d w{dense.dirs[3 * s], dense.dirs[3 * s + 1], dense.dirs[3 * s + 2]};
        const double f = clamped_cosine(n, w);
        sh_eval_k(K, w.x, w.y, w.z, y.data());
        for (int i = 0; i < K; ++i) second_moment[i] += dense.weights[s] * f * f * y[i] * y[i];
    }
    for (std::size_t v = 0; v < plane.vertex_count(); ++v) {
        ASSERT_EQ(plane.normals[v], plane.normals[0]) << "the plane has one normal";
        for (int i = 0; i < K; ++i) {
            const double sigma =
                std::sqrt(std::max(0.0, 4 * kPi * second_moment[i] - exact[i] * exact[i]) / S);
            ASSERT_NEAR(t.receiver(v)[i], exact[i], kSigmas * sigma)
                << "vertex " << v << " coefficient " << i;
        }
    }
    // Irradiance under constant unit light is π for an unoccluded plane: c_0·√(4π).
    EXPECT_NEAR(t.receiver(0)[0] * std::sqrt(4 * kPi), kPi, kSigmas * 4 * kPi / std::sqrt(6.0 * S));
}

TEST(BakeSphere, EveryVertexSeesTheClampedCosineAndShadowedEqualsUnshadowed) {
    const Mesh sphere = make_builtin("sphere");
    const DirectionSet set = quadrature_set_for_bands(10);
    BakeOptions options;
    options.K = 16;
    options.transfer = TransferKind::shadowed;
    const TransferSet shadowed = bake(sphere, options, set);
    options.transfer = TransferKind::unshadowed;
    const TransferSet unshadowed = bake(sphere, options, set);
    EXPECT_EQ(unshadowed.stats.rays_cast, 0u);
    EXPECT_GT(shadowed.stats.rays_cast, 0u);
    // A convex object never occludes itself: every cast ray escapes, W is the same, and so are
    // the coefficients, bit for bit.
    ASSERT_EQ(shadowed.coeffs.size(), unshadowed.coeffs.size());
    std::size_t differing = 0;
    for (std::size_t k = 0; k < shadowed.coeffs.size(); ++k)
        differing += shadowed.coeffs[k] != unshadowed.coeffs[k];
    EXPECT_EQ(differing, 0u) << "of " << shadowed.coeffs.size() << " coefficients";
    expect_clamped_cosine_projection(sphere, shadowed, set);
}

// Form factor from a differential area at p (unit normal n) to a planar polygon (Lambert's
// contour formula): F = |Σ_i Θ_i · n·Γ_i| / (2π), with Θ_i the angle edge (q_i, q_i+1) subtends
// at p and Γ_i the unit normal of the plane through p and that edge. Exact for a polygon in the
// closed upper hemisphere of p; F is the fraction of the cosine-weighted hemisphere it covers.
double polygon_form_factor(Vec3d p, Vec3d n, const std::vector<Vec3d>& polygon) {
    double sum = 0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const Vec3d a = normalize(polygon[i] - p);
        const Vec3d b = normalize(polygon[(i + 1) % polygon.size()] - p);
        const Vec3d g = cross(a, b);
        const double len = length(g);
        if (len == 0) continue;
        sum += std::acos(std::clamp(dot(a, b), -1.0, 1.0)) * dot(n, g / len);
    }
    return std::fabs(sum) / (2 * kPi);
}

TEST(BakeCorner, LambertFormulaOracleGivesOneHalfForAnInfiniteWall) {
    // An (effectively) infinite wall rising from the line through p's tangent plane covers half
    // of the cosine-weighted hemisphere, by symmetry.
    constexpr double kBig = 1e6;
    const std::vector<Vec3d> wall = {
        {0, 0, -kBig}, {0, kBig, -kBig}, {0, kBig, kBig}, {0, 0, kBig}};
    EXPECT_NEAR(polygon_form_factor({0.1, 0, 0}, {0, 1, 0}, wall), 0.5, 1e-6);
}

TEST(BakeCorner, VertexDeepInTheCornerHasTheAnalyticOccludedFraction) {
    // Floor [0,A]² at y = 0 (normal +Y) fanned around the vertex c = (d, 0, d); walls x = 0
    // (normal +X) and z = 0 (normal +Z), both A wide and H high, meeting the floor and each
    // other at the corner. Nothing else: the sky is visible over and beside the walls.
    constexpr float A = 1.0f, H = 1.0f, d = 0.1f;
    Mesh m;
    m.source = "test:corner";
    const Vec3f up{0, 1, 0};
    const Vec3f c{d, 0, d};
    const Vec3f floor_corners[4] = {{0, 0, 0}, {0, 0, A}, {A, 0, A}, {A, 0, 0}};  // CCW from +Y
    m.positions.push_back(c);
    m.normals.push_back(up);
    m.albedo.push_back({0.5f, 0.5f, 0.5f});
    for (Vec3f q : floor_corners) {
        m.positions.push_back(q);
        m.normals.push_back(up);
        m.albedo.push_back({0.5f, 0.5f, 0.5f});
    }
    for (std::uint32_t i = 0; i < 4; ++i) m.triangles.push_back({0, 1 + i, 1 + (i + 1) % 4});
    test::add_quad(m, {0, 0, 0}, {0, 0, A}, {0, H, A}, {0, H, 0}, {1, 0, 0});
    test::add_quad(m, {0, 0, 0}, {0, H, 0}, {A, H, 0}, {A, 0, 0}, {0, 0, 1});

    const Vec3d p = cast<double>(c), n{0, 1, 0};
    const double F_x = polygon_form_factor(p, n, {{0, 0, 0}, {0, 0, A}, {0, H, A}, {0, H, 0}});
    const double F_z = polygon_form_factor(p, n, {{0, 0, 0}, {0, H, 0}, {A, H, 0}, {A, 0, 0}});
    EXPECT_NEAR(F_x, F_z, 1e-12) << "c is on the diagonal: both walls look the same";
    const double occluded = F_x + F_z;
    // Infinite walls would leave only the quadrant x > 0, z > 0 of the hemisphere (by symmetry
    // 1/4 of the cosine-weighted hemisphere): hidden 3/4; one infinite wall hides 1/2.
    ASSERT_GT(occluded, 0.5) << "deep in the corner, the walls hide more than one wall would";
    ASSERT_LT(occluded, 0.75) << "finite walls hide less than infinite ones";

    constexpr std::uint32_t S = 1u << 20;
    BakeOptions options;
    options.K = 4;
    options.samples = S;
    options.seed = 3;
    const TransferSet t = bake(m, options);
    // Under constant unit light (coefficient √(4π) on y_0, 0 elsewhere) the irradiance is
    // E = c_0·√(4π) = ∫ V·max(0, n·w) dω = π·(1 − occluded fraction).
    const double E = t.receiver(0)[0] * std::sqrt(4 * kPi);
    const double expected = kPi * (1 - occluded);
    // Var(Ê) = (4π·∫V cos² dω − E²)/S ≤ 4π·(2π/3)/S.
    const double sigma = std::sqrt(4 * kPi * (2 * kPi / 3) / S);
    EXPECT_NEAR(E, expected, kSigmas * sigma) << "occluded fraction " << occluded;
    // And it is clearly not the unoccluded value: the test can fail.
    EXPECT_GT(kPi - E, 10 * kSigmas * sigma);
}

TEST(BakeCorner, BuiltinCornerProbeMatchesItsAnalyticOcclusion) {
    const Mesh corner = make_builtin("corner");
    std::size_t probe = corner.vertex_count();
    for (std::size_t v = 0; v < corner.vertex_count(); ++v)
        if (corner.positions[v] == kCornerProbe && corner.normals[v] == Vec3f{0, 1, 0}) probe = v;
    ASSERT_LT(probe, corner.vertex_count()) << "builtin:corner has its probe vertex";
    constexpr std::uint32_t S = 1u << 14;
    BakeOptions options;
    options.K = 1;
    options.samples = S;
    options.seed = 9;
    const TransferSet t = bake(corner, options);
    const double E = t.receiver(probe)[0] * std::sqrt(4 * kPi);
    const double occluded = corner_occlusion(kCornerProbe.x, kCornerProbe.z).cosine;
    const double sigma = std::sqrt(4 * kPi * (2 * kPi / 3) / S);
    EXPECT_NEAR(E, kPi * (1 - occluded), kSigmas * sigma) << "occluded fraction " << occluded;
    EXPECT_GT(kPi - E, 4 * kSigmas * sigma) << "clearly not the unoccluded value";
}

}  // namespace
}  // namespace shprt
