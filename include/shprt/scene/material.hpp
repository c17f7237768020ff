// A surface's glossy BRDF as a scene carries it: the model and its one parameter, per material
// (Mesh::brdfs). Shading turns it into a zonal lobe (render/glossy.hpp, docs/glossy.md); the
// loader reads it from the file's materials (scene/load.hpp).
#pragma once

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
    bool operator==(const Brdf&) const = default;
};

// "phong:E", "blinn:E" or "ggx:R"; throws Error(invalid_argument) naming `spec` and the problem.
Brdf parse_brdf(const std::string& spec);
// The spec parse_brdf reads, e.g. "ggx:0.3" (the shortest text that reads back to the same
// parameter).
std::string to_string(const Brdf& brdf);
// Throws Error(invalid_argument) unless the parameter is in its model's range (above).
void check_brdf(const Brdf& brdf);

}  // namespace shprt
