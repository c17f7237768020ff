// Glossy transfer matrices (TransferKind::glossy): the SGEMM on the pair-product table against
// the slow double-precision reference, against the analytic hemisphere matrix of an unoccluded
// receiver, and determinism.
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace shprt {
namespace {

// Float rounding of sums of ~S products of size ≤ 1 (|y_i y_j| ≤ (2l+1)/(4π) ≲ 0.6 for l < 4).
constexpr double kReferenceTolerance = 2e-5;

BakeOptions glossy_options(int K, std::uint32_t samples) {
    BakeOptions o;
    o.transfer = TransferKind::glossy;
    o.K = K;
    o.samples = samples;
    o.seed = 3;
    o.threads = 2;
    return o;
}

// H(n)_ij = ∫_{n·ω>0} y_i(ω) y_j(ω) dω, in double, by exact product quadrature in n's frame
// (Gauss–Legendre in cos θ on [0, 1] × uniform φ): the integrand is a polynomial there.
std::vector<double> hemisphere_matrix(int K, Vec3d n) {
    const int bands = sh_bands_for(K);
    const DirectionSetD q = gauss_legendre_set_d(2 * bands + 2, 4 * bands + 2);
    // Only the upper half of the set (z > 0) with doubled weights would not be exact (the GL
    // nodes are on [−1, 1]); instead map each node's z to (z + 1)/2 on [0, 1], weight / 2.
    Vec3d t = std::fabs(n.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    const Vec3d u = normalize(cross(t, n));
    const Vec3d v = cross(n, u);
    std::vector<double> H(std::size_t(K) * K, 0.0), y(K);
    for (std::size_t s = 0; s < q.size(); ++s) {
        const double x0 = q.dirs[3 * s], y0 = q.dirs[3 * s + 1], z0 = q.dirs[3 * s + 2];
        const double rho0 = std::sqrt(std::max(0.0, 1 - z0 * z0));
        const double z = 0.5 * (z0 + 1);
        const double rho = std::sqrt(std::max(0.0, 1 - z * z));
        const double cx = rho0 > 0 ? x0 / rho0 : 1, cy = rho0 > 0 ? y0 / rho0 : 0;
        const Vec3d w = u * (rho * cx) + v * (rho * cy) + n * z;
        sh_eval_k<double>(K, w.x, w.y, w.z, y.data());
        const double weight = 0.5 * q.weights[s];
        for (int i = 0; i < K; ++i)
            for (int j = 0; j < K; ++j) H[std::size_t(i) * K + j] += weight * y[i] * y[j];
    }
    return H;
}

double packed(const float* row, int K, int i, int j) {
    if (i > j) std::swap(i, j);
    // Row i of the upper triangle starts after i rows of lengths K, K−1, ...
    return row[std::size_t(i) * K - std::size_t(i) * (i - 1) / 2 + (j - i)];
}

TEST(GlossyBake, LayoutIsOneSymmetricMatrixPerVertex) {
    const Mesh plane = make_builtin("plane");
    const TransferSet t = bake(plane, glossy_options(9, 64));
    EXPECT_EQ(t.kind, TransferKind::glossy);
    EXPECT_EQ(t.layout.shape, TransferShape::symmetric_matrix);
    EXPECT_EQ(t.layout.channels, 1);
    EXPECT_EQ(t.layout.floats_per_receiver(), 45u);
    EXPECT_EQ(t.coeffs.size(), plane.vertex_count() * 45);
}

TEST(GlossyBake, AnalyticHemisphereMatrixSumsToTheIdentityWithItsOpposite) {
    // The oracle's own check: the two hemispheres of any axis tile the sphere, and the SH basis
    // is orthonormal on it.
    const int K = 16;
    const Vec3d n = normalize(Vec3d{0.3, 0.8, -0.2});
    const std::vector<double> a = hemisphere_matrix(K, n), b = hemisphere_matrix(K, n * -1.0);
    for (int i = 0; i < K; ++i)
        for (int j = 0; j < K; ++j)
            EXPECT_NEAR(a[i * K + j] + b[i * K + j], i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;
}

TEST(GlossyBake, UnoccludedVertexMatrixIsTheProjectedHemisphereIdentity) {
    // Every vertex of the plane sees its whole hemisphere: M = H(n), the identity restricted to
    // the hemisphere (projected to K), to Monte Carlo precision (Sobol, S = 8192).
    const int K = 16;
    const Mesh plane = make_builtin("plane");
    const TransferSet t = bake(plane, glossy_options(K, 8192));
    const std::vector<double> H = hemisphere_matrix(K, Vec3d{0, 1, 0});
    double worst = 0;
    for (std::size_t v = 0; v < plane.vertex_count(); v += 37)
        for (int i = 0; i < K; ++i)
            for (int j = 0; j < K; ++j)
                worst = std::max(worst, std::fabs(packed(t.receiver(v), K, i, j) - H[i * K + j]));
    EXPECT_LT(worst, 2e-3);  // Sobol at S = 8192: measured ~4e-4 for this discontinuous integrand
}

TEST(GlossyBake, FastPathEqualsTheSlowReferenceWithOcclusion) {
    const Mesh scene = make_builtin("box_on_plane");
    const BakeOptions options = glossy_options(9, 256);
    const DirectionSet set = make_direction_set(options.sampler, options.seed, options.samples);
    const auto tracer = make_embree_tracer(scene);
    const TransferSet fast = bake_with_tracer(scene, options, set, *tracer);
    const TransferSet slow = bake_reference(scene, options, set, *tracer);
    ASSERT_EQ(fast.coeffs.size(), slow.coeffs.size());
    double worst = 0;
    for (std::size_t i = 0; i < fast.coeffs.size(); ++i)
        worst = std::max(worst, std::fabs(double(fast.coeffs[i]) - slow.coeffs[i]));
    EXPECT_LT(worst, kReferenceTolerance);
    // Occlusion happened: some vertex's M_00 (the visible solid angle / 4π) is below 1/2.
    double least = 1;
    for (std::size_t v = 0; v < scene.vertex_count(); ++v)
        least = std::min(least, double(fast.receiver(v)[0]));
    EXPECT_LT(least, 0.4);
}

TEST(GlossyBake, SameBitsWithAnyThreadCount) {
    const Mesh scene = make_builtin("box_on_plane");
    BakeOptions one = glossy_options(16, 128), two = one;
    one.threads = 1;
    two.threads = 2;
    EXPECT_EQ(bake(scene, one).coeffs, bake(scene, two).coeffs);
}

TEST(GlossyBake, RefusesTooManyBands) {
    const Mesh plane = make_builtin("plane");
    try {
        bake(plane, glossy_options(81, 16));
        FAIL() << "81 coefficients (9 bands) should be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        EXPECT_NE(std::string(e.what()).find("too large"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace shprt
