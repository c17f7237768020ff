// Orbit and fly camera control (camera_controller.hpp).
#include "camera_controller.hpp"

#include "shprt/core/math.hpp"

#include <algorithm>
#include <cmath>

namespace shprt::viewer {
namespace {

Vec3f forward_of(float yaw, float pitch) {
    return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw)};
}

}  // namespace

CameraController::CameraController(const Camera& start, const Bounds& bounds)
    : m_eye(start.eye), m_fov_y_deg(start.fov_y_deg), m_bounds(bounds) {
    const Vec3f d = start.target - start.eye;
    m_distance = std::max(length(d), 1e-6f);
    const Vec3f f = d / m_distance;
    set_direction(std::atan2(f.x, -f.z), std::asin(std::clamp(f.y, -1.0f, 1.0f)));
    m_diagonal = std::max(length(bounds.hi - bounds.lo), 1e-6f);
    m_speed = 0.25f * m_diagonal;
}

void CameraController::set_direction(float yaw, float pitch) {
    const float max_pitch = kMaxPitchDeg * kPiF / 180.0f;
    m_pitch = std::clamp(pitch, -max_pitch, max_pitch);
    // Wrap to (−π, π] so that long drags do not lose float precision.
    m_yaw = std::remainder(yaw, 2 * kPiF);
}

Vec3f CameraController::forward() const { return forward_of(m_yaw, m_pitch); }
Vec3f CameraController::right() const { return {std::cos(m_yaw), 0.0f, std::sin(m_yaw)}; }
Vec3f CameraController::up() const { return cross(right(), forward()); }
Vec3f CameraController::target() const { return m_eye + forward() * m_distance; }

void CameraController::rotate(float dx_px, float dy_px) {
    const Vec3f pivot = target();
    set_direction(m_yaw + dx_px * kCameraRadiansPerPixel, m_pitch - dy_px * kCameraRadiansPerPixel);
    if (m_mode == CameraMode::orbit) m_eye = pivot - forward() * m_distance;
}

void CameraController::pan(float dx_px, float dy_px, float viewport_height_px) {
    // World units per pixel at the target's distance.
    const float scale = 2.0f * m_distance * std::tan(m_fov_y_deg * kPiF / 360.0f) /
                        std::max(viewport_height_px, 1.0f);
    // The scene follows the cursor: the camera moves the other way.
    m_eye += right() * (-dx_px * scale) + up() * (dy_px * scale);
}

void CameraController::zoom(float steps) {
    if (m_mode == CameraMode::orbit) {
        const Vec3f pivot = target();
        m_distance =
            std::clamp(m_distance * std::pow(0.85f, steps), 1e-3f * m_diagonal, 10.0f * m_diagonal);
        m_eye = pivot - forward() * m_distance;
    } else {
        m_eye += forward() * (steps * 0.05f * m_diagonal);
    }
}

void CameraController::move(Vec3f local, float seconds) {
    const Vec3f delta = right() * local.x + up() * local.y + forward() * local.z;
    m_eye += delta * (m_speed * seconds);
}

void CameraController::orbit_by(float radians) {
    const Vec3f pivot = target();
    set_direction(m_yaw + radians, m_pitch);
    m_eye = pivot - forward() * m_distance;
}

Camera CameraController::camera() const {
    // Pitch stays within ±kMaxPitchDeg, so the up vector is always +Y here.
    return look_at_camera(m_eye, target(), m_fov_y_deg, m_bounds);
}

}  // namespace shprt::viewer
