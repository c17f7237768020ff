// sRGB transfer functions (IEC 61966-2-1) for converting between 8-bit file colours and the
// linear RGB albedo that shprt stores and shades with.
#pragma once

#include <cstdint>

namespace shprt {

// Decodes one sRGB-encoded channel in [0, 1] to linear [0, 1]; inputs outside [0, 1] are clamped.
float srgb_to_linear(float encoded);

// Encodes one linear channel in [0, 1] to sRGB [0, 1]; inputs outside [0, 1] (and NaN) are
// clamped.
float linear_to_srgb(float linear);

// Encodes one linear channel to an 8-bit sRGB value, rounded to nearest.
std::uint8_t linear_to_srgb8(float linear);

}  // namespace shprt
