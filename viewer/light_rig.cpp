// The viewer's light: full-band source + rotation by drag (light_rig.hpp), both through the one
// light path of light/light_setup.hpp (light_source, light_rotation, rotated_light).
#include "light_rig.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"

#include <cmath>

namespace shprt::viewer {
namespace {

// Gram–Schmidt on the rows: thousands of small drags must not drift away from a rotation.
Mat3d orthonormalize(const Mat3d& R) {
    Vec3d a{R.m[0][0], R.m[0][1], R.m[0][2]}, b{R.m[1][0], R.m[1][1], R.m[1][2]};
    a = normalize(a);
    b = normalize(b - a * dot(a, b));
    const Vec3d c = cross(a, b);
    return {{{a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z}}};
}

}  // namespace

Mat3d light_drag_rotation(double dx_px, double dy_px, Vec3d right) {
    const Mat3d yaw = rotation_y(dx_px * kLightRadiansPerPixel);
    const double n = length(right);
    if (!(n > 0) || dy_px == 0) return yaw;
    const Mat3d pitch =
        matrix_from_quat(quat_from_axis_angle(right / n, dy_px * kLightRadiansPerPixel));
    return pitch * yaw;
}

LightRig::LightRig(int K) : m_K(K) {
    SHPRT_CHECK(K >= 1 && K <= kMaxLightK, invalid_argument,
                "light basis size K = {} is outside 1..{}", K, kMaxLightK);
}

void LightRig::set_source(const LightSetup& setup) {
    ShLight source = light_source(setup, m_K);
    std::optional<PreparedSun> sun;
    if (setup.sun) {
        LightSetup unturned = setup;
        unturned.yaw_pitch_roll_deg = {0, 0, 0};
        sun = prepare_sun(unturned, m_K);
    }
    m_base = light_rotation(setup);
    m_source = std::move(source);
    m_sun = std::move(sun);
    m_setup = setup;
    m_has_source = true;
}

void LightRig::drag(double dx_px, double dy_px, Vec3d right) {
    if (dx_px == 0 && dy_px == 0) return;
    m_drag = orthonormalize(light_drag_rotation(dx_px, dy_px, right) * m_drag);
}

void LightRig::reset_drag() { m_drag = Mat3d::identity(); }

Mat3d LightRig::rotation() const { return m_drag * m_base; }

const ShLight& LightRig::source() const {
    SHPRT_CHECK(m_has_source, invalid_argument, "LightRig::source before set_source");
    return m_source;
}

ShLight LightRig::light() const {
    SHPRT_CHECK(m_has_source, invalid_argument, "LightRig::light before set_source");
    return rotated_light(m_source, rotation(), m_K);
}

}  // namespace shprt::viewer
