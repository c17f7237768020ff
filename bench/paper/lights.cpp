// The paper study's two lights (lights.hpp).
#include "paper/lights.hpp"

#include "shprt/light/light.hpp"

#include <fmt/format.h>

namespace shprt::paper {
namespace {

std::string vec_spec(Vec3d v) { return fmt::format("{:.6g},{:.6g},{:.6g}", v.x, v.y, v.z); }

GradientSky scaled(const GradientSky& s, double f) {
    return {s.zenith * f, s.horizon * f, s.ground * f};
}

std::string gradient_spec(const GradientSky& s) {
    return "gradient:" + vec_spec(s.zenith) + ":" + vec_spec(s.horizon) + ":" + vec_spec(s.ground);
}

}  // namespace

Lights make_lights() {
    Lights l;
    const GradientSky sky{};
    l.sun_dir = builtin_sun_direction();
    l.sky_specs = {gradient_spec(sky)};
    l.sun_specs = {fmt::format("sun:{},{:g}", vec_spec(l.sun_dir), kSunRadiusDeg),
                   gradient_spec(scaled(sky, kSunSkyScale))};
    l.truth.sky = [sky](Vec3d d) { return gradient_radiance(sky, d); };
    const Vec3d E{kSunIrradiance, kSunIrradiance, kSunIrradiance};
    l.truth.discs.push_back(
        {l.sun_dir, kSunRadiusDeg, sun_radiance_for_irradiance(E, kSunRadiusDeg)});
    return l;
}

std::string quote_specs(const std::vector<std::string>& specs) {
    std::string s;
    for (const auto& x : specs) s += (s.empty() ? "" : " + ") + ("`" + x + "`");
    return s;
}

}  // namespace shprt::paper
