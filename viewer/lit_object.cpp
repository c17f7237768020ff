#include "lit_object.hpp"

#include <chrono>

namespace shprt::viewer {

namespace {
bool same(const ObjectPose& a, const ObjectPose& b) {
    return a.position == b.position && a.scale == b.scale &&
           a.yaw_pitch_roll_deg == b.yaw_pitch_roll_deg;
}
bool same(const ObjectShadeOptions& a, const ObjectShadeOptions& b) {
    return a.view == b.view && a.k == b.k && a.brdf == b.brdf &&
           a.material_brdfs == b.material_brdfs && a.albedo == b.albedo && a.eye == b.eye &&
           a.K_used == b.K_used;
}
}  // namespace

Vec3f object_step(Vec3f camera_right, Vec3f camera_forward, float along, float ahead, float up) {
    const auto horizontal = [](Vec3f v) {
        v.y = 0;
        const float n = length(v);
        return n > 1e-6f ? v * (1.0f / n) : Vec3f{0, 0, 0};
    };
    Vec3f step = horizontal(camera_right) * along + horizontal(camera_forward) * ahead;
    step.y += up;
    return step;
}

bool LitObject::update(Renderer& renderer, const ShLight& light, ObjectShadeOptions options,
                       Vec3f eye) {
    if (!present()) return false;
    // The eye matters to the glossy term only.
    options.eye = options.k < 1 && options.view == ShadeView::radiance ? eye : Vec3f{0, 0, 0};
    if (m_valid && same(m_pose, m_object.pose) && same(m_options, options) &&
        m_light == light.coeffs)
        return false;
    const auto start = std::chrono::steady_clock::now();
    m_shading = shade_object(*m_object.object, m_object.pose, *m_object.probes, light, options);
    renderer.set_object(&m_object.object->mesh, &m_shading);
    m_shade_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    m_valid = true;
    m_pose = m_object.pose;
    m_options = options;
    m_light = light.coeffs;
    return true;
}

}  // namespace shprt::viewer
