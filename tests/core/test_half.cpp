// float_to_half / half_to_float against known values, a slow reference built from the definition
// of binary16 (exact decoding in double, nearest value by search, ties to even), and, where the
// compiler has _Float16, its conversions.
#include "shprt/core/half.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace shprt {
namespace {

float from_bits(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

bool half_is_nan(std::uint16_t h) { return (h & 0x7c00u) == 0x7c00u && (h & 0x3ffu) != 0; }

// Exact value of a finite binary16, from its definition.
double reference_half_value(std::uint16_t h) {
    const int e = (h >> 10) & 0x1f;
    const int m = h & 0x3ff;
    const double magnitude =
        e == 0 ? std::ldexp(double(m), -24) : std::ldexp(double(1024 + m), e - 25);
    return (h & 0x8000) ? -magnitude : magnitude;
}

// Nearest binary16 by binary search over all positive finite values, ties to the even mantissa;
// values at or past the midpoint between 65504 and 2^16 overflow to infinity (IEEE rule).
std::uint16_t reference_float_to_half(float f) {
    static const std::vector<double> values = [] {
        std::vector<double> v;
        for (std::uint32_t h = 0; h <= 0x7bff; ++h)
            v.push_back(reference_half_value(std::uint16_t(h)));
        v.push_back(65536.0);  // the next value binary16 would have: rounding towards it is inf
        return v;
    }();
    const std::uint16_t sign = std::signbit(f) ? 0x8000 : 0;
    const double a = std::fabs(double(f));
    if (std::isinf(f)) return sign | 0x7c00;
    const auto it = std::upper_bound(values.begin(), values.end(), a);
    const std::size_t lo = std::size_t(it - values.begin()) - 1;  // values[0] = 0 <= a
    if (values[lo] == a) return std::uint16_t(sign | lo);
    const std::size_t hi = lo + 1;
    const double dlo = a - values[lo], dhi = values[hi] - a;
    std::size_t pick = dlo < dhi ? lo : (dhi < dlo ? hi : (lo % 2 == 0 ? lo : hi));
    return std::uint16_t(sign | (pick > 0x7bff ? 0x7c00 : pick));
}

TEST(IoHalf, KnownValues) {
    struct Case {
        float f;
        std::uint16_t h;
    };
    const Case cases[] = {
        {0.0f, 0x0000},
        {-0.0f, 0x8000},
        {1.0f, 0x3c00},
        {-2.0f, 0xc000},
        {0.5f, 0x3800},
        {0.1f, 0x2e66},
        {1.0f / 3.0f, 0x3555},
        {65504.0f, 0x7bff},   // largest finite
        {65519.99f, 0x7bff},  // just below the overflow midpoint
        {65520.0f, 0x7c00},   // the midpoint rounds (to even) to inf
        {1e9f, 0x7c00},
        {-1e9f, 0xfc00},
        {std::numeric_limits<float>::infinity(), 0x7c00},
        {-std::numeric_limits<float>::infinity(), 0xfc00},
        {std::ldexp(1.0f, -14), 0x0400},             // smallest normal
        {std::ldexp(1.0f, -24), 0x0001},             // smallest subnormal
        {std::ldexp(1023.0f, -24), 0x03ff},          // largest subnormal
        {std::ldexp(1.0f, -25), 0x0000},             // half of the smallest: tie to even (0)
        {std::ldexp(1.5f, -25), 0x0001},             // above the tie: rounds up
        {std::ldexp(3.0f, -25), 0x0002},             // 1.5 ulp: tie to even (2)
        {std::ldexp(1023.5f, -24), 0x0400},          // rounds up into the normals
        {1.0f + std::ldexp(1.0f, -11), 0x3c00},      // tie between 0x3c00 and 0x3c01: even
        {1.0f + 3 * std::ldexp(1.0f, -11), 0x3c02},  // tie between 0x3c01 and 0x3c02: even
        {1.0f + std::ldexp(1.0f, -11) + std::ldexp(1.0f, -20), 0x3c01},  // above the tie
        {2047.0f / 1024.0f + std::ldexp(1.0f, -11), 0x4000},  // mantissa carry into exponent
        {std::numeric_limits<float>::denorm_min(), 0x0000},   // float subnormal -> 0
        {-std::numeric_limits<float>::denorm_min(), 0x8000},
    };
    for (const Case& c : cases) {
        EXPECT_EQ(float_to_half(c.f), c.h) << "f = " << c.f;
        EXPECT_EQ(reference_float_to_half(c.f), c.h) << "reference, f = " << c.f;
    }
    EXPECT_EQ(half_to_float(0x7bff), 65504.0f);
    EXPECT_EQ(half_to_float(0x0001), std::ldexp(1.0f, -24));
    EXPECT_EQ(half_to_float(0x3555), 0.333251953125f);
    EXPECT_TRUE(std::signbit(half_to_float(0x8000)));
    EXPECT_TRUE(std::isinf(half_to_float(0xfc00)) && half_to_float(0xfc00) < 0);
}

TEST(IoHalf, NanStaysNanWithSign) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(half_is_nan(float_to_half(nan)));
    EXPECT_TRUE(half_is_nan(float_to_half(-nan)));
    EXPECT_EQ(float_to_half(-nan) & 0x8000, 0x8000);
    // A signalling NaN whose payload lies only in the low bits must not become infinity.
    EXPECT_TRUE(half_is_nan(float_to_half(from_bits(0x7f800001u))));
    EXPECT_TRUE(std::isnan(half_to_float(0x7e00)));
    EXPECT_TRUE(std::isnan(half_to_float(0x7c01)));
}

// Every binary16 value: decoding matches the exact definition and encoding gives it back.
TEST(IoHalf, ExhaustiveDecodeAndRoundTrip) {
    for (std::uint32_t h = 0; h <= 0xffff; ++h) {
        const auto hh = std::uint16_t(h);
        const float f = half_to_float(hh);
        if (half_is_nan(hh)) {
            EXPECT_TRUE(std::isnan(f)) << std::hex << h;
            EXPECT_TRUE(half_is_nan(float_to_half(f))) << std::hex << h;
            continue;
        }
        if ((hh & 0x7fff) == 0x7c00) {
            EXPECT_TRUE(std::isinf(f)) << std::hex << h;
        } else {
            ASSERT_EQ(double(f), reference_half_value(hh)) << std::hex << h;
        }
        ASSERT_EQ(float_to_half(f), hh) << std::hex << h;
    }
}

// Rounding: every midpoint between neighbouring binary16 values and the floats on either side
// of it, plus a million random float bit patterns, against the reference.
TEST(IoHalf, RoundingMatchesReference) {
    std::vector<float> inputs;
    for (std::uint32_t h = 0; h < 0x7bff; ++h) {
        const double mid = 0.5 * (reference_half_value(std::uint16_t(h)) +
                                  reference_half_value(std::uint16_t(h + 1)));
        const float m = float(mid);  // exact: a binary16 midpoint needs 12 significant bits
        ASSERT_EQ(double(m), mid);
        for (float x : {m, std::nextafter(m, 0.0f), std::nextafter(m, 1e30f)}) {
            inputs.push_back(x);
            inputs.push_back(-x);
        }
    }
    std::mt19937 rng(12345);
    for (int i = 0; i < 1000000; ++i) {
        const float f = from_bits(std::uint32_t(rng()));
        if (!std::isnan(f)) inputs.push_back(f);
    }
    for (float f : inputs) ASSERT_EQ(float_to_half(f), reference_float_to_half(f)) << "f = " << f;
#if defined(__FLT16_MAX__)
    // The compiler's own conversion (F16C or soft-float), a third opinion.
    for (float f : inputs) {
        const _Float16 c = static_cast<_Float16>(f);
        std::uint16_t bits;
        std::memcpy(&bits, &c, sizeof bits);
        ASSERT_EQ(float_to_half(f), bits) << "f = " << f;
    }
#endif
}

// Relative error bound the file format documents for float16 coefficients.
TEST(IoHalf, RelativeErrorWithinHalfUlp) {
    constexpr float kHalfRelativeError = 1.0f / 2048.0f;  // 2^-11 for normal binary16 values
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> dist(-60000.0f, 60000.0f);
    for (int i = 0; i < 100000; ++i) {
        float f = dist(rng) * (i % 2 ? 1.0f : 1e-3f);
        if (std::fabs(f) < std::ldexp(1.0f, -14)) continue;
        const float back = half_to_float(float_to_half(f));
        EXPECT_LE(std::fabs(back - f), kHalfRelativeError * std::fabs(f)) << f;
    }
}

}  // namespace
}  // namespace shprt
