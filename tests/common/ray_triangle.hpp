// The ray–triangle test the tests hold tracers and renderers to: Möller & Trumbore 1997 in double
// precision, two-sided, written for clarity rather than speed.
#pragma once

#include "shprt/core/vec.hpp"

#include <optional>

namespace shprt::test {

struct TriangleHit {
    double t;     // distance along the ray in units of |d|
    double u, v;  // barycentrics: the point is a + u·e1 + v·e2
};

// Where the line o + t·d meets the triangle (a, a + e1, a + e2), for any t (callers choose the
// range); nullopt when it misses or is parallel to the triangle's plane.
inline std::optional<TriangleHit> intersect_triangle(Vec3d o, Vec3d d, Vec3d a, Vec3d e1,
                                                     Vec3d e2) {
    const Vec3d p = cross(d, e2);
    const double det = dot(e1, p);
    if (det == 0.0) return std::nullopt;
    const double inv = 1.0 / det;
    const Vec3d s = o - a;
    const double u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return std::nullopt;
    const Vec3d q = cross(s, e1);
    const double v = dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) return std::nullopt;
    return TriangleHit{dot(e2, q) * inv, u, v};
}

}  // namespace shprt::test
