// 3D rotations: elementary axis rotations, ZYZ Euler angles, yaw/pitch/roll and unit quaternions,
// all as 3x3 matrices acting on column vectors (v' = R v).
//
// Conventions:
// * Right-handed rotations: rotation_z(a) turns +X toward +Y by a radians (counter-clockwise
//   looking down +Z), rotation_x(a) turns +Y toward +Z, rotation_y(a) turns +Z toward +X.
// * ZYZ Euler angles (α, β, γ) give R = Rz(γ)·Ry(β)·Rz(α): first α about Z, then β about Y, then
//   γ about Z, all about the fixed world axes. This is the convention of `shprt sh rotate --zyz`.
// * Yaw/pitch/roll (degrees) give R = Ry(yaw)·Rx(pitch)·Rz(roll) with +Y up (world space is
//   right-handed, +Y up): roll about the viewing axis Z first, then pitch about X, then yaw about
//   the up axis Y. Used by `--rotate` of lights.
// * A quaternion (w, x, y, z) = (cos(θ/2), sin(θ/2)·axis) rotates by θ about `axis`.
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/vec.hpp"

#include <cmath>

namespace shprt {

struct Quat {
    double w, x, y, z;  // unit quaternion; w is the scalar part
};

// ZYZ Euler angles in radians: R = Rz(gamma)·Ry(beta)·Rz(alpha).
struct EulerZyz {
    double alpha, beta, gamma;
};

SHPRT_HD_INLINE Mat3d rotation_x(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return {{{1, 0, 0}, {0, c, -s}, {0, s, c}}};
}
SHPRT_HD_INLINE Mat3d rotation_y(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return {{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}};
}
SHPRT_HD_INLINE Mat3d rotation_z(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return {{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}};
}

// R = Rz(gamma)·Ry(beta)·Rz(alpha), angles in radians.
SHPRT_HD_INLINE Mat3d matrix_from_zyz(double alpha, double beta, double gamma) {
    return rotation_z(gamma) * rotation_y(beta) * rotation_z(alpha);
}

// R = Ry(yaw)·Rx(pitch)·Rz(roll), angles in degrees; +Y is up.
SHPRT_HD_INLINE Mat3d matrix_from_yaw_pitch_roll_deg(double yaw, double pitch, double roll) {
    return rotation_y(yaw * kDeg) * rotation_x(pitch * kDeg) * rotation_z(roll * kDeg);
}

// Rotation matrix of the quaternion q. q is normalised first, so any non-zero finite quaternion
// is accepted; throws Error(invalid_argument) for a zero or non-finite quaternion.
Mat3d matrix_from_quat(const Quat& q);

// Unit quaternion rotating by `angle` radians about `axis` (normalised here; throws
// Error(invalid_argument) when the axis is zero or not finite).
Quat quat_from_axis_angle(Vec3d axis, double angle);

// ZYZ angles of a rotation matrix, with beta in [0, π] and alpha, gamma in [−π, π]. At the
// gimbal-lock poles (beta = 0 or π) only alpha ± gamma is defined; then alpha = 0. alpha comes
// from the third row and gamma from the well-conditioned sum or difference α ± γ, so
// matrix_from_zyz(zyz_from_matrix(R)) reproduces R to rounding even near the poles. Precondition: R
// is a rotation (see is_rotation).
EulerZyz zyz_from_matrix(const Mat3d& R);

// True when R is orthonormal with determinant +1 to within `tolerance` (max-abs entry of
// RᵀR − I and |det R − 1|).
bool is_rotation(const Mat3d& R, double tolerance = 1e-6);

// A rotation taking +Z to the unit direction `dir`: Rz(φ)·Ry(θ) with (θ, φ) the spherical
// angles of dir. Used to rotate zonal lobes (pole +Z) onto a direction.
Mat3d rotation_z_to(Vec3d dir);

}  // namespace shprt
