// The projection by sums (bake/stages.hpp, project_visibility_rows): a local set's rows hold one
// weight or 0, so W·Y is a sum of Y's rows. It must equal the SGEMM to rounding, give the same
// bits whatever kernel the CPU runs and whatever other rows share the call.
#include "bake/stages.hpp"
#include "shprt/core/host.hpp"

#include <gtest/gtest.h>

#include <cblas.h>

#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

namespace shprt::detail {
namespace {

struct Case {
    std::size_t count, S, depth;
    int K;
    std::vector<float> W, Y, T;
    float w = 0.0123f;
};

// `count` rows of `depth` weights (w or 0) with the visible shares of `visible`, row r's share
// visible[r % size], in rows of stride S; a random table Y (S × K) and its sums over depth.
Case make_case(std::size_t count, std::size_t S, std::size_t depth, int K,
               const std::vector<double>& visible, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> y(-1.0f, 1.0f);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Case c{count,
           S,
           depth,
           K,
           std::vector<float>(count * S, 0.0f),
           std::vector<float>(S * std::size_t(K)),
           {}};
    for (float& v : c.Y) v = y(rng);
    for (std::size_t r = 0; r < count; ++r)
        for (std::size_t s = 0; s < depth; ++s)
            c.W[r * S + s] = u(rng) < visible[r % visible.size()] ? c.w : 0.0f;
    c.T = segment_sums(c.Y.data(), depth, K);
    return c;
}

std::vector<float> by_sums(const Case& c) {
    std::vector<float> C(c.count * std::size_t(c.K));
    project_visibility_rows(c.W.data(), c.count, c.S, c.depth, c.Y.data(), c.K, c.T.data(), c.w,
                            C.data());
    return C;
}

TEST(ProjectVisibilityRows, EqualsTheProductToRounding) {
    const std::vector<double> shares = {0.0, 0.01, 0.3, 0.5, 0.7, 0.99, 1.0};
    for (const int K : {9, 64, 256, 300})
        for (const std::size_t depth : {64u, 200u, 1024u}) {
            SCOPED_TRACE(::testing::Message() << "K " << K << " depth " << depth);
            const Case c = make_case(21, depth + 7, depth, K, shares, std::uint32_t(K + depth));
            const std::vector<float> C = by_sums(c);
            std::vector<float> want(C.size());
            project_rows(c.W.data(), c.count, c.S, depth, c.Y.data(), K, want.data());
            for (std::size_t i = 0; i < C.size(); ++i)
                ASSERT_NEAR(C[i], want[i], 2e-6 * double(depth) * c.w) << "element " << i;
        }
}

TEST(ProjectVisibilityRows, EveryKernelGivesTheSameBits) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> y(-1.0f, 1.0f);
    for (const int K : {1, 9, 63, 256, 300, 600}) {
        std::vector<float> Y(1000 * std::size_t(K));
        for (float& v : Y) v = y(rng);
        std::vector<std::uint32_t> rows;
        for (std::uint32_t q = 0; q < 1000; q += 1 + q % 3) rows.push_back((q * 7919u) % 1000u);
        std::vector<float> want(std::size_t(K), 0.0f), got(std::size_t(K), 1.0f);
        sum_rows(Y.data(), K, rows.data(), rows.size(), want.data(), SumKernel::portable);
        for (const SumKernel k : {SumKernel::avx2, SumKernel::avx512, SumKernel::automatic}) {
            if ((k == SumKernel::avx2 && !cpu_has_avx2()) ||
                (k == SumKernel::avx512 && !cpu_has_avx512f())) {
                std::printf("K %d: this CPU lacks kernel %d: not compared\n", K, int(k));
                continue;
            }
            sum_rows(Y.data(), K, rows.data(), rows.size(), got.data(), k);
            EXPECT_EQ(std::memcmp(got.data(), want.data(), want.size() * sizeof(float)), 0)
                << "K " << K << ", kernel " << int(k);
        }
    }
}

// A row alone gives the bits it gets among others: nothing of a row depends on its neighbours
// (an SGEMM's rows may, with the height of the call and the row's place in it).
TEST(ProjectVisibilityRows, ARowsBitsAreItsOwn) {
    const Case c = make_case(37, 515, 512, 256, {0.2, 0.45, 0.55, 0.9}, 3);
    const std::vector<float> all = by_sums(c);
    for (std::size_t r = 0; r < c.count; ++r) {
        std::vector<float> one(std::size_t(c.K));
        project_visibility_rows(c.W.data() + r * c.S, 1, c.S, c.depth, c.Y.data(), c.K, c.T.data(),
                                c.w, one.data());
        EXPECT_EQ(
            std::memcmp(one.data(), all.data() + r * std::size_t(c.K), one.size() * sizeof(float)),
            0)
            << "row " << r;
    }
}

// rotate_rows_to_world's AVX-512 kernel (eight receivers, one per lane) gives the portable
// loop's bits for every receiver: 8-at-a-time groups and the rest, full and truncated K, normals
// at the poles too.
TEST(RotateRowsToWorld, EveryKernelGivesTheSameBits) {
    if (!cpu_has_avx512f()) GTEST_SKIP() << "this CPU has no AVX-512F";
    std::mt19937 rng(7);
    std::normal_distribution<float> g;
    for (const auto& [KL, K] :
         {std::pair{16, 16}, std::pair{256, 256}, std::pair{256, 250}, std::pair{1024, 1024}}) {
        const std::size_t count = 21;
        std::vector<Vec3f> normals(count);
        for (Vec3f& n : normals) {
            n = {g(rng), g(rng), g(rng)};
            n = n * (1.0f / std::sqrt(dot(n, n)));
        }
        normals[3] = {0, 0, 1};
        normals[9] = {0, 0, -1};
        std::vector<float> local(count * std::size_t(KL));
        for (float& v : local) v = g(rng);
        std::vector<float> want(count * std::size_t(K)), got(want.size());
        rotate_rows_to_world(normals.data(), count, KL, K, false, local.data(), want.data(),
                             RotationKernel::portable);
        rotate_rows_to_world(normals.data(), count, KL, K, false, local.data(), got.data(),
                             RotationKernel::avx512);
        for (std::size_t i = 0; i < want.size(); ++i)
            ASSERT_EQ(std::memcmp(&got[i], &want[i], sizeof(float)), 0)
                << "KL " << KL << " K " << K << ": receiver " << i / std::size_t(K)
                << ", coefficient " << i % std::size_t(K) << ": " << got[i] << " vs " << want[i];
    }
}

}  // namespace
}  // namespace shprt::detail
