// sRGB transfer functions (IEC 61966-2-1:1999, the exact piecewise curve: a linear segment below
// 0.04045 encoded / 0.0031308 linear), defined once for every layer that converts between 8-bit
// file colours and linear RGB: scene colours (PLY albedo), PNG light images, PNG pictures and the
// renderer's display encoding. Pure math, host and device.
#pragma once

#include "shprt/core/hd.hpp"

#include <cmath>
#include <cstdint>

namespace shprt {

// sRGB-encoded [0, 1] → linear [0, 1]; inputs outside [0, 1] are clamped, NaN gives 0.
SHPRT_HD_INLINE float srgb_to_linear(float s) {
    if (!(s > 0.0f)) return 0.0f;
    if (s >= 1.0f) return 1.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

// Linear [0, 1] → sRGB-encoded [0, 1]; inputs outside [0, 1] are clamped, NaN gives 0.
SHPRT_HD_INLINE float linear_to_srgb(float x) {
    if (!(x > 0.0f)) return 0.0f;
    if (x >= 1.0f) return 1.0f;
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

// Linear → 8-bit sRGB code, rounded to nearest, halves away from zero (linear_to_srgb clamps, so
// the code is 0..255).
SHPRT_HD_INLINE std::uint8_t linear_to_srgb8(float x) {
    return static_cast<std::uint8_t>(std::round(linear_to_srgb(x) * 255.0f));
}

}  // namespace shprt
