#include "shprt/transfer/object.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/rotation3.hpp"

#include <cmath>

namespace shprt {

void check(const ObjectPose& pose) {
    const Vec3f p = pose.position;
    SHPRT_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), invalid_argument,
                "object position ({}, {}, {}) must be finite", p.x, p.y, p.z);
    SHPRT_CHECK(std::isfinite(pose.scale) && pose.scale > 0, invalid_argument,
                "object scale {} must be finite and > 0", pose.scale);
    const Vec3d a = pose.yaw_pitch_roll_deg;
    SHPRT_CHECK(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z), invalid_argument,
                "object rotation ({}, {}, {}) must be finite", a.x, a.y, a.z);
}

Mat3d object_rotation(const ObjectPose& pose) {
    const Vec3d a = pose.yaw_pitch_roll_deg;
    if (a.x == 0 && a.y == 0 && a.z == 0) return Mat3d::identity();
    return matrix_from_yaw_pitch_roll_deg(a.x, a.y, a.z);
}

}  // namespace shprt
