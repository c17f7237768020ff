// Mouse and keyboard camera control of the viewer: an orbit camera (turns around a target point)
// and a fly camera (turns in place, moves along its own axes), sharing one state so that
// switching mode keeps the view.
//
// State: eye position, yaw and pitch of the view direction, and the distance to the target, with
//     forward = (cos p · sin y, sin p, −cos p · cos y)     (yaw 0 looks toward −Z, +Y up)
//     target  = eye + distance · forward
//     right   = normalize(forward × +Y) = (cos y, 0, sin y),  up = right × forward.
// Pitch is kept within ±kMaxPitchDeg so that +Y is never parallel to the view direction (the
// Camera's up vector stays +Y). Orbit rotation keeps the target and the distance; fly rotation
// keeps the eye. No GLFW or OpenGL here: the window feeds it pixel deltas, tests call it directly.
#pragma once

#include "shprt/scene/mesh_ops.hpp"
#include "shprt/shade/camera.hpp"

namespace shprt::viewer {

enum class CameraMode { orbit, fly };

// Radians of rotation per pixel of mouse drag.
inline constexpr float kCameraRadiansPerPixel = 0.005f;
// Largest |pitch|, degrees.
inline constexpr float kMaxPitchDeg = 89.0f;

class CameraController {
public:
    // Starts from `start` (eye, target, fov; its up vector is replaced by +Y, and a view straight
    // up or down is tilted to kMaxPitchDeg). `bounds` (the scene's) sets the clip planes of
    // camera(), the zoom limits and the fly speed (a quarter of the bounds' diagonal per second).
    CameraController(const Camera& start, const Bounds& bounds);

    CameraMode mode() const { return m_mode; }
    // Switches mode; the eye, direction and target stay where they are.
    void set_mode(CameraMode mode) { m_mode = mode; }

    // A mouse drag of (dx, dy) pixels (x right, y down). Both modes turn the view by
    // kCameraRadiansPerPixel per pixel: yaw += dx·rate, pitch −= dy·rate. Orbit moves the eye on
    // the sphere around the target (target and distance fixed); fly turns in place (eye fixed).
    void rotate(float dx_px, float dy_px);
    // Moves eye and target together in the view plane so that a point at the target's distance
    // follows the cursor: (dx, dy) pixels in a viewport `viewport_height_px` pixels tall.
    void pan(float dx_px, float dy_px, float viewport_height_px);
    // Mouse wheel. Orbit: distance × 0.85^steps (toward the target for steps > 0), kept within
    // [1e-3, 10] × the bounds' diagonal. Fly: eye and target move forward by steps × 5 % of the
    // diagonal.
    void zoom(float steps);
    // Keyboard motion in both modes: eye and target move by (right·x + up·y + forward·z) ·
    // speed() · seconds, where `local` = (x, y, z) has components in [−1, 1].
    void move(Vec3f local, float seconds);
    // Turns the eye about the vertical axis through the target by `radians` (orbit rotation;
    // used by the benchmark whatever the mode).
    void orbit_by(float radians);

    // The camera for drawing: look_at_camera(eye, target, field of view, bounds)
    // (shade/camera.hpp), so up is +Y (the pitch clamp keeps it off the view direction) and the
    // clip planes are fitted to the bounds.
    Camera camera() const;

    Vec3f eye() const { return m_eye; }
    Vec3f target() const;
    Vec3f forward() const;
    Vec3f right() const;
    Vec3f up() const;
    float distance() const { return m_distance; }
    float yaw() const { return m_yaw; }
    float pitch() const { return m_pitch; }
    float speed() const { return m_speed; }
    void set_speed(float units_per_second) { m_speed = units_per_second; }
    float fov_y_deg() const { return m_fov_y_deg; }
    void set_fov_y_deg(float degrees) { m_fov_y_deg = degrees; }

private:
    void set_direction(float yaw, float pitch);  // clamps pitch, wraps yaw to (−π, π]

    CameraMode m_mode = CameraMode::orbit;
    Vec3f m_eye;
    float m_yaw = 0, m_pitch = 0, m_distance = 1;
    float m_fov_y_deg = 60;
    float m_diagonal = 1, m_speed = 1;
    Bounds m_bounds;
};

}  // namespace shprt::viewer
