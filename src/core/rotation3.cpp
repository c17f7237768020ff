// 3D rotation helpers: quaternion to matrix, robust ZYZ Euler angle extraction.
#include "shprt/core/rotation3.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"

#include <algorithm>
#include <cmath>

namespace shprt {

Mat3d matrix_from_quat(const Quat& q) {
    const double n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    SHPRT_CHECK(std::isfinite(n2) && n2 > 1e-300, invalid_argument,
                "quaternion ({}, {}, {}, {}) is zero or not finite", q.w, q.x, q.y, q.z);
    const double s = 2.0 / n2;  // normalises q on the fly
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    return {{{1 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y)},
             {s * (x * y + w * z), 1 - s * (x * x + z * z), s * (y * z - w * x)},
             {s * (x * z - w * y), s * (y * z + w * x), 1 - s * (x * x + y * y)}}};
}

Quat quat_from_axis_angle(Vec3d axis, double angle) {
    const double n = length(axis);
    SHPRT_CHECK(std::isfinite(n) && n > 1e-300 && std::isfinite(angle), invalid_argument,
                "rotation axis ({}, {}, {}) with angle {} is zero or not finite", axis.x, axis.y,
                axis.z, angle);
    const double s = std::sin(0.5 * angle) / n;
    return {std::cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s};
}

EulerZyz zyz_from_matrix(const Mat3d& R) {
    const auto& m = R.m;
    const auto wrap = [](double a) {
        while (a > kPi) a -= 2 * kPi;
        while (a <= -kPi) a += 2 * kPi;
        return a;
    };
    // Third row and column (note 1): R20 = −sin β cos α, R21 = sin β sin α, R02 = cos γ sin β,
    // R12 = sin γ sin β, R22 = cos β. They give β to rounding and α, γ to rounding / sin β.
    const double sb = 0.5 * (std::hypot(m[2][0], m[2][1]) + std::hypot(m[0][2], m[1][2]));
    const double beta = std::atan2(sb, std::clamp(m[2][2], -1.0, 1.0));
    const double alpha = sb > 0 ? std::atan2(m[2][1], -m[2][0]) : 0.0;
    // The upper-left 2x2 block gives the sum and difference well conditioned exactly where the
    // third row and column are not (note 1):
    //   R00 + R11 = (1 + cos β) cos(α + γ),     R10 − R01 = (1 + cos β) sin(α + γ)
    //   R11 − R00 = (1 − cos β) cos(γ − α),   −(R01 + R10) = (1 − cos β) sin(γ − α)
    // Taking α from the third row and γ from the sum (cos β ≥ 0) or the difference (cos β < 0)
    // keeps matrix_from_zyz(zyz_from_matrix(R)) within rounding of R even near the poles: α and
    // γ are each off by ~rounding / sin β, but those errors cancel in the α ± γ that the 2x2
    // block needs and are multiplied by sin β in the third row and column.
    double gamma;
    if (m[2][2] >= 0)
        gamma = std::atan2(m[1][0] - m[0][1], m[0][0] + m[1][1]) - alpha;
    else
        gamma = std::atan2(-(m[0][1] + m[1][0]), m[1][1] - m[0][0]) + alpha;
    return {alpha, beta, wrap(gamma)};
}

bool is_rotation(const Mat3d& R, double tolerance) {
    const Mat3d p = transpose(R) * R;
    double worst = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double e = std::abs(p.m[i][j] - (i == j ? 1.0 : 0.0));
            if (!(e <= worst)) worst = e;  // also catches NaN
        }
    const auto& m = R.m;
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    return worst <= tolerance && std::abs(det - 1.0) <= tolerance;
}

Mat3d rotation_z_to(Vec3d dir) {
    const double theta = std::acos(std::clamp(dir.z, -1.0, 1.0));
    const double phi = (dir.x == 0 && dir.y == 0) ? 0.0 : std::atan2(dir.y, dir.x);
    return rotation_z(phi) * rotation_y(theta);
}

}  // namespace shprt

// Note 1: Rz(γ)Ry(β)Rz(α) =
//   [cγcβcα − sγsα, −cγcβsα − sγcα, cγsβ;  sγcβcα + cγsα, −sγcβsα + cγcα, sγsβ;
//    −sβcα, sβsα, cβ];
// sums and differences of the upper-left entries collapse to the (1 ± cos β) forms above.
