// The equirectangular (latitude–longitude) mapping of environment maps, per DESIGN.md:
//
//   u = 0.5 + atan2(d.x, −d.z) / (2π),   v = acos(d.y) / π,   u, v ∈ [0, 1]
//
// u runs left → right across the image, v top → bottom. Row 0 (v = 0) is the zenith +Y, the
// bottom row the nadir −Y. The image centre (u, v) = (0.5, 0.5) looks toward −Z; moving right
// from the centre turns toward +X (u = 0.75), the left and right edges both look toward +Z, and
// u = 0.25 looks toward −X. This is the usual "view from inside" panorama for a right-handed,
// +Y-up world whose default camera looks down −Z. A pixel (x, y) covers
// u ∈ [x/W, (x+1)/W], v ∈ [y/H, (y+1)/H]; its centre is ((x + 0.5)/W, (y + 0.5)/H).
//
// Directions are unit world vectors pointing from the scene toward the light they see.
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/vec.hpp"

#include <cmath>

namespace shprt {

namespace detail {
template <class T>
SHPRT_HD_INLINE Vec3<T> equirect_direction(T u, T v) {
    constexpr T pi = T(kPi);
    const T theta = v * pi;                  // polar angle from +Y
    const T phi = (u - T(0.5)) * T(2) * pi;  // azimuth: 0 toward −Z, +π/2 toward +X
    const T s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}
template <class T>
SHPRT_HD_INLINE void equirect_uv(Vec3<T> d, T& u, T& v) {
    constexpr T pi = T(kPi);
    const T y = d.y < T(-1) ? T(-1) : (d.y > T(1) ? T(1) : d.y);
    u = T(0.5) + std::atan2(d.x, -d.z) / (T(2) * pi);
    v = std::acos(y) / pi;
}
}  // namespace detail

// Unit direction seen at image coordinates (u, v) ∈ [0, 1]² (float and double overloads; mixed
// or integer arguments do not compile, on purpose).
SHPRT_HD_INLINE Vec3f equirect_direction(float u, float v) {
    return detail::equirect_direction(u, v);
}
SHPRT_HD_INLINE Vec3d equirect_direction(double u, double v) {
    return detail::equirect_direction(u, v);
}

// Image coordinates (u, v) ∈ [0, 1]² of the unit direction d (inverse of equirect_direction;
// d.y is clamped to [−1, 1] before acos, so slightly non-unit input is tolerated).
SHPRT_HD_INLINE void equirect_uv(Vec3f d, float& u, float& v) { detail::equirect_uv(d, u, v); }
SHPRT_HD_INLINE void equirect_uv(Vec3d d, double& u, double& v) { detail::equirect_uv(d, u, v); }

// Direction through the centre of pixel (x, y) of a width × height map; T (float or double) is
// given explicitly: equirect_pixel_direction<double>(x, y, W, H).
template <class T>
SHPRT_HD_INLINE Vec3<T> equirect_pixel_direction(int x, int y, int width, int height) {
    return detail::equirect_direction<T>((T(x) + T(0.5)) / T(width), (T(y) + T(0.5)) / T(height));
}

// Exact solid angle (steradians) of one pixel in row y of a width × height map:
// Δω = Δφ · (cos θ0 − cos θ1) with Δφ = 2π/width, θ0 = π·y/height, θ1 = π·(y+1)/height.
// Summed over all pixels it is 4π up to rounding.
SHPRT_HD_INLINE double equirect_pixel_solid_angle(int y, int width, int height) {
    const double t0 = kPi * double(y) / double(height), t1 = kPi * double(y + 1) / double(height);
    // cos t0 − cos t1 = 2 sin((t0+t1)/2) sin((t1−t0)/2), free of cancellation near the poles.
    return (2.0 * kPi / double(width)) * 2.0 * std::sin(0.5 * (t0 + t1)) *
           std::sin(0.5 * (t1 - t0));
}

}  // namespace shprt
