// Light preparation shared by the shading tools: project, window, rotate, truncate.
#include "shprt/render/light_setup.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"

#include <vector>

namespace shprt {

ShLight prepare_light(const LightSetup& setup, int K) {
    SHPRT_CHECK(K >= 1 && K <= kMaxLightK, invalid_argument,
                "light basis size K = {} is outside 1..{}", K, kMaxLightK);
    const int full = sh_count(sh_bands_for(K));
    ShLight light = make_light(setup.specs, full);
    window_light(light, setup.window, setup.window_strength);
    const Vec3d a = setup.yaw_pitch_roll_deg;
    if (a.x != 0 || a.y != 0 || a.z != 0)
        rotate_light(light, matrix_from_yaw_pitch_roll_deg(a.x, a.y, a.z));
    if (full == K) return light;
    ShLight out = ShLight::zero(K);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < K; ++i) out.channel(c)[i] = light.channel(c)[i];
    return out;
}

Vec3d parse_yaw_pitch_roll(const std::string& text) {
    const std::vector<double> v = parse_numbers(text, 3, "rotation YAW,PITCH,ROLL (degrees)");
    return {v[0], v[1], v[2]};
}

}  // namespace shprt
