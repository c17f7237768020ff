// SH basis: fast recurrence vs slow reference, closed forms of bands 0-3, orthonormality by
// exact quadrature (Gauss-Legendre in cos θ × uniform φ) to 30 bands in double.
#include "shprt/core/math.hpp"
#include "shprt/sh/basis.hpp"

#include "shprt/core/error.hpp"

#include "common/gauss_legendre.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace shprt {
namespace {

using test_support::gauss_legendre;

struct Dir {
    double theta, phi, x, y, z;
};

std::vector<Dir> random_dirs(int n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Dir> dirs;
    for (int i = 0; i < n; ++i) {
        const double theta = std::acos(1.0 - 2.0 * u(rng)), phi = 2.0 * kPi * u(rng);
        dirs.push_back({theta, phi, std::sin(theta) * std::cos(phi),
                        std::sin(theta) * std::sin(phi), std::cos(theta)});
    }
    // The poles and the equator are where recurrences usually break.
    dirs.push_back({0.0, 0.0, 0.0, 0.0, 1.0});
    dirs.push_back({kPi, 0.0, 0.0, 0.0, -1.0});
    dirs.push_back({kPi / 2, kPi / 3, std::cos(kPi / 3), std::sin(kPi / 3), 0.0});
    return dirs;
}

TEST(ShBasis, IndexHelpers) {
    EXPECT_EQ(sh_index(0, 0), 0);
    EXPECT_EQ(sh_index(1, -1), 1);
    EXPECT_EQ(sh_index(2, 2), 8);
    EXPECT_EQ(sh_count(16), 256);
    EXPECT_EQ(sh_bands_for(1), 1);
    EXPECT_EQ(sh_bands_for(32), 6);
    EXPECT_EQ(sh_bands_for(48), 7);
    EXPECT_EQ(sh_bands_for(49), 7);
    EXPECT_EQ(sh_bands_for(256), 16);
    for (int i = 0; i < 4096; ++i) {
        const int l = sh_band(i);
        EXPECT_LE(l * l, i);
        EXPECT_GT((l + 1) * (l + 1), i);
    }
}

TEST(ShBasis, FastMatchesReferenceDouble30Bands) {
    const int bands = 31;  // l = 0..30
    std::vector<double> y(sh_count(bands));
    for (const Dir& d : random_dirs(200, 1)) {
        sh_eval(bands, d.x, d.y, d.z, y.data());
        for (int l = 0; l < bands; ++l)
            for (int m = -l; m <= l; ++m) {
                const double ref = sh_eval_reference(l, m, d.theta, d.phi);
                ASSERT_NEAR(y[sh_index(l, m)], ref, 1e-12 * (1.0 + std::abs(ref)))
                    << "l=" << l << " m=" << m << " theta=" << d.theta << " phi=" << d.phi;
            }
    }
}

TEST(ShBasis, FastMatchesReferenceFloat20Bands) {
    const int bands = 21;
    std::vector<float> y(sh_count(bands));
    for (const Dir& d : random_dirs(200, 2)) {
        sh_eval(bands, float(d.x), float(d.y), float(d.z), y.data());
        for (int l = 0; l < bands; ++l)
            for (int m = -l; m <= l; ++m) {
                const double ref = sh_eval_reference(l, m, d.theta, d.phi);
                // Float inputs carry ~6e-8 relative direction error, amplified by ~l² in band l.
                ASSERT_NEAR(y[sh_index(l, m)], ref, 2e-5 * (1.0 + std::abs(ref)))
                    << "l=" << l << " m=" << m;
            }
    }
}

TEST(ShBasis, ClosedFormsBands0To3) {
    for (const Dir& d : random_dirs(50, 3)) {
        const double x = d.x, y = d.y, z = d.z;
        std::vector<double> v(16);
        sh_eval(4, x, y, z, v.data());
        const double expected[16] = {
            0.5 * std::sqrt(1 / kPi),
            -std::sqrt(3 / (4 * kPi)) * y,
            std::sqrt(3 / (4 * kPi)) * z,
            -std::sqrt(3 / (4 * kPi)) * x,
            0.5 * std::sqrt(15 / kPi) * x * y,
            -0.5 * std::sqrt(15 / kPi) * y * z,
            0.25 * std::sqrt(5 / kPi) * (3 * z * z - 1),
            -0.5 * std::sqrt(15 / kPi) * x * z,
            0.25 * std::sqrt(15 / kPi) * (x * x - y * y),
            -0.25 * std::sqrt(35 / (2 * kPi)) * y * (3 * x * x - y * y),
            0.5 * std::sqrt(105 / kPi) * x * y * z,
            -0.25 * std::sqrt(21 / (2 * kPi)) * y * (5 * z * z - 1),
            0.25 * std::sqrt(7 / kPi) * z * (5 * z * z - 3),
            -0.25 * std::sqrt(21 / (2 * kPi)) * x * (5 * z * z - 1),
            0.25 * std::sqrt(105 / kPi) * z * (x * x - y * y),
            -0.25 * std::sqrt(35 / (2 * kPi)) * x * (x * x - 3 * y * y),
        };
        for (int i = 0; i < 16; ++i) EXPECT_NEAR(v[i], expected[i], 1e-13) << "index " << i;
    }
}

TEST(ShBasis, PartialBandWritesExactlyK) {
    std::vector<double> full(49), part(33, -7.0);
    sh_eval(7, 0.48, -0.6, 0.64, full.data());
    sh_eval_k(32, 0.48, -0.6, 0.64, part.data());
    for (int i = 0; i < 32; ++i) EXPECT_EQ(part[i], full[i]);
    EXPECT_EQ(part[32], -7.0) << "sh_eval_k wrote past K";
}

// The host evaluator tabulates the recurrence's factors once (the bake's basis table): the same
// bits as sh_eval_k, in double and in float, for partial and full bands, with nothing written
// past K.
template <class T>
void expect_evaluator_bits(int K) {
    const ShBasisEvaluator<T> eval(K);
    std::vector<T> want(std::size_t(K) + 1, T(-7)), got(std::size_t(K) + 1, T(-7));
    for (const Dir& d : random_dirs(200, 7 + unsigned(K))) {
        sh_eval_k(K, T(d.x), T(d.y), T(d.z), want.data());
        eval(T(d.x), T(d.y), T(d.z), got.data());
        for (int i = 0; i < K; ++i)
            ASSERT_EQ(std::memcmp(&got[std::size_t(i)], &want[std::size_t(i)], sizeof(T)), 0)
                << "K " << K << ", coefficient " << i << ": " << got[std::size_t(i)] << " vs "
                << want[std::size_t(i)];
        ASSERT_EQ(got[std::size_t(K)], T(-7)) << "K " << K << ": wrote past K";
    }
}

TEST(ShBasis, TabulatedEvaluatorGivesTheSameBits) {
    for (const int K : {1, 2, 4, 9, 17, 256, 700, 1024}) {
        expect_evaluator_bits<double>(K);
        expect_evaluator_bits<float>(K);
    }
}

TEST(ShBasis, OrthonormalByExactQuadrature30Bands) {
    const int bands = 31, K = sh_count(bands);
    // Products of two band-30 functions are degree-60 polynomials: 31 Gauss nodes in cos θ and
    // 61+ uniform φ nodes integrate them exactly.
    std::vector<double> gx, gw;
    gauss_legendre(32, gx, gw);
    const int nphi = 64;
    std::vector<double> gram(size_t(K) * K, 0.0), y(K);
    for (size_t a = 0; a < gx.size(); ++a) {
        const double z = gx[a], s = std::sqrt(1 - z * z);
        for (int b = 0; b < nphi; ++b) {
            const double phi = 2 * kPi * (b + 0.5) / nphi;
            sh_eval(bands, s * std::cos(phi), s * std::sin(phi), z, y.data());
            const double w = gw[a] * 2 * kPi / nphi;
            for (int i = 0; i < K; ++i) {
                const double wi = w * y[i];
                for (int j = i; j < K; ++j) gram[size_t(i) * K + j] += wi * y[j];
            }
        }
    }
    double worst = 0;
    for (int i = 0; i < K; ++i)
        for (int j = i; j < K; ++j)
            worst = std::max(worst, std::abs(gram[size_t(i) * K + j] - (i == j)));
    EXPECT_LT(worst, 1e-10);
}

TEST(ShBasis, ReferenceRejectsBadIndices) {
    EXPECT_THROW(sh_eval_reference(-1, 0, 0.1, 0.2), Error);
    EXPECT_THROW(sh_eval_reference(3, 4, 0.1, 0.2), Error);
    EXPECT_THROW(sh_eval_reference(81, 0, 0.1, 0.2), Error);
}

}  // namespace
}  // namespace shprt
