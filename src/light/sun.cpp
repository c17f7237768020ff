// The sun's model (light/sun.hpp): its spec's numbers and the directions that sample its disc.
// Concentric map: P. Shirley, K. Chiu, "A Low Distortion Map Between Disk and Square", JGT 1997.
// Orthonormal frame: T. Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017.
#include "shprt/light/sun.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/sh/rng.hpp"

#include <cmath>

namespace shprt {

Sun parse_sun(std::string_view numbers, const std::string& what, const std::string& syntax) {
    const std::vector<double> v = parse_numbers(numbers, what);
    SHPRT_CHECK(v.size() == 3 || v.size() == 4 || v.size() == 7, invalid_argument,
                "{}: expected {} (3, 4 or 7 numbers), got {} numbers", what, syntax, v.size());
    const double radius = v.size() > 3 ? v[3] : kDefaultSunRadiusDeg;
    SHPRT_CHECK(radius > 0.0 && radius <= 90.0, invalid_argument,
                "{}: sun radius {} degrees must be in (0, 90]", what, radius);
    const Vec3d radiance =
        v.size() == 7 ? Vec3d{v[4], v[5], v[6]}
                      : sun_radiance_for_irradiance(Vec3d{1, 1, 1} * kDefaultSunIrradiance, radius);
    try {
        return make_sun({v[0], v[1], v[2]}, radius, radiance);
    } catch (const Error& e) {
        throw Error(e.code(), fmt::format("{}: {}", what, e.what()));
    }
}

double sun_solid_angle(const Sun& sun) {
    return 2.0 * kPi * (1.0 - std::cos(sun.radius_deg * kDeg));
}

Vec3d sun_irradiance(const Sun& sun) {
    const double s = std::sin(sun.radius_deg * kDeg);
    return sun.radiance * (kPi * s * s);
}

std::vector<Vec3d> sun_disc_directions(const Sun& given, int count, std::uint64_t seed) {
    const int n = static_cast<int>(std::lround(std::sqrt(double(std::max(count, 0)))));
    SHPRT_CHECK(count >= 1 && count <= kMaxSunSamples && n * n == count, invalid_argument,
                "sun disc samples {}: must be a square (1, 4, 9, 16, ..., {})", count,
                kMaxSunSamples);
    const Sun sun = make_sun(given.direction, given.radius_deg, given.radiance);
    const Vec3d s = sun.direction;
    if (count == 1) return {s};
    // A frame (t, b, s) around the sun's direction (Duff et al. 2017).
    const double sign = std::copysign(1.0, s.z);
    const double a = -1.0 / (sign + s.z), c = s.x * s.y * a;
    const Vec3d t{1.0 + sign * s.x * s.x * a, sign * c, -sign * s.x};
    const Vec3d b{c, sign + s.y * s.y * a, -s.y};
    const double one_minus_cos_r = 1.0 - std::cos(sun.radius_deg * kDeg);
    std::vector<Vec3d> dirs;
    dirs.reserve(count);
    for (int cell = 0; cell < count; ++cell) {
        const RngBlock r = rng_block(seed, std::uint64_t(cell), kStreamSunDisc);
        const double u = (cell % n + to_unit_double(r.v[0], r.v[1])) / n * 2.0 - 1.0;
        const double v = (cell / n + to_unit_double(r.v[2], r.v[3])) / n * 2.0 - 1.0;
        // Concentric map of (u, v) ∈ [−1, 1]² to the point (x, y) = ρ·(cos φ, sin φ) of the unit
        // disc (ρ may come out negative: the point is then across the centre).
        double rho = 0, phi = 0;
        if (u != 0 || v != 0) {
            if (std::abs(u) > std::abs(v)) {
                rho = u;
                phi = (kPi / 4) * (v / u);
            } else {
                rho = v;
                phi = kPi / 2 - (kPi / 4) * (u / v);
            }
        }
        // Disc area ρ² ↦ cap solid angle: 1 − cos θ = ρ²(1 − cos r); the azimuth is the point's.
        const double one_minus_cos = rho * rho * one_minus_cos_r;
        const double cos_theta = 1.0 - one_minus_cos;
        const double sin_theta = std::sqrt(std::max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
        const double side = rho < 0 ? -sin_theta : sin_theta;
        const Vec3d d = t * (side * std::cos(phi)) + b * (side * std::sin(phi)) + s * cos_theta;
        dirs.push_back(normalize(d));
    }
    return dirs;
}

}  // namespace shprt
