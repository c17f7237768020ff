// The one path for a light (light_setup.hpp): project with full bands, window, rotate, truncate.
// Rotation of SH coefficients: Ivanic & Ruedenberg 1996 (through rotate_light); rotating the
// light rather than re-projecting it: Sloan, Kautz & Snyder 2002 §6.
#include "shprt/light/light_setup.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"

#include <algorithm>

namespace shprt {

ShLight light_source(const LightSetup& setup, int K) {
    SHPRT_CHECK(K >= 1 && K <= kMaxLightK, invalid_argument,
                "light basis size K = {} is outside 1..{}", K, kMaxLightK);
    const int full = sh_count(sh_bands_for(K));
    if (setup.specs.empty() && setup.sun) return ShLight::zero(full);  // the sun alone
    ShLight light = make_light(setup.specs, full);
    window_light(light, setup.window, setup.window_strength);
    return light;
}

PreparedSun prepare_sun(const LightSetup& setup, int K) {
    SHPRT_CHECK(setup.sun.has_value(), invalid_argument, "prepare_sun: the light setup has no sun");
    SHPRT_CHECK(K >= 1 && K <= kMaxLightK, invalid_argument,
                "light basis size K = {} is outside 1..{}", K, kMaxLightK);
    ShLight source = sun_light(*setup.sun, sh_count(sh_bands_for(K)));
    window_light(source, setup.window, setup.window_strength);
    const Mat3d R = light_rotation(setup);
    PreparedSun out;
    out.sun = *setup.sun;
    if (!(R == Mat3d::identity())) out.sun.direction = normalize(R * setup.sun->direction);
    out.sh = rotated_light(source, R, K);
    return out;
}

Mat3d light_rotation(const LightSetup& setup) {
    const Vec3d a = setup.yaw_pitch_roll_deg;
    if (a.x == 0 && a.y == 0 && a.z == 0) return Mat3d::identity();
    return matrix_from_yaw_pitch_roll_deg(a.x, a.y, a.z);
}

ShLight rotated_light(const ShLight& source, const Mat3d& R, int K) {
    SHPRT_CHECK(source.K >= 1 && source.coeffs.size() == 3 * std::size_t(source.K),
                invalid_argument, "rotated_light: malformed light (K = {}, {} coefficients)",
                source.K, source.coeffs.size());
    SHPRT_CHECK(K >= 1 && K <= source.K, invalid_argument,
                "rotated_light: K = {} is outside 1..{} (the source's basis size)", K, source.K);
    const bool turned = !(R == Mat3d::identity());
    if (!turned && K == source.K) return source;
    ShLight full = source;
    if (turned) rotate_light(full, R);
    if (K == full.K) return full;
    ShLight out = ShLight::zero(K);
    for (int c = 0; c < 3; ++c) std::copy_n(full.channel(c), K, out.channel(c));
    return out;
}

ShLight prepare_light(const LightSetup& setup, int K) {
    return rotated_light(light_source(setup, K), light_rotation(setup), K);
}

Vec3d parse_yaw_pitch_roll(const std::string& text) {
    const std::vector<double> v = parse_numbers(text, 3, "rotation YAW,PITCH,ROLL (degrees)");
    return {v[0], v[1], v[2]};
}

}  // namespace shprt
