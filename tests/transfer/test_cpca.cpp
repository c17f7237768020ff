// Clustered PCA of transfer rows (transfer/cpca.hpp) on synthetic sets: exact reconstruction at
// full rank or one cluster per receiver, error falling with more vectors, determinism across
// thread counts, and the one-line refusals.
#include "shprt/transfer/cpca.hpp"

#include "shprt/core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace shprt {
namespace {

// `n` symmetric K×K matrices (packed): a few clusters of low-rank variation plus noise.
TransferSet synthetic(std::size_t n, int K, unsigned seed) {
    TransferInfo info;
    info.kind = TransferKind::glossy;
    info.layout.K = K;
    info.layout.shape = TransferShape::symmetric_matrix;
    TransferSet t = TransferSet::zeros(info, n);
    const std::size_t D = info.layout.floats_per_receiver();
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<float> centres(4 * D), dirs(4 * 3 * D);
    for (float& x : centres) x = g(rng);
    for (float& x : dirs) x = g(rng);
    for (std::size_t r = 0; r < n; ++r) {
        const std::size_t c = r % 4;
        const float a = g(rng), b = g(rng), e = g(rng);
        for (std::size_t d = 0; d < D; ++d)
            t.coeffs[r * D + d] = centres[c * D + d] + a * dirs[(c * 3 + 0) * D + d] +
                                  0.3f * b * dirs[(c * 3 + 1) * D + d] +
                                  0.1f * e * dirs[(c * 3 + 2) * D + d] + 0.01f * g(rng);
    }
    return t;
}

std::vector<Vec3f> up_normals(std::size_t n) { return std::vector<Vec3f>(n, Vec3f{0, 1, 0}); }

double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
    double worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        worst = std::max(worst, double(std::fabs(a[i] - b[i])));
    return worst;
}

TEST(Cpca, OneClusterPerReceiverReproducesTheInputExactly) {
    const TransferSet t = synthetic(40, 4, 1);
    const std::size_t D = t.layout.floats_per_receiver();
    CpcaOptions o;
    o.clusters = 40;
    o.vectors = int(D);
    const CpcaCode code = compress_cpca(t, o);
    std::vector<float> rows;
    reconstruct_cpca(code, D, rows);
    EXPECT_EQ(rows, t.coeffs);  // every mean is its one member, bit for bit
}

TEST(Cpca, OneClusterPerReceiverSeparatesNearlyEqualRows) {
    // Rows of norm ~300 that differ by 0.01 in one float, and exact repeats: in float the
    // expanded distance ‖x‖² − 2x·c + ‖c‖² rounds by more than the true distances (1e-4), so
    // the nearest centre must be settled exactly, or rows share a cluster and one vector
    // cannot rebuild them.
    TransferInfo info;
    info.kind = TransferKind::glossy;
    info.layout.K = 4;
    info.layout.shape = TransferShape::symmetric_matrix;
    const std::size_t D = info.layout.floats_per_receiver();
    const std::size_t n = 24;
    TransferSet t = TransferSet::zeros(info, n);
    for (std::size_t r = 0; r < n; ++r) {
        for (std::size_t d = 0; d < D; ++d) t.coeffs[r * D + d] = 100.0f + float(d);
        if (r % 8 != 0) t.coeffs[r * D + (r % 8) % D] += 0.01f * float(r / 8 + 1);
    }
    CpcaOptions o;
    o.clusters = int(n);
    o.vectors = 1;
    for (int threads : {1, 2}) {
        o.threads = threads;
        const CpcaCode code = compress_cpca(t, o);
        std::vector<float> rows;
        reconstruct_cpca(code, D, rows);
        EXPECT_EQ(rows, t.coeffs) << threads << " threads";
    }
}

TEST(Cpca, FullRankOneClusterReproducesTheInputToRounding) {
    const TransferSet t = synthetic(60, 4, 2);
    const std::size_t D = t.layout.floats_per_receiver();  // 10 (K² = 16 for the full matrix)
    CpcaOptions o;
    o.clusters = 1;
    o.vectors = int(D);
    const CpcaCode code = compress_cpca(t, o);
    std::vector<float> rows;
    reconstruct_cpca(code, D, rows);
    EXPECT_LT(max_abs_diff(rows, t.coeffs), 1e-4);
    o.vectors = int(D) - 3;  // below the rank: not exact
    std::vector<float> fewer;
    reconstruct_cpca(compress_cpca(t, o), D, fewer);
    EXPECT_GT(max_abs_diff(fewer, t.coeffs), 1e-3);
}

TEST(Cpca, ErrorFallsMonotonicallyWithMoreVectorsAndMoreClusters) {
    const TransferSet t = synthetic(400, 5, 3);
    const std::vector<Vec3f> normals = up_normals(400);
    double previous = 1e30;
    for (int vectors : {1, 2, 3, 5, 8}) {
        CpcaOptions o;
        o.clusters = 4;
        o.vectors = vectors;
        const double e = compress_transfer(t, normals, o, false).error.relative_rmse;
        EXPECT_LT(e, previous) << vectors << " vectors";
        previous = e;
    }
    previous = 1e30;
    for (int clusters : {1, 2, 4, 16, 64}) {
        CpcaOptions o;
        o.clusters = clusters;
        o.vectors = 1;
        const double e = compress_transfer(t, normals, o, false).error.relative_rmse;
        EXPECT_LT(e, previous) << clusters << " clusters";
        previous = e;
    }
}

TEST(Cpca, SameBitsWithAnyThreadCountAndSeedMatters) {
    const TransferSet t = synthetic(700, 4, 4);
    CpcaOptions a;
    a.clusters = 9;
    a.vectors = 3;
    a.threads = 1;
    CpcaOptions b = a;
    b.threads = 2;
    const CpcaCode ca = compress_cpca(t, a), cb = compress_cpca(t, b);
    EXPECT_EQ(ca.cluster, cb.cluster);
    EXPECT_EQ(ca.basis, cb.basis);
    EXPECT_EQ(ca.weights, cb.weights);
    b.seed = 99;
    EXPECT_NE(compress_cpca(t, b).cluster, ca.cluster);
}

TEST(Cpca, WorksOnDiffuseVectors) {
    TransferInfo info;
    info.layout.K = 9;
    TransferSet t = TransferSet::zeros(info, 50);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1, 1);
    for (float& x : t.coeffs) x = u(rng);
    CpcaOptions o;
    o.clusters = 50;
    o.vectors = 9;
    std::vector<float> rows;
    reconstruct_cpca(compress_cpca(t, o), 9, rows);
    EXPECT_EQ(rows, t.coeffs);
    const CpcaResult r = compress_transfer(t, up_normals(50), o, false);
    EXPECT_EQ(r.error.relative_rmse, 0.0);
}

// The error under a given light (`shprt compress --light`): an approximation that is the exact
// rows × 1.01 is 1 % off under any light, matrices or vectors, RGB light on grey rows or on RGB
// rows; a colour the transfer is not lit by changes nothing; the light's size is checked.
TEST(Cpca, TheErrorUnderAGivenLightIsItsRelativeRmse) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.1f, 1);
    for (const bool matrices : {true, false})
        for (const int channels : {1, 3}) {
            TransferSet exact = synthetic(40, 9, 7);
            if (!matrices || channels == 3) {
                TransferInfo info;
                info.layout.K = 9;
                info.layout.channels = channels;
                if (matrices) {
                    info.kind = TransferKind::glossy;
                    info.layout.shape = TransferShape::symmetric_matrix;
                }
                exact = TransferSet::zeros(info, 40);
                for (float& x : exact.coeffs) x = u(rng);
            }
            TransferSet approx = exact;
            for (float& x : approx.coeffs) x *= 1.01f;
            std::vector<float> light(27);
            for (float& x : light) x = u(rng);
            const TransferError e = transfer_error(exact, approx, up_normals(40), light);
            EXPECT_NEAR(e.relative_rmse, 0.01, 1e-5) << matrices << " " << channels;
            EXPECT_EQ(transfer_error(exact, exact, up_normals(40), light).relative_rmse, 0.0);
            // Only channel 0's rows off, and a light that is red only: 1 % for RGB rows (the
            // red channel), 1 % for grey ones (lit by the red part).
            TransferSet red_off = exact;
            for (std::size_t r = 0; r < 40; ++r)
                for (std::size_t i = 0; i < exact.layout.floats_per_channel(); ++i)
                    red_off.receiver(r, 0)[i] *= 1.01f;
            std::vector<float> red(27, 0.0f);
            for (int i = 0; i < 9; ++i) red[std::size_t(i)] = light[std::size_t(i)];
            EXPECT_NEAR(transfer_error(exact, red_off, up_normals(40), red).relative_rmse, 0.01,
                        1e-5);
            // ... and a light without red does not see the red channel's error (RGB rows).
            std::vector<float> green_blue = light;
            for (int i = 0; i < 9; ++i) green_blue[std::size_t(i)] = 0;
            if (channels == 3)
                EXPECT_EQ(transfer_error(exact, red_off, up_normals(40), green_blue).relative_rmse,
                          0.0);
            EXPECT_THROW(transfer_error(exact, approx, up_normals(40),
                                        std::vector<float>(light.begin(), light.begin() + 9)),
                         Error);
        }
}

// An interreflected set's direct part goes with the code as it is (rounded to float16 with half),
// so that a compressed file still shows "direct only".
TEST(Cpca, TheDirectPartIsKept) {
    TransferInfo info;
    info.kind = TransferKind::interreflected;
    info.layout.K = 4;
    info.layout.channels = 3;
    TransferSet t = TransferSet::zeros(info, 20);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0, 1);
    for (float& x : t.coeffs) x = u(rng);
    t.direct.resize(20 * 4);
    for (float& x : t.direct) x = u(rng);
    CpcaOptions o;
    o.clusters = 3;
    o.vectors = 2;
    const CpcaResult f32 = compress_transfer(t, up_normals(20), o, false);
    EXPECT_EQ(f32.compressed.direct, t.direct);
    EXPECT_EQ(f32.direct_bytes_per_receiver, 16.0);
    const CpcaResult f16 = compress_transfer(t, up_normals(20), o, true);
    ASSERT_EQ(f16.compressed.direct.size(), t.direct.size());
    EXPECT_LT(max_abs_diff(f16.compressed.direct, t.direct), 1e-3);
    EXPECT_EQ(f16.direct_bytes_per_receiver, 8.0);
    EXPECT_EQ(f16.compressed.direct_only().coeffs, f16.compressed.direct);
}

// validate (cpca_code.hpp): no code passes; a code passes only with every array the size its
// clusters, vectors, rows and D say, and every row's cluster below the clusters.
TEST(Cpca, ACodeIsCheckedAgainstItsRowsAndFloats) {
    EXPECT_NO_THROW(validate(CpcaCode{}, 5, 9));
    CpcaCode code;
    code.clusters = 2;
    code.vectors = 1;
    code.cluster = {0, 1, 1};
    code.weights.assign(3, 0.5f);
    code.means.assign(2 * 4, 0.0f);
    code.basis.assign(2 * 1 * 4, 1.0f);
    EXPECT_NO_THROW(validate(code, 3, 4));
    const auto message = [](const CpcaCode& c, std::size_t rows, std::size_t D) {
        try {
            validate(c, rows, D);
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    EXPECT_NE(message(code, 4, 4).find("does not fit: 2 clusters, 1 vectors, 3 rows for 4, D = 4"),
              std::string::npos);
    EXPECT_NE(message(code, 3, 5).find("does not fit"), std::string::npos);
    CpcaCode bad = code;
    bad.cluster[1] = 2;
    EXPECT_NE(message(bad, 3, 4).find("CPCA cluster 2 of receiver 1 is not below 2"),
              std::string::npos);
    bad = CpcaCode{};
    bad.weights = {1.0f};  // arrays with no clusters: not "no code"
    EXPECT_NE(message(bad, 0, 4).find("does not fit"), std::string::npos);
}

TEST(Cpca, BadParametersAreRefused) {
    const TransferSet t = synthetic(10, 3, 6);
    for (auto [clusters, vectors] : {std::pair{0, 1}, {11, 1}, {2, 0}, {2, 7}}) {
        CpcaOptions o;
        o.clusters = clusters;
        o.vectors = vectors;
        EXPECT_THROW(compress_cpca(t, o), Error) << clusters << "," << vectors;
    }
}

// Transfer probes compressed (compress_probes): a 4×3×2 grid of RGB 9×9 matrices drawn from
// three well-separated families of rank one, probes 4 and 17 invalid.
ProbeGrid synthetic_probes() {
    ProbeGrid g;
    g.counts = {4, 3, 2};
    g.K = 9;
    g.channels = 3;
    g.valid.assign(g.count(), 1);
    g.valid[4] = g.valid[17] = 0;
    const std::size_t D = 3 * 81;
    g.matrices.assign(g.count() * D, 0.0f);
    std::mt19937 rng(11);
    std::normal_distribution<float> n(0.0f, 1.0f);
    std::vector<float> base(3 * D), dir(3 * D);
    for (float& x : base) x = n(rng);
    for (float& x : dir) x = n(rng);
    for (std::size_t p = 0; p < g.count(); ++p) {
        if (!g.valid[p]) continue;
        const std::size_t f = p % 3;
        const float a = n(rng);
        for (std::size_t d = 0; d < D; ++d)
            g.matrices[p * D + d] = 5.0f * base[f * D + d] + a * dir[f * D + d] + 0.01f * n(rng);
    }
    return g;
}

TEST(CpcaProbes, OneClusterPerValidProbeIsExactAndFewerAreClose) {
    const ProbeGrid g = synthetic_probes();
    CpcaOptions options;
    options.clusters = 22;  // the valid probes
    options.vectors = 1;
    const ProbeCpcaResult exact = compress_probes(g, options);
    EXPECT_LT(max_abs_diff(exact.compressed.matrices, g.matrices), 1e-5);
    EXPECT_LT(exact.relative_rmse, 1e-6);
    // Three families of rank one (plus 1 % noise): 3 clusters × 1 vector hold them to the noise.
    options.clusters = 3;
    const std::vector<float> light(3 * 9, 0.5f);
    const ProbeCpcaResult r = compress_probes(g, options, &light);
    EXPECT_GT(r.relative_rmse, 1e-4);
    EXPECT_LT(r.relative_rmse, 0.02);
    ASSERT_TRUE(r.light_relative_rmse.has_value());
    EXPECT_GT(*r.light_relative_rmse, 0.0);
    EXPECT_LT(*r.light_relative_rmse, 0.05);
    EXPECT_EQ(r.compressed.cpca.cluster.size(), 22u);
    for (const std::size_t invalid : {4u, 17u})
        for (std::size_t d = 0; d < 3 * 81; ++d)
            EXPECT_EQ(r.compressed.matrices[invalid * 3 * 81 + d], 0.0f);
    EXPECT_LT(r.bytes_per_probe, r.raw_bytes_per_probe);
    EXPECT_NO_THROW(r.compressed.validate());
    // The same code from any thread count.
    options.threads = 1;
    const ProbeCpcaResult one = compress_probes(g, options);
    options.threads = 2;
    EXPECT_TRUE(one.compressed == compress_probes(g, options).compressed);
}

TEST(CpcaProbes, BadRequestsNameTheirParameter) {
    const ProbeGrid g = synthetic_probes();
    const auto message = [&](int clusters, int vectors, const ProbeGrid& grid) {
        CpcaOptions options;
        options.clusters = clusters;
        options.vectors = vectors;
        try {
            compress_probes(grid, options);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message(23, 1, g).find("clusters = 23 must be 1 to the valid probes, 22"),
              std::string::npos);
    EXPECT_NE(message(2, 244, g).find("vectors = 244 must be 1 to 243"), std::string::npos);
    EXPECT_NE(message(1, 1, ProbeGrid{}).find("the file has no probes"), std::string::npos);
    ProbeGrid none = g;
    std::fill(none.valid.begin(), none.valid.end(), 0);
    EXPECT_NE(message(1, 1, none).find("no probe is valid"), std::string::npos);
    // A code that does not fit the grid is refused when rebuilt.
    ProbeGrid bad = g;
    CpcaOptions options;
    options.clusters = 2;
    options.vectors = 1;
    bad.cpca = compress_probes(g, options).compressed.cpca;
    bad.cpca.cluster.pop_back();
    EXPECT_THROW(reconstruct_probes(bad), Error);
}

}  // namespace
}  // namespace shprt
