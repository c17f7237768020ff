// A surface's glossy BRDF as a scene carries it: the model, its one parameter and its specular
// colour, per material (Mesh::brdfs). Shading turns it into a zonal lobe times the colour
// (shade/glossy.hpp, docs/glossy.md); the loader reads it from the file's materials
// (scene/load.hpp).
#pragma once

#include "shprt/core/vec.hpp"

#include <string>

namespace shprt {

// Default Phong exponent of the glossy lobe (`--gloss`, and Brdf's default).
inline constexpr double kDefaultGloss = 16.0;
// Lowest GGX roughness: narrower lobes need more quadrature nodes than the zonal fit uses (and far
// more bands than a transfer matrix has).
inline constexpr double kMinGgxRoughness = 0.05;
// Highest Phong or Blinn–Phong exponent.
inline constexpr double kMaxBrdfExponent = 1e4;

enum class BrdfModel { phong, blinn_phong, ggx };

struct Brdf {
    BrdfModel model = BrdfModel::phong;
    double parameter = kDefaultGloss;  // Phong/Blinn exponent E in [0, 1e4], or GGX roughness R
                                       // in [0.05, 1]
    // ρ_s: the colour the lobe's reflection is multiplied by (linear RGB, each in [0, 1]; white
    // for a dielectric's highlight, the metal's colour for a metal). The lobe does not depend
    // on it.
    Vec3f specular{1, 1, 1};
    bool operator==(const Brdf&) const = default;
};

// "phong:E", "blinn:E" or "ggx:R", each optionally followed by ":R,G,B", the specular colour
// (white without it), e.g. "ggx:0.4:1,0.71,0.29" (gold); throws Error(invalid_argument) naming
// `spec` and the problem.
Brdf parse_brdf(const std::string& spec);
// The spec parse_brdf reads, e.g. "ggx:0.3" or "phong:40:0.9,0.5,0.2": the shortest text that
// reads back to the same parameter and colour; the colour only where it is not white.
std::string to_string(const Brdf& brdf);
// Throws Error(invalid_argument) unless the parameter is in its model's range (above) and each
// specular channel is in [0, 1].
void check_brdf(const Brdf& brdf);

}  // namespace shprt
