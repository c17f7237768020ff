// sRGB transfer functions, IEC 61966-2-1:1999 (piecewise: linear segment below 0.04045 /
// 0.0031308).
#include "shprt/scene/colour.hpp"

#include <algorithm>
#include <cmath>

namespace shprt {
namespace {
float clamp01(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; }  // NaN -> 0
}  // namespace

float srgb_to_linear(float encoded) {
    const float c = clamp01(encoded);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
    const float c = clamp01(linear);
    return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

std::uint8_t linear_to_srgb8(float linear) {
    const float v = std::round(linear_to_srgb(linear) * 255.0f);
    return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f));
}

}  // namespace shprt
