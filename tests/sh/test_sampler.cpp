// Counter-based RNG (Philox known answers), sphere samplers (determinism, unit length, float vs
// double, moments, χ² over equal-solid-angle bins, stratification for any count, Sobol net
// property, integration error against uniform) and Gauss–Legendre quadrature.
#include "shprt/core/math.hpp"
#include "shprt/sh/direction_order.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/sh/zonal.hpp"

#include "shprt/core/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace shprt {
namespace {

Vec3d dir_at(const DirectionSet& set, std::size_t s) {
    return {set.dirs[3 * s], set.dirs[3 * s + 1], set.dirs[3 * s + 2]};
}
Vec3d dir_at(const DirectionSetD& set, std::size_t s) {
    return {set.dirs[3 * s], set.dirs[3 * s + 1], set.dirs[3 * s + 2]};
}

// ---- RNG ------------------------------------------------------------------------------------

// Random123 tests/kat_vectors, "philox4x32 10" lines: counter[4], key[2] -> result[4].
TEST(Rng, PhiloxKnownAnswers) {
    struct Kat {
        RngBlock ctr;
        std::uint32_t k0, k1;
        RngBlock expected;
    };
    const Kat kats[] = {
        {{{0, 0, 0, 0}}, 0, 0, {{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}}},
        {{{0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu}},
         0xffffffffu,
         0xffffffffu,
         {{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}}},
        {{{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}},
         0xa4093822u,
         0x299f31d0u,
         {{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}}},
    };
    for (const Kat& k : kats) {
        const RngBlock out = philox4x32<10>(k.ctr, k.k0, k.k1);
        for (int i = 0; i < 4; ++i) EXPECT_EQ(out.v[i], k.expected.v[i]) << "word " << i;
    }
    // The (seed, counter, stream) mapping onto Philox's counter and key.
    const RngBlock mapped = rng_block(0x299f31d0a4093822ull, 0x85a308d3243f6a88ull, 0x13198a2eu);
    const RngBlock direct = philox4x32<10>(RngBlock{{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0u}},
                                           0xa4093822u, 0x299f31d0u);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(mapped.v[i], direct.v[i]);
    EXPECT_EQ(rng_u32(1, 2, 3), rng_block(1, 2, 3).v[0]);
}

TEST(Rng, UnitConversionsAndUniformity) {
    EXPECT_EQ(to_unit_float(0xffffffffu), 1.0f - std::ldexp(1.0f, -24));
    EXPECT_LT(to_unit_double(0xffffffffu, 0xffffffffu), 1.0);
    EXPECT_EQ(to_unit_float(0u), 0.0f);
    constexpr int kBins = 64, kN = 64 * 1000;
    std::vector<int> hist(kBins, 0);
    for (int i = 0; i < kN; ++i) {
        const float f = rng_float(42, static_cast<std::uint64_t>(i), 7);
        const double d = rng_double(42, static_cast<std::uint64_t>(i), 7);
        ASSERT_GE(f, 0.0f);
        ASSERT_LT(f, 1.0f);
        ASSERT_GE(d, 0.0);
        ASSERT_LT(d, 1.0);
        // rng_float is rng_double rounded down to a multiple of 2^-24.
        ASSERT_EQ(static_cast<double>(f), std::floor(d * 16777216.0) / 16777216.0);
        ++hist[static_cast<int>(d * kBins)];
    }
    double chi2 = 0.0;
    for (int h : hist) chi2 += (h - 1000.0) * (h - 1000.0) / 1000.0;
    constexpr double kChi2Max63 = 103.4;  // χ²(63 dof) 0.999 quantile
    EXPECT_LT(chi2, kChi2Max63);
    // Streams, counters and seeds all change the output.
    EXPECT_NE(rng_u32(1, 0, 0), rng_u32(1, 0, 1));
    EXPECT_NE(rng_u32(1, 0, 0), rng_u32(1, 1, 0));
    EXPECT_NE(rng_u32(1, 0, 0), rng_u32(2, 0, 0));
    EXPECT_NE(rng_u32(1, 0, 0), rng_u32(1, std::uint64_t{1} << 32, 0));
    EXPECT_NE(rng_u32(1, 0, 0), rng_u32(1 + (std::uint64_t{1} << 32), 0, 0));
}

// ---- Names ----------------------------------------------------------------------------------

TEST(Sampler, NamesRoundTripAndUnknownNameThrows) {
    for (SamplerKind kind : kAllSamplerKinds) EXPECT_EQ(parse_sampler_kind(to_string(kind)), kind);
    EXPECT_STREQ(to_string(SamplerKind::uniform), "uniform");
    EXPECT_STREQ(to_string(SamplerKind::sobol), "sobol");
    try {
        parse_sampler_kind("halton");
        FAIL() << "no exception";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        const std::string msg = e.what();
        EXPECT_NE(msg.find("halton"), std::string::npos) << msg;
        EXPECT_NE(msg.find("fibonacci"), std::string::npos) << msg;
    }
    EXPECT_THROW(parse_sampler_kind(""), Error);
    EXPECT_THROW(parse_sampler_kind("Uniform"), Error);
}

TEST(Sampler, BadInputsThrow) {
    for (SamplerKind kind : kAllSamplerKinds) {
        EXPECT_THROW(make_direction_set(kind, 1, 0), Error);
        EXPECT_THROW(make_direction_set_d(kind, 1, 0), Error);
        EXPECT_THROW(make_direction_set(kind, 1, (1u << 28) + 1), Error);
    }
    EXPECT_THROW(gauss_legendre_set(0, 4), Error);
    EXPECT_THROW(gauss_legendre_set_d(4, 0), Error);
    EXPECT_THROW(gauss_legendre_set_d(-3, 4), Error);
    EXPECT_THROW(gauss_legendre_set_d(65536, 65536), Error);
    EXPECT_THROW(quadrature_set_for_bands(0), Error);
    EXPECT_THROW(quadrature_set_for_bands_d(-1), Error);
}

// ---- Properties every sampler must have -----------------------------------------------------

class EachSampler : public ::testing::TestWithParam<SamplerKind> {};

TEST_P(EachSampler, DeterministicAndSeedDependent) {
    const SamplerKind kind = GetParam();
    constexpr std::uint32_t kCount = 1000;
    const DirectionSet a = make_direction_set(kind, 12345, kCount);
    const DirectionSet b = make_direction_set(kind, 12345, kCount);
    const DirectionSet c = make_direction_set(kind, 12346, kCount);
    ASSERT_EQ(a.size(), kCount);
    ASSERT_EQ(a.dirs.size(), 3 * kCount);
    EXPECT_EQ(std::memcmp(a.dirs.data(), b.dirs.data(), a.dirs.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(a.weights.data(), b.weights.data(), kCount * sizeof(float)), 0);
    std::size_t same = 0;
    for (std::size_t i = 0; i < a.dirs.size(); ++i) same += a.dirs[i] == c.dirs[i];
    EXPECT_LT(same, a.dirs.size() / 10) << "seed barely changes the set";
    for (float w : a.weights) EXPECT_FLOAT_EQ(w, static_cast<float>(4.0 * kPi / kCount));

    // A pure function of (seed, index): two threads computing halves in reverse order give the
    // same bits as the set.
    std::vector<Vec3f> by_thread(kCount);
    auto work = [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t s = end; s-- > begin;)
            by_thread[s] = cast<float>(sphere_direction<double>(kind, 12345, s, kCount));
    };
    std::thread t1(work, 0u, kCount / 2), t2(work, kCount / 2, kCount);
    t1.join();
    t2.join();
    for (std::uint32_t s = 0; s < kCount; ++s) {
        ASSERT_EQ(by_thread[s].x, a.dirs[3 * s]);
        ASSERT_EQ(by_thread[s].y, a.dirs[3 * s + 1]);
        ASSERT_EQ(by_thread[s].z, a.dirs[3 * s + 2]);
    }
}

TEST_P(EachSampler, UnitLengthAndFloatAgreesWithDouble) {
    const SamplerKind kind = GetParam();
    constexpr double kUnitTolFloat = 1e-6, kUnitTolDouble = 1e-14;
    // |Δu| ≤ 2^-24 moves the direction by ≤ 2·√(2^-24) = 2^-11 at the poles, ~1e-7 elsewhere.
    constexpr double kFloatDoubleMax = 1.0 / 2048.0, kFloatDoubleMean = 1e-6;
    for (std::uint32_t count : {1u, 2u, 3u, 7u, 100u, 4096u, 5000u}) {
        const DirectionSet set = make_direction_set(kind, 99, count);
        const DirectionSetD setd = make_direction_set_d(kind, 99, count);
        double mean_diff = 0.0;
        for (std::uint32_t s = 0; s < count; ++s) {
            const Vec3d d = dir_at(set, s), dd = dir_at(setd, s);
            ASSERT_NEAR(length(d), 1.0, kUnitTolFloat) << count << " " << s;
            ASSERT_NEAR(length(dd), 1.0, kUnitTolDouble) << count << " " << s;
            const Vec3f f = sphere_direction<float>(kind, 99, s, count);
            ASSERT_NEAR(length(cast<double>(f)), 1.0, kUnitTolFloat);
            const double diff = length(cast<double>(f) - dd);
            ASSERT_LE(diff, kFloatDoubleMax) << count << " " << s;
            mean_diff += diff / count;
        }
        EXPECT_LT(mean_diff, kFloatDoubleMean) << count;
    }
}

// Mean ≈ 0 and E[x²] = E[y²] = E[z²] = 1/3 to 5 standard errors of a uniform random set.
TEST_P(EachSampler, Moments) {
    const SamplerKind kind = GetParam();
    constexpr std::uint32_t kCount = 12800;
    const double tol_mean = 5.0 * std::sqrt(1.0 / 3.0 / kCount);          // Var(x) = 1/3
    const double tol_sq = 5.0 * std::sqrt((1.0 / 5 - 1.0 / 9) / kCount);  // Var(x²) = 4/45
    const DirectionSet set = make_direction_set(kind, 2024, kCount);
    Vec3d mean{0, 0, 0}, sq{0, 0, 0};
    for (std::uint32_t s = 0; s < kCount; ++s) {
        const Vec3d d = dir_at(set, s);
        mean += d / static_cast<double>(kCount);
        sq += Vec3d{d.x * d.x, d.y * d.y, d.z * d.z} / static_cast<double>(kCount);
    }
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(mean[a], 0.0, tol_mean) << "axis " << a;
        EXPECT_NEAR(sq[a], 1.0 / 3.0, tol_sq) << "axis " << a;
    }
}

// χ² over 8 bands of equal z-height × 16 equal φ-sectors = 128 bins of equal solid angle.
TEST_P(EachSampler, ChiSquareEqualSolidAngleBins) {
    const SamplerKind kind = GetParam();
    constexpr int kZBins = 8, kPhiBins = 16, kBins = kZBins * kPhiBins;
    constexpr std::uint32_t kCount = 100 * kBins;
    constexpr double kChi2Max127 = 182.0;  // χ²(127 dof) 0.999 quantile (Wilson–Hilferty)
    const DirectionSet set = make_direction_set(kind, 777, kCount);
    std::vector<int> hist(kBins, 0);
    for (std::uint32_t s = 0; s < kCount; ++s) {
        const Vec3d d = dir_at(set, s);
        const int zb = std::clamp(static_cast<int>((1.0 - d.z) / 2.0 * kZBins), 0, kZBins - 1);
        double phi = std::atan2(d.y, d.x);
        if (phi < 0) phi += 2 * kPi;
        const int pb = std::clamp(static_cast<int>(phi / (2 * kPi) * kPhiBins), 0, kPhiBins - 1);
        ++hist[zb * kPhiBins + pb];
    }
    const double expected = static_cast<double>(kCount) / kBins;
    double chi2 = 0.0;
    for (int h : hist) chi2 += (h - expected) * (h - expected) / expected;
    EXPECT_LT(chi2, kChi2Max127) << to_string(kind);
    RecordProperty("chi2", std::to_string(chi2));
}

INSTANTIATE_TEST_SUITE_P(AllKinds, EachSampler, ::testing::ValuesIn(kAllSamplerKinds),
                         [](const auto& p) { return std::string(to_string(p.param)); });

// ---- Kind-specific checks -------------------------------------------------------------------

// The uniform set is literally the paper's formula with x, y from Philox.
TEST(Sampler, UniformIsThePapersMap) {
    constexpr double kTol = 1e-12;
    for (std::uint32_t s = 0; s < 2000; ++s) {
        const RngBlock b = rng_block(5, s, kStreamUniform);
        const double x = to_unit_double(b.v[0], b.v[1]), y = to_unit_double(b.v[2], b.v[3]);
        const double theta = 2.0 * std::acos(std::sqrt(1.0 - x)), phi = 2.0 * kPi * y;
        const Vec3d d = sphere_direction<double>(SamplerKind::uniform, 5, s, 2000);
        EXPECT_NEAR(d.x, std::sin(theta) * std::cos(phi), kTol);
        EXPECT_NEAR(d.y, std::sin(theta) * std::sin(phi), kTol);
        EXPECT_NEAR(d.z, std::cos(theta), kTol);
        // Independent of the set size: prefixes are sets.
        EXPECT_EQ(d, sphere_direction<double>(SamplerKind::uniform, 5, s, 1 + s));
    }
}

// Every count gives cells of equal solid angle that tile the sphere, one point in each.
TEST(Sampler, StratifiedCellsTileTheSphereForAnyCount) {
    for (std::uint32_t count = 1; count <= 300; ++count) {
        const std::uint32_t rows = stratified_rows(count);
        ASSERT_GE(rows, 1u);
        ASSERT_LE(rows, count);
        std::uint32_t expect_first = 0, last_row = 0;
        for (std::uint32_t s = 0; s < count; ++s) {
            const StratifiedCell c = stratified_cell(s, count);
            ASSERT_EQ(c.rows, rows);
            ASSERT_LE(c.first, s);
            ASSERT_LT(s, c.first + c.cells);
            ASSERT_GE(c.cells, count / rows);
            ASSERT_LE(c.cells, (count + rows - 1) / rows);
            if (s == c.first) {  // rows are contiguous, in order, starting after the last one
                ASSERT_EQ(c.first, expect_first) << count << " " << s;
                ASSERT_EQ(c.row, s == 0 ? 0u : last_row + 1);
                expect_first = c.first + c.cells;
                last_row = c.row;
            }
            // The point lies in its cell: z in the row's band, φ in the cell's sector.
            const Vec3d d = sphere_direction<double>(SamplerKind::stratified, 3, s, count);
            const double z_hi = 1.0 - 2.0 * c.first / count;
            const double z_lo = 1.0 - 2.0 * (c.first + c.cells) / static_cast<double>(count);
            ASSERT_LE(d.z, z_hi + 1e-12);
            ASSERT_GE(d.z, z_lo - 1e-12);
            if (c.cells > 1 && std::hypot(d.x, d.y) > 1e-9) {
                double phi = std::atan2(d.y, d.x);
                if (phi < 0) phi += 2 * kPi;
                const double k = s - c.first;
                ASSERT_GE(phi, 2 * kPi * k / c.cells - 1e-9);
                ASSERT_LE(phi, 2 * kPi * (k + 1) / c.cells + 1e-9);
            }
        }
        ASSERT_EQ(expect_first, count);  // rows covered every cell: heights sum to 2
        ASSERT_EQ(last_row + 1, rows);
    }
    // Large counts: no 32-bit overflow in the row search.
    const std::uint32_t big = 3000000000u;
    const StratifiedCell c = stratified_cell(big - 1, big);
    EXPECT_EQ(c.row, c.rows - 1);
    EXPECT_EQ(c.first + c.cells, big);
}

// Owen scrambling keeps the (0,m,2)-net property of Sobol points: for N = 2^m, every elementary
// interval [a/2^i, (a+1)/2^i) × [b/2^j, (b+1)/2^j) with i + j = m holds exactly one point.
TEST(Sampler, SobolIsANetScrambledOrNot) {
    constexpr int kM = 10;
    constexpr std::uint32_t kN = 1u << kM;
    for (int scrambled = 0; scrambled < 2; ++scrambled) {
        std::vector<std::uint32_t> u(kN), v(kN);
        for (std::uint32_t s = 0; s < kN; ++s) {
            u[s] = scrambled ? sobol_scrambled_u32(11, s, 0) : sobol_u32(s, 0);
            v[s] = scrambled ? sobol_scrambled_u32(11, s, 1) : sobol_u32(s, 1);
        }
        for (int i = 0; i <= kM; ++i) {
            const int j = kM - i;
            std::vector<int> hist(kN, 0);
            for (std::uint32_t s = 0; s < kN; ++s) {
                const std::uint32_t a = i == 0 ? 0 : u[s] >> (32 - i);
                const std::uint32_t b = j == 0 ? 0 : v[s] >> (32 - j);
                ++hist[(a << j) | b];
            }
            for (int h : hist) ASSERT_EQ(h, 1) << "scrambled=" << scrambled << " i=" << i;
        }
    }
    // Known unscrambled values (natural, not Gray-code, order): dimension 1 is
    // 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8 (v = 1/2, 3/4, 5/8 XORed by the index bits).
    const std::uint32_t expect[] = {0, 4, 6, 2, 5, 1, 3, 7};
    for (std::uint32_t s = 0; s < 8; ++s) EXPECT_EQ(sobol_u32(s, 1), expect[s] << 29) << s;
    EXPECT_EQ(sobol_u32(1, 0), 0x80000000u);
    EXPECT_EQ(sobol_u32(3, 0), 0xC0000000u);
    // Different seeds scramble differently; the scramble is a bijection on 16-bit prefixes.
    EXPECT_NE(sobol_scrambled_u32(1, 5, 0), sobol_scrambled_u32(2, 5, 0));
    std::vector<bool> seen(1u << 16, false);
    for (std::uint32_t x = 0; x < (1u << 16); ++x) {
        const std::uint32_t y = owen_scramble(x << 16, 0xabcdef12u) >> 16;
        ASSERT_FALSE(seen[y]);
        seen[y] = true;
    }
}

// The seed only rotates the Fibonacci lattice: all pairwise dot products are seed-independent.
TEST(Sampler, FibonacciSeedIsARotation) {
    constexpr std::uint32_t kCount = 500;
    const DirectionSetD a = make_direction_set_d(SamplerKind::fibonacci, 1, kCount);
    const DirectionSetD b = make_direction_set_d(SamplerKind::fibonacci, 2, kCount);
    for (std::uint32_t s = 0; s < kCount; s += 7)
        for (std::uint32_t t = 0; t < kCount; t += 11)
            ASSERT_NEAR(dot(dir_at(a, s), dir_at(a, t)), dot(dir_at(b, s), dir_at(b, t)), 1e-13);
    EXPECT_GT(length(dir_at(a, 0) - dir_at(b, 0)), 1e-3);
    // The unrotated lattice: z = 1 − (2s + 1)/N and successive φ advance by 2π/Φ.
    const double golden = (1.0 + std::sqrt(5.0)) / 2.0;
    for (std::uint32_t s = 0; s < kCount; ++s) {
        const Vec3d p = fibonacci_lattice_point<double>(s, kCount);
        ASSERT_NEAR(p.z, 1.0 - (2.0 * s + 1.0) / kCount, 1e-15);
        double phi = std::atan2(p.y, p.x);
        const double expect = 2 * kPi * (s / golden - std::floor(s / golden));
        double diff = std::remainder(phi - expect, 2 * kPi);
        ASSERT_NEAR(diff, 0.0, 1e-9) << s;
    }
    // random_rotation is a rotation.
    const Mat3d r = random_rotation<double>(77, kStreamFibonacci);
    const Mat3d rrt = r * transpose(r);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(rrt.m[i][j], i == j ? 1.0 : 0.0, 1e-14);
    const double det =
        dot(Vec3d{r.m[0][0], r.m[0][1], r.m[0][2]},
            cross(Vec3d{r.m[1][0], r.m[1][1], r.m[1][2]}, Vec3d{r.m[2][0], r.m[2][1], r.m[2][2]}));
    EXPECT_NEAR(det, 1.0, 1e-14);
}

// Low-discrepancy and stratified sets integrate a smooth function with far smaller error than
// the uniform random set at S = 4096 (RMS over 8 seeds).
TEST(Sampler, LowDiscrepancyBeatsUniformAt4096) {
    constexpr std::uint32_t kCount = 4096;
    constexpr int kSeeds = 8;
    constexpr double kMaxRatio = 0.25;  // LD RMS error / uniform RMS error
    const Vec3d a{0.45, -0.75, 1.2};
    const double norm_a = length(a);
    const double exact = 4 * kPi * std::sinh(norm_a) / norm_a;  // ∫ exp(a·ω) dω
    double rms[4] = {0, 0, 0, 0};
    for (SamplerKind kind : kAllSamplerKinds) {
        for (int seed = 0; seed < kSeeds; ++seed) {
            const DirectionSetD set = make_direction_set_d(kind, 1000 + seed, kCount);
            double sum = 0.0;
            for (std::uint32_t s = 0; s < kCount; ++s)
                sum += set.weights[s] * std::exp(dot(a, dir_at(set, s)));
            rms[static_cast<int>(kind)] += (sum - exact) * (sum - exact) / kSeeds;
        }
    }
    for (double& r : rms) r = std::sqrt(r) / exact;
    const double uniform = rms[static_cast<int>(SamplerKind::uniform)];
    EXPECT_GT(uniform, 1e-4);  // sanity: MC error at 4096 samples is ~1e-2·σ
    for (SamplerKind kind : {SamplerKind::stratified, SamplerKind::fibonacci, SamplerKind::sobol})
        EXPECT_LT(rms[static_cast<int>(kind)], kMaxRatio * uniform)
            << to_string(kind) << ": " << rms[static_cast<int>(kind)] << " vs uniform " << uniform;
}

// ---- Convergence: the 1/√S law, for every sampler -------------------------------------------
//
// The error of a Monte Carlo projection is a random variable of the set; its RMS over seeds falls
// as 1/√S for a random set (a factor 4 from S to 16S) and faster for stratified and
// low-discrepancy sets. One seed's curve is a single draw: with nested prefixes the error at 16S
// contains the error at S, and for a peaked integrand (a sun) about a quarter of seeds show no
// fall at all from S to 4S — for shprt's uniform set and for an independent std::mt19937_64 set
// alike (issue 39). So the law is checked on the RMS over kConvergenceSeeds seeds, against an
// independent random set measured the same way.

constexpr int kConvergenceK = 9;              // 3 bands
constexpr int kConvergenceSeeds = 16;         // RMS over this many seeds
constexpr std::uint32_t kConvergenceS = 128;  // S, then 16·S
constexpr double kMinFallRandom = 3.0;        // ideal 4 = √16 (a period of 8·S: 2.8)
constexpr double kMaxVsIndependent = 1.3;     // RMS at 16·S ÷ the independent set's
// Stratified and low-discrepancy sets fall faster: S^(−3/4) for a function with a jump across a
// curve (Owen-scrambled nets, jittered grids), a factor 8; more for smooth functions.
constexpr double kMinFallQmc = 5.5;
constexpr double kMaxVsIndependentQmc = 0.25;
const Vec3d kLobeAxis = normalize(Vec3d{0.36, -0.48, 0.8});

// y_l^0(x) = √((2l+1)/4π) P_l(x) for l < bands.
std::vector<double> zonal_basis(int bands, double x) {
    std::vector<double> y(bands);
    double p0 = 1.0, p1 = x;
    for (int l = 0; l < bands; ++l) {
        const double p = l == 0   ? 1.0
                         : l == 1 ? x
                                  : ((2.0 * l - 1.0) * x * p1 - (l - 1.0) * p0) / l;
        if (l >= 2) {
            p0 = p1;
            p1 = p;
        }
        y[l] = std::sqrt((2.0 * l + 1.0) / (4 * kPi)) * p;
    }
    return y;
}

// z_l = 2π ∫_lo^1 h(x) y_l^0(x) dx of a zonal function h(a·ω) that is 0 for a·ω < lo, by
// 64-node Gauss–Legendre on [lo, 1]: exact to rounding for the polynomial and for exp.
template <class H>
std::vector<double> zonal_coefficients(const H& h, double lo, int bands) {
    const DirectionSetD gl = gauss_legendre_set_d(64, 1);
    std::vector<double> z(bands, 0.0);
    for (std::size_t i = 0; i < gl.size(); ++i) {
        const double t = gl.dirs[3 * i + 2], w = gl.weights[i] / (2 * kPi);  // ∫_{−1}^{1}
        const double x = lo + (1.0 - lo) * (t + 1.0) / 2.0;
        const std::vector<double> y = zonal_basis(bands, x);
        for (int l = 0; l < bands; ++l) z[l] += 2 * kPi * w * (1.0 - lo) / 2.0 * h(x) * y[l];
    }
    return z;
}

struct TestFunction {
    const char* name;
    double (*h)(double);  // h(a·ω)
    double lo;            // h = 0 below
};
// smooth: exp(2 a·ω); discontinuous: the cosine lobe max(0, a·ω) clipped by the plane
// a·ω = 0.4 (a jump of 0.4 there).
constexpr double kClipPlane = 0.4;
const TestFunction kTestFunctions[] = {
    {"smooth exp(2a·w)", [](double x) { return std::exp(2.0 * x); }, -1.0},
    {"clipped cosine lobe", [](double x) { return x > kClipPlane ? x : 0.0; }, kClipPlane},
};

// The exact first K coefficients: the zonal ones rotated to the axis (zonal.hpp's identity).
std::vector<double> exact_coefficients(const TestFunction& f) {
    const int bands = sh_bands_for(kConvergenceK);
    const std::vector<double> z = zonal_coefficients(f.h, f.lo, bands);
    std::vector<double> c(kConvergenceK);
    rotate_zonal(z.data(), kConvergenceK, kLobeAxis, c.data());
    return c;
}

// ‖ĉ − c‖₂ of the projection by the first `count` directions given by dir(s), weight 4π/count.
template <class Dir>
double projection_error(const TestFunction& f, const std::vector<double>& exact,
                        std::uint32_t count, const Dir& dir) {
    std::vector<double> c(kConvergenceK, 0.0), y(kConvergenceK);
    for (std::uint32_t s = 0; s < count; ++s) {
        const Vec3d d = dir(s);
        const double x = dot(kLobeAxis, d);
        if (x < f.lo) continue;
        sh_eval_k(kConvergenceK, d.x, d.y, d.z, y.data());
        const double v = f.h(x) * 4 * kPi / count;
        for (int k = 0; k < kConvergenceK; ++k) c[k] += v * y[k];
    }
    double e2 = 0.0;
    for (int k = 0; k < kConvergenceK; ++k) e2 += (c[k] - exact[k]) * (c[k] - exact[k]);
    return std::sqrt(e2);
}

// RMS over seeds of the error of `kind` at S and 16·S (the set of each size, as the bake makes
// it; for uniform and Sobol the S set is the prefix of the 16·S set).
std::pair<double, double> sampler_rms(SamplerKind kind, const TestFunction& f,
                                      const std::vector<double>& exact) {
    double r[2] = {0, 0};
    for (int seed = 0; seed < kConvergenceSeeds; ++seed)
        for (int i = 0; i < 2; ++i) {
            const std::uint32_t S = i == 0 ? kConvergenceS : 16 * kConvergenceS;
            const double e = projection_error(f, exact, S, [&](std::uint32_t s) {
                return sphere_direction<double>(kind, 500 + seed, s, S);
            });
            r[i] += e * e / kConvergenceSeeds;
        }
    return {std::sqrt(r[0]), std::sqrt(r[1])};
}

// The same for an independent uniform random set: the paper's map of std::mt19937_64 words.
std::pair<double, double> independent_rms(const TestFunction& f, const std::vector<double>& exact) {
    double r[2] = {0, 0};
    for (int seed = 0; seed < kConvergenceSeeds; ++seed) {
        std::mt19937_64 engine(9000 + seed);
        std::vector<Vec3d> dirs(16 * kConvergenceS);
        for (Vec3d& d : dirs) {
            const double u = static_cast<double>(engine() >> 11) * 0x1.0p-53;
            const double v = static_cast<double>(engine() >> 11) * 0x1.0p-53;
            d = square_to_sphere<double>(u, v);
        }
        for (int i = 0; i < 2; ++i) {
            const std::uint32_t S = i == 0 ? kConvergenceS : 16 * kConvergenceS;
            const double e =
                projection_error(f, exact, S, [&](std::uint32_t s) { return dirs[s]; });
            r[i] += e * e / kConvergenceSeeds;
        }
    }
    return {std::sqrt(r[0]), std::sqrt(r[1])};
}

TEST(Sampler, ErrorFallsAsOneOverRootSForEverySampler) {
    for (const TestFunction& f : kTestFunctions) {
        const std::vector<double> exact = exact_coefficients(f);
        const auto [ind_S, ind_16S] = independent_rms(f, exact);
        // The yardstick itself: an independent random set falls by ≈ 4.
        ASSERT_GE(ind_S / ind_16S, kMinFallRandom) << f.name;
        for (SamplerKind kind : kAllSamplerKinds) {
            const bool qmc = kind != SamplerKind::uniform;
            const auto [rms_S, rms_16S] = sampler_rms(kind, f, exact);
            EXPECT_GE(rms_S / rms_16S, qmc ? kMinFallQmc : kMinFallRandom)
                << to_string(kind) << ", " << f.name << ": RMS error " << rms_S
                << " at S = " << kConvergenceS << ", " << rms_16S
                << " at 16 S (independent set: " << ind_S << ", " << ind_16S << ")";
            EXPECT_LE(rms_16S, (qmc ? kMaxVsIndependentQmc : kMaxVsIndependent) * ind_16S)
                << to_string(kind) << ", " << f.name << ": RMS error at 16 S " << rms_16S
                << " against the independent set's " << ind_16S;
            RecordProperty(std::string(to_string(kind)) + (f.lo > -1 ? "_clipped" : "_smooth"),
                           std::to_string(rms_S) + " " + std::to_string(rms_16S));
        }
    }
}

// ---- The coherent tracing order ---------------------------------------------------------------

// Hilbert keys: every aligned 2^k × 2^k block of cells is one run of 4^k consecutive keys, and
// successive keys are edge-adjacent cells (checked on the curve's first 2^16 cells).
TEST(DirectionOrder, HilbertKeysAreContiguousPerBlockAndStepToNeighbours) {
    std::mt19937_64 engine(3);
    for (int trial = 0; trial < 200; ++trial) {
        const int k = 1 + trial % 4;
        const std::uint32_t size = 1u << k;
        const std::uint32_t x0 = (static_cast<std::uint32_t>(engine()) & 0xffffu) & ~(size - 1);
        const std::uint32_t y0 = (static_cast<std::uint32_t>(engine()) & 0xffffu) & ~(size - 1);
        std::vector<std::uint32_t> keys;
        for (std::uint32_t dy = 0; dy < size; ++dy)
            for (std::uint32_t dx = 0; dx < size; ++dx)
                keys.push_back(hilbert_index(x0 + dx, y0 + dy));
        std::sort(keys.begin(), keys.end());
        ASSERT_EQ(keys.front() % (size * size), 0u) << x0 << " " << y0 << " k=" << k;
        for (std::size_t i = 1; i < keys.size(); ++i) ASSERT_EQ(keys[i], keys[0] + i);
    }
    std::vector<std::uint32_t> at(1u << 16, ~0u);  // cell of key d, for d < 2^16: x | y << 16
    for (std::uint32_t y = 0; y < 256; ++y)
        for (std::uint32_t x = 0; x < 256; ++x) {
            const std::uint32_t d = hilbert_index(x, y);
            if (d < at.size()) at[d] = x | y << 16;
        }
    for (std::size_t d = 0; d < at.size(); ++d) {
        ASSERT_NE(at[d], ~0u) << d;  // the first 4^8 keys lie in the first 256 × 256 block
        if (d == 0) continue;
        const int dx = int(at[d] & 0xffffu) - int(at[d - 1] & 0xffffu);
        const int dy = int(at[d] >> 16) - int(at[d - 1] >> 16);
        ASSERT_EQ(std::abs(dx) + std::abs(dy), 1) << d;
    }
}

// The order is a permutation, a pure function of the set, and coherent: successive directions
// are close (the set's own order jumps across the sphere).
TEST_P(EachSampler, CoherentOrderIsACoherentPermutation) {
    const SamplerKind kind = GetParam();
    constexpr std::uint32_t kCount = 4096;
    // Mean angle between successive directions: ~π/2 in a random order; along the curve about
    // the spacing √(4π/S) ≈ 0.055 rad, with the curve's few long jumps.
    constexpr double kMaxMeanStepCoherent = 0.1;
    const DirectionSet set = make_direction_set(kind, 8, kCount);
    const std::vector<std::uint32_t> order = coherent_order(set);
    ASSERT_EQ(order.size(), kCount);
    std::vector<bool> seen(kCount, false);
    for (std::uint32_t s : order) {
        ASSERT_LT(s, kCount);
        ASSERT_FALSE(seen[s]);
        seen[s] = true;
    }
    EXPECT_EQ(order, coherent_order(make_direction_set(kind, 8, kCount)));
    double step = 0.0, step_set = 0.0;
    for (std::uint32_t i = 1; i < kCount; ++i) {
        const double c = dot(dir_at(set, order[i]), dir_at(set, order[i - 1]));
        step += std::acos(std::clamp(c, -1.0, 1.0)) / (kCount - 1);
        const double c_set = dot(dir_at(set, i), dir_at(set, i - 1));
        step_set += std::acos(std::clamp(c_set, -1.0, 1.0)) / (kCount - 1);
    }
    EXPECT_LT(step, kMaxMeanStepCoherent) << to_string(kind) << " (set order: " << step_set << ")";
    RecordProperty("mean_step", std::to_string(step) + " vs " + std::to_string(step_set));
}

// ---- Quadrature -----------------------------------------------------------------------------

// ∫ x^a y^b z^c dω over the unit sphere: 0 if any exponent is odd, else
// 2 Γ((a+1)/2) Γ((b+1)/2) Γ((c+1)/2) / Γ((a+b+c+3)/2).
double monomial_integral(int a, int b, int c) {
    if (a % 2 || b % 2 || c % 2) return 0.0;
    return 2.0 * std::exp(std::lgamma((a + 1) / 2.0) + std::lgamma((b + 1) / 2.0) +
                          std::lgamma((c + 1) / 2.0) - std::lgamma((a + b + c + 3) / 2.0));
}

TEST(Quadrature, GaussLegendreIntegratesPolynomialsExactly) {
    constexpr double kTol = 1e-12;
    constexpr int kDegree = 20;  // total degree of x^a y^b z^c
    // Degree ≤ 2L − 2 in (x, y, z) needs n_theta = L, n_phi = 2L − 1.
    const DirectionSetD set = quadrature_set_for_bands_d(kDegree / 2 + 1);
    double wsum = 0.0;
    for (double w : set.weights) wsum += w;
    EXPECT_NEAR(wsum, 4 * kPi, kTol);
    for (std::size_t s = 0; s < set.size(); ++s) ASSERT_NEAR(length(dir_at(set, s)), 1.0, 1e-15);
    for (int a = 0; a <= kDegree; ++a)
        for (int b = 0; a + b <= kDegree; ++b)
            for (int c = 0; a + b + c <= kDegree; ++c) {
                double sum = 0.0;
                for (std::size_t s = 0; s < set.size(); ++s) {
                    const Vec3d d = dir_at(set, s);
                    sum += set.weights[s] * std::pow(d.x, a) * std::pow(d.y, b) * std::pow(d.z, c);
                }
                ASSERT_NEAR(sum, monomial_integral(a, b, c), kTol) << a << " " << b << " " << c;
            }
    // And it is the smallest such rule: one node fewer in θ misses z^(2L−2).
    const int L = kDegree / 2 + 1;
    const DirectionSetD small = gauss_legendre_set_d(L - 1, 2 * L - 1);
    double sum = 0.0;
    for (std::size_t s = 0; s < small.size(); ++s)
        sum += small.weights[s] * std::pow(dir_at(small, s).z, kDegree);
    EXPECT_GT(std::abs(sum - monomial_integral(0, 0, kDegree)), 1e-6);
}

TEST(Quadrature, GaussLegendreNodesAreSymmetricAndOrdered) {
    for (int n : {1, 2, 3, 8, 31, 64}) {
        const DirectionSetD set = gauss_legendre_set_d(n, 1);
        double wsum = 0.0;
        for (std::size_t i = 0; i < set.size(); ++i) {
            wsum += set.weights[i];
            ASSERT_NEAR(set.dirs[3 * i + 2], -set.dirs[3 * (set.size() - 1 - i) + 2], 1e-15);
            if (i > 0) {
                ASSERT_LT(set.dirs[3 * i + 2], set.dirs[3 * (i - 1) + 2]);
            }
        }
        EXPECT_NEAR(wsum, 4 * kPi, 1e-12) << n;
    }
    const DirectionSet f = gauss_legendre_set(4, 7);
    EXPECT_EQ(f.size(), 28u);
    EXPECT_EQ(quadrature_set_for_bands(5).size(), 5u * 9u);
}

}  // namespace
}  // namespace shprt

namespace shprt {
namespace {

// open_hemisphere_transfer: the cosine vector is the clamped cosine's zonal vector (closed form,
// zonal.hpp), and the matrix ∫_H y_i·y_j agrees with a fine midpoint rule in θ (an independent
// quadrature, error O(h²)); its diagonal is 1/2 (y_i² is even in z, so half its sphere integral).
TEST(OpenHemisphereTransfer, IsTheClampedCosineAndTheHemisphereGram) {
    const int K = 36;
    const std::vector<double> zonal = clamped_cosine_zonal(6);
    const std::vector<double> v = open_hemisphere_transfer(K, HemisphereDensity::cosine);
    ASSERT_EQ(v.size(), std::size_t(K));
    for (int l = 0; l < 6; ++l)
        for (int m = -l; m <= l; ++m)
            EXPECT_NEAR(v[std::size_t(l * (l + 1) + m)], m == 0 ? zonal[std::size_t(l)] : 0.0,
                        1e-13)
                << l << ", " << m;

    const std::vector<double> M = open_hemisphere_transfer(K, HemisphereDensity::uniform);
    ASSERT_EQ(M.size(), std::size_t(K * (K + 1) / 2));
    const int n_theta = 2000, n_phi = 64;
    std::vector<double> ref(M.size(), 0.0), y(K);
    for (int i = 0; i < n_theta; ++i) {
        const double theta = 0.5 * kPi * (i + 0.5) / n_theta;
        for (int k = 0; k < n_phi; ++k) {
            const double phi = 2 * kPi * (k + 0.5) / n_phi;
            const double w = std::sin(theta) * (0.5 * kPi / n_theta) * (2 * kPi / n_phi);
            sh_eval_k(K, std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                      std::cos(theta), y.data());
            std::size_t p = 0;
            for (int a = 0; a < K; ++a)
                for (int b = a; b < K; ++b) ref[p++] += w * y[a] * y[b];
        }
    }
    std::size_t p = 0;
    for (int a = 0; a < K; ++a)
        for (int b = a; b < K; ++b, ++p) {
            EXPECT_NEAR(M[p], ref[p], 1e-5) << a << ", " << b;
            if (a == b) EXPECT_NEAR(M[p], 0.5, 1e-13) << a;
        }
    EXPECT_THROW(open_hemisphere_transfer(0, HemisphereDensity::cosine), Error);
}

}  // namespace
}  // namespace shprt
