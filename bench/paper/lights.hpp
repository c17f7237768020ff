// The paper study's two lights (docs/paper_table.md): a smooth sky, and a small sun over a dim copy
// of that sky. Each is given as --light specs (make_light, at any K) and in the direct form the
// ground truth integrates without SH (bake/ground_truth.hpp).
#pragma once

#include "shprt/bake/ground_truth.hpp"
#include "shprt/core/vec.hpp"

#include <string>
#include <vector>

namespace shprt::paper {

// The smooth sky (light/light.hpp GradientSky defaults), and the sun scene's dim sky: the same
// gradient at kSunSkyScale, so that shadows are dark but not black.
inline constexpr double kSunSkyScale = 0.15;
inline constexpr double kSunRadiusDeg = 2.0;
inline constexpr double kSunIrradiance =
    3.0;  // at normal incidence, white (the sun spec's default)

struct Lights {
    std::vector<std::string> sky_specs, sun_specs;  // --light specs
    GroundTruthLight truth;                         // sky = the full gradient; disc = the sun
    Vec3d sun_dir;                                  // builtin_sun_direction()
};

Lights make_lights();

// The specs as the report quotes them: "`a` + `b`".
std::string quote_specs(const std::vector<std::string>& specs);

}  // namespace shprt::paper
