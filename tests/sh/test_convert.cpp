// SH convention converters: round trips, and "the same function" checks — the converted
// coefficients evaluated with the other convention's own basis polynomials (as its source code
// writes them) equal ours evaluated at the same physical direction. Known values from the
// engines' constants.
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/convert.hpp"
#include "shprt/sh/zonal.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace shprt {
namespace {

constexpr double kTightTol = 1e-14;
constexpr double kThreeTol = 2e-5;  // three.js rounds its constants to 6 digits

using Arr9 = std::array<double, 9>;

Arr9 random9(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    Arr9 a;
    for (double& v : a) v = u(rng);
    return a;
}

double ours(const Arr9& c, double x, double y, double z) {
    double b[9];
    sh_eval(3, x, y, z, b);
    double s = 0;
    for (int i = 0; i < 9; ++i) s += c[i] * b[i];
    return s;
}

// three.js SphericalHarmonics3.getAt, constants as in its source.
double threejs_get_at(const Arr9& c, double x, double y, double z) {
    return c[0] * 0.282095 + c[1] * 0.488603 * y + c[2] * 0.488603 * z + c[3] * 0.488603 * x +
           c[4] * 1.092548 * x * y + c[5] * 1.092548 * y * z + c[6] * 0.315392 * (3 * z * z - 1) +
           c[7] * 1.092548 * x * z + c[8] * 0.546274 * (x * x - y * y);
}

// Unity / Sloan basis: {k0, −k1, k1, −k1, k2, −k2, k3, −k2, k4} on
// (1, y, z, x, xy, yz, 3z²−1, xz, x²−y²), in Unity's own (left-handed) coordinates.
double unity_canonical_eval(const Arr9& c, double x, double y, double z) {
    const double k0 = 0.28209479177387814347, k1 = 0.48860251190291992159,
                 k2 = 1.09254843059207907054, k3 = 0.31539156525252000603,
                 k4 = 0.54627421529603953527;
    return c[0] * k0 - c[1] * k1 * y + c[2] * k1 * z - c[3] * k1 * x + c[4] * k2 * x * y -
           c[5] * k2 * y * z + c[6] * k3 * (3 * z * z - 1) - c[7] * k2 * x * z +
           c[8] * k4 * (x * x - y * y);
}

// Unity's shader evaluation of a stored probe (the packing of HDRP's PackCoefficients).
double unity_probe_eval(const Arr9& s, double x, double y, double z) {
    return (s[0] - s[6]) + s[1] * y + s[2] * z + s[3] * x + s[4] * x * y + s[5] * y * z +
           3 * s[6] * z * z + s[7] * x * z + s[8] * (x * x - y * y);
}

std::vector<std::array<double, 3>> some_dirs() {
    std::mt19937_64 rng(9);
    std::normal_distribution<double> n(0, 1);
    std::vector<std::array<double, 3>> d = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 30; ++i) {
        const double x = n(rng), y = n(rng), z = n(rng), l = std::sqrt(x * x + y * y + z * z);
        d.push_back({x / l, y / l, z / l});
    }
    return d;
}

TEST(Convert, RoundTrips) {
    std::mt19937_64 rng(1);
    using Fn = void (*)(const double*, double*);
    const std::pair<Fn, Fn> pairs[] = {{to_threejs_l2, from_threejs_l2},
                                       {to_unity_l2, from_unity_l2},
                                       {to_unity_probe_l2, from_unity_probe_l2}};
    for (auto [to, from] : pairs) {
        const Arr9 c = random9(rng);
        Arr9 a, b;
        to(c.data(), a.data());
        from(a.data(), b.data());
        for (int i = 0; i < 9; ++i) EXPECT_NEAR(b[i], c[i], kTightTol);
        Arr9 in_place = c;  // in == out allowed
        to(in_place.data(), in_place.data());
        for (int i = 0; i < 9; ++i) EXPECT_EQ(in_place[i], a[i]);
    }
    std::vector<double> c(100), a(100), b(100);
    for (int i = 0; i < 100; ++i) c[i] = std::sin(1.0 + i);
    to_no_condon_shortley(c.data(), a.data(), 100);
    from_no_condon_shortley(a.data(), b.data(), 100);
    EXPECT_EQ(b, c);
}

TEST(Convert, NoCondonShortleyBasisRepresentsTheSameFunction) {
    const int bands = 9, K = sh_count(bands);
    std::vector<double> c(K), nc(K), y(K);
    for (int i = 0; i < K; ++i) c[i] = std::cos(0.3 * i);
    to_no_condon_shortley(c.data(), nc.data(), K);
    for (const auto& d : some_dirs()) {
        sh_eval(bands, d[0], d[1], d[2], y.data());
        double f = 0, g = 0;
        for (int l = 0; l < bands; ++l)
            for (int m = -l; m <= l; ++m) {
                const int i = sh_index(l, m);
                f += c[i] * y[i];
                g += nc[i] * ((m & 1) ? -y[i] : y[i]);  // y'_lm = (−1)^m y_lm
            }
        EXPECT_NEAR(f, g, kTightTol * 10);
    }
    // Known signs: (1,±1) and (2,±1) flip, the rest stay.
    Arr9 e{}, out{};
    for (int i = 0; i < 9; ++i) e[i] = 1;
    to_no_condon_shortley(e.data(), out.data(), 9);
    const Arr9 expected{1, -1, 1, -1, 1, -1, 1, -1, 1};
    EXPECT_EQ(out, expected);
}

TEST(Convert, ThreeJsGetAtSeesTheSameFunction) {
    std::mt19937_64 rng(2);
    for (int t = 0; t < 5; ++t) {
        const Arr9 c = random9(rng);
        Arr9 three;
        to_threejs_l2(c.data(), three.data());
        for (const auto& d : some_dirs())  // three.js world axes = ours
            EXPECT_NEAR(threejs_get_at(three, d[0], d[1], d[2]), ours(c, d[0], d[1], d[2]),
                        kThreeTol);
    }
    // Known value: our y_{1,1} = −0.488603·x is three.js coefficient 3 with value −1.
    Arr9 c{};
    c[3] = 1;
    Arr9 three;
    to_threejs_l2(c.data(), three.data());
    EXPECT_EQ(three[3], -1.0);
}

TEST(Convert, UnityCanonicalSeesTheSameFunctionInUnityAxes) {
    std::mt19937_64 rng(3);
    for (int t = 0; t < 5; ++t) {
        const Arr9 c = random9(rng);
        Arr9 u;
        to_unity_l2(c.data(), u.data());
        for (const auto& d : some_dirs())  // d_unity = (−x, y, z)
            EXPECT_NEAR(unity_canonical_eval(u, -d[0], d[1], d[2]), ours(c, d[0], d[1], d[2]),
                        kTightTol * 10);
    }
}

TEST(Convert, UnityProbeGivesIrradianceOverPi) {
    std::mt19937_64 rng(4);
    const std::vector<double> z = clamped_cosine_zonal(3);
    for (int t = 0; t < 5; ++t) {
        const Arr9 radiance = random9(rng);
        Arr9 irr = radiance, probe;
        convolve_zonal(z.data(), 3, irr.data(), 9);
        to_unity_probe_l2(radiance.data(), probe.data());
        for (const auto& d : some_dirs())
            EXPECT_NEAR(unity_probe_eval(probe, -d[0], d[1], d[2]),
                        ours(irr, d[0], d[1], d[2]) / kPi, kTightTol * 10);
    }
    // White sky of radiance 1: Unity's shader returns exactly 1 (= E/π) everywhere.
    Arr9 white{}, probe;
    white[0] = std::sqrt(4 * kPi);
    to_unity_probe_l2(white.data(), probe.data());
    EXPECT_NEAR(probe[0], 1.0, kTightTol);
    for (int i = 1; i < 9; ++i) EXPECT_EQ(probe[i], 0.0);
    // Unity's own constants (HDRP SphericalHarmonicMath.invNormConsts, float):
    const Arr9 inv_norm{3.5449076,  -3.0699801, 3.0699801,  -3.0699801, 3.6611648,
                        -3.6611648, 12.682647,  -3.6611648, 7.3223295};
    const Arr9 mirror{1, 1, 1, -1, -1, 1, 1, -1, 1};  // x → −x signs per index
    for (int i = 0; i < 9; ++i) {
        Arr9 e{}, back;
        e[i] = 1;
        from_unity_probe_l2(e.data(), back.data());
        EXPECT_NEAR(back[i] * mirror[i], inv_norm[i], 1e-6 * std::abs(inv_norm[i])) << i;
    }
}

TEST(Convert, BadInputThrows) {
    double a[4] = {}, b[4];
    EXPECT_THROW(to_no_condon_shortley(a, b, -1), Error);
    EXPECT_THROW(from_no_condon_shortley(a, b, -3), Error);
    EXPECT_NO_THROW(to_no_condon_shortley(a, b, 0));
}

}  // namespace
}  // namespace shprt
