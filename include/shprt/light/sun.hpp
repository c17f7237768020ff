// The sun: a disc of constant radiance around one direction. One model for both ways shprt lights
// with it:
//   * projected into the SH sum (`--light sun:X,Y,Z[,RADIUS_DEG[,R,G,B]]`, light.hpp's parse_light:
//     sun_light below, exact zonal projection), soft by construction: K coefficients cannot hold a
//     disc of a few degrees (docs/lights.md, "The sun");
//   * kept out of the SH sum (`--sun X,Y,Z[,RADIUS_DEG[,R,G,B]]`, shade/sun_shade.hpp): its direct
//     light traced per receiver through the disc directions below, its bounced light from an
//     interreflected file's T − T₀ under sun_light's projection (docs/lights.md, "A sun kept out of
//     the SH sum").
//
// Conventions (light.hpp): `direction` points from the scene toward the sun, world space, +Y up;
// `radiance` is the disc's radiance per channel (linear RGB). A disc of angular radius r and
// radiance L subtends Ω = 2π(1 − cos r) and gives irradiance E = L·π·sin²r at normal incidence
// (∫ over the cap of cos θ dω). The default radiance gives E = kDefaultSunIrradiance per channel.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace shprt {

inline constexpr double kDefaultSunRadiusDeg = 2.0;
inline constexpr double kDefaultSunIrradiance = 3.0;  // per channel, at normal incidence

struct Sun {
    Vec3d direction{0, 1, 0};                  // unit, toward the sun
    double radius_deg = kDefaultSunRadiusDeg;  // angular radius, in (0, 90]
    Vec3d radiance{0, 0, 0};                   // per channel, ≥ 0
    bool operator==(const Sun&) const = default;
};

// A checked Sun: `direction` finite and non-zero (normalised here), radius in (0, 90], radiance
// finite and ≥ 0. Throws Error(invalid_argument) "sun direction (0, 0, 0) must be finite and
// non-zero", "sun radius 95° must be in (0, 90]", "sun radiance (...) must be finite and
// non-negative".
Sun make_sun(Vec3d direction, double radius_deg, Vec3d radiance);

// The numbers of a sun spec, "X,Y,Z[,RADIUS_DEG[,R,G,B]]" (3, 4 or 7 finite numbers; radius 2° and
// irradiance 3 per channel by default): what follows `sun:` in a light spec and what `--sun`
// takes. Every error is one Error(invalid_argument) line that begins with `what` (e.g.
// "light 'sun:1,2'" or "--sun '1,2'") and, for a wrong count, names `syntax`:
//   "--sun '1,2': expected X,Y,Z[,RADIUS_DEG[,R,G,B]] (3, 4 or 7 numbers), got 2 numbers"
Sun parse_sun(std::string_view numbers, const std::string& what, const std::string& syntax);

// Ω = 2π(1 − cos r), steradians.
double sun_solid_angle(const Sun& sun);
// E = L·π·sin²r per channel: the irradiance of the whole disc at normal incidence.
Vec3d sun_irradiance(const Sun& sun);

// The sun projected into SH, exactly (zonal quadrature of the disc, then the zonal rotation
// identity): basis size K, 1 ≤ K ≤ kMaxLightK. The same coefficients as `sun:` gives in a light.
ShLight sun_light(const Sun& sun, int K);

// Largest disc sample count sun_disc_directions accepts (64 × 64).
inline constexpr int kMaxSunSamples = 4096;

// `count` directions on the sun's disc, each standing for Ω/count of it: for count = n² > 1 an
// n × n jittered grid on the unit square (jitter from Philox(seed, cell, kStreamSunDisc)), mapped
// to the unit disc by Shirley & Chiu's concentric map (area-preserving) and the disc to the cap
// by 1 − cos θ = ρ²(1 − cos r) (area-preserving again: uniform in solid angle). count = 1 is the
// centre direction itself: a point sun. A pure function of (sun, count, seed): the same set for
// every receiver, thread and run. Throws Error(invalid_argument) unless count is a square in
// [1, kMaxSunSamples].
inline constexpr std::uint32_t kStreamSunDisc = 0x53500010u;
std::vector<Vec3d> sun_disc_directions(const Sun& sun, int count, std::uint64_t seed);

}  // namespace shprt
