// Display transforms of the picture writers: PNG files (save_image), display-encoded PLY colours
// (write_shade_ply); the OpenGL renderer's present shader mirrors the same formulas. Pure math,
// host and device.
//
// * Tone map: Krzysztof Narkowicz's fit of the ACES filmic reference rendering transform
//   ("ACES Filmic Tone Mapping Curve", 2016): f(x) = x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14),
//   clamped to [0, 1], applied per channel to linear RGB after multiplying by the exposure. It
//   maps 0 → 0, is monotonic, and reaches about 0.8 at x = 1.
// * sRGB: the exact IEC 61966-2-1 piecewise curve (core/colour.hpp).
#pragma once

#include "shprt/core/colour.hpp"
#include "shprt/core/hd.hpp"

namespace shprt {

// Narkowicz's ACES filmic fit, clamped to [0, 1]; negative and NaN inputs give 0.
SHPRT_HD_INLINE float tonemap_aces(float x) {
    if (!(x > 0.0f)) return 0.0f;
    const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    return y < 1.0f ? y : 1.0f;
}

// The PNG writer's full chain for one channel: 8-bit code of srgb(tonemap(exposure · x)), rounded
// to nearest.
SHPRT_HD_INLINE unsigned char display_encode8(float x, float exposure) {
    const float s = linear_to_srgb(tonemap_aces(x * exposure));
    return static_cast<unsigned char>(s * 255.0f + 0.5f);
}

}  // namespace shprt
