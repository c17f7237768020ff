// The one sRGB pair (core/colour.hpp): every 8-bit code survives decode → encode, known values of
// the IEC 61966-2-1 curve, the curves invert each other, and out-of-range input is clamped.
#include "shprt/core/colour.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace shprt {
namespace {

TEST(Colour, SrgbRoundTripsEveryByteAndMatchesKnownValues) {
    for (int b = 0; b < 256; ++b)
        EXPECT_EQ(linear_to_srgb8(srgb_to_linear(static_cast<float>(b) / 255.0f)), b) << b;
    EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404114f, 1e-6f);
    EXPECT_NEAR(linear_to_srgb(0.5f), 0.73536f, 1e-5f);
    EXPECT_EQ(srgb_to_linear(0.0f), 0.0f);
    EXPECT_EQ(srgb_to_linear(1.0f), 1.0f);
    EXPECT_EQ(linear_to_srgb(1.0f), 1.0f);
    // The linear segment.
    EXPECT_FLOAT_EQ(srgb_to_linear(0.04f), 0.04f / 12.92f);
    EXPECT_FLOAT_EQ(linear_to_srgb(0.003f), 0.003f * 12.92f);
}

TEST(Colour, TheCurvesInvertEachOther) {
    for (int i = 0; i <= 255; ++i) {
        const float s = float(i) / 255.0f;
        EXPECT_NEAR(linear_to_srgb(srgb_to_linear(s)), s, 2e-6f) << i;
    }
}

TEST(Colour, OutOfRangeAndNanAreClamped) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(linear_to_srgb8(2.0f), 255);
    EXPECT_EQ(linear_to_srgb8(-1.0f), 0);
    EXPECT_EQ(linear_to_srgb8(nan), 0);
    EXPECT_EQ(linear_to_srgb(-0.5f), 0.0f);
    EXPECT_EQ(linear_to_srgb(7.0f), 1.0f);
    EXPECT_EQ(srgb_to_linear(-0.5f), 0.0f);
    EXPECT_EQ(srgb_to_linear(3.0f), 1.0f);
    EXPECT_EQ(srgb_to_linear(nan), 0.0f);
}

}  // namespace
}  // namespace shprt
