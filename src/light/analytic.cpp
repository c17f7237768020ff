// Analytic lights projected exactly. A radiance function symmetric about an axis a,
// L(d) = g(d·a), has SH coefficients given by the Funk–Hecke theorem:
//   c_lm = sqrt(4π/(2l+1)) · z_l · y_lm(a),   z_l = 2π ∫_{−1}^{1} g(t) sqrt((2l+1)/(4π)) P_l(t) dt
// (Sloan, Kautz & Snyder 2002, §5 — the zonal-harmonic rotation also used for the glossy lobe;
// Ramamoorthi & Hanrahan 2001 for the clamped-cosine case). z_l is integrated with
// Gauss–Legendre quadrature on each smooth piece of g, exact for the polynomial pieces used here.
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/sh/zonal.hpp"

#include <cmath>
#include <functional>
#include <vector>

namespace shprt {
namespace {

using ZonalProfile = std::function<Vec3d(double)>;

// z_l (l < bands, per channel, channel-major 3·bands) of g on the pieces [edges[k], edges[k+1]].
// n Gauss–Legendre nodes per piece integrate g·P_l exactly when that product is a polynomial of
// degree ≤ 2n − 1; we use n = bands + 64, ample for polynomial pieces of degree ≤ 64 and, for
// smooth g, converged to rounding.
std::vector<double> zonal_coefficients(const ZonalProfile& g, const std::vector<double>& edges,
                                       int bands) {
    const int n = bands + 64;
    // Nodes and weights on [−1, 1] from the sphere rule with one azimuth: z_i and w_i·2π.
    const DirectionSetD rule = gauss_legendre_set_d(n, 1);
    std::vector<double> z(3 * std::size_t(bands), 0.0), p(bands);
    for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
        const double lo = edges[k], hi = edges[k + 1];
        if (!(hi > lo)) continue;
        const double half = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
        for (int i = 0; i < n; ++i) {
            const double t = mid + half * rule.dirs[3 * std::size_t(i) + 2];
            const double w = half * rule.weights[i] / (2.0 * kPi);
            const Vec3d v = g(t);
            // Legendre P_l(t) by the three-term recurrence (stable for |t| ≤ 1).
            double p0 = 1.0, p1 = t;
            for (int l = 0; l < bands; ++l) {
                if (l == 0) {
                    p[0] = 1.0;
                } else if (l == 1) {
                    p[1] = t;
                } else {
                    const double p2 = ((2.0 * l - 1.0) * t * p1 - (l - 1.0) * p0) / l;
                    p0 = p1;
                    p1 = p2;
                    p[l] = p2;
                }
            }
            for (int l = 0; l < bands; ++l) {
                const double f = 2.0 * kPi * std::sqrt((2.0 * l + 1.0) / (4.0 * kPi)) * p[l] * w;
                z[0 * bands + l] += f * v.x;
                z[1 * std::size_t(bands) + l] += f * v.y;
                z[2 * std::size_t(bands) + l] += f * v.z;
            }
        }
    }
    return z;
}

// Adds the zonal function with coefficients z (per channel) about unit axis `a` into `light`,
// through the zonal rotation identity (sh/zonal.hpp).
void add_zonal(ShLight& light, const std::vector<double>& z, int bands, Vec3d a) {
    const int K = light.K;
    std::vector<double> out(K);
    for (int c = 0; c < 3; ++c) {
        rotate_zonal(z.data() + std::size_t(c) * bands, K, a, out.data());
        float* ch = light.channel(c);
        for (int i = 0; i < K; ++i) ch[i] += static_cast<float>(out[i]);
    }
}

void check_radiance(Vec3d r, const char* what) {
    SHPRT_CHECK(std::isfinite(r.x) && std::isfinite(r.y) && std::isfinite(r.z) && r.x >= 0 &&
                    r.y >= 0 && r.z >= 0,
                invalid_argument, "{} radiance ({}, {}, {}) must be finite and non-negative", what,
                r.x, r.y, r.z);
}

Vec3d lerp(Vec3d a, Vec3d b, double t) { return a + (b - a) * t; }

// Built-in environment parameters (documented in light.hpp and docs/lights.md).
constexpr double kBuiltinSunRadiusDeg = 2.0;
constexpr Vec3d kBuiltinSunIrradiance{3.2, 3.0, 2.7};
constexpr Vec3d kBuiltinGlow{0.3, 0.27, 0.21};
constexpr double kBuiltinGlowSharpness = 8.0;

}  // namespace

ShLight constant_light(Vec3d radiance, int K) {
    check_radiance(radiance, "constant light");
    ShLight light = ShLight::zero(K);
    const double s = std::sqrt(4.0 * kPi);
    for (int c = 0; c < 3; ++c) light.channel(c)[0] = static_cast<float>(s * radiance[c]);
    return light;
}

Vec3d gradient_radiance(const GradientSky& sky, Vec3d d) {
    const double t = d.y < -1.0 ? -1.0 : (d.y > 1.0 ? 1.0 : d.y);
    if (t >= 0.0) return lerp(sky.horizon, sky.zenith, 1.0 - std::pow(1.0 - t, 3.0));
    return lerp(sky.horizon, sky.ground, 1.0 - std::pow(1.0 + t, 8.0));
}

ShLight gradient_light(const GradientSky& sky, int K) {
    check_radiance(sky.zenith, "gradient zenith");
    check_radiance(sky.horizon, "gradient horizon");
    check_radiance(sky.ground, "gradient ground");
    ShLight light = ShLight::zero(K);
    const int bands = sh_bands_for(K);
    const auto g = [&](double t) { return gradient_radiance(sky, Vec3d{0.0, t, 0.0}); };
    add_zonal(light, zonal_coefficients(g, {-1.0, 0.0, 1.0}, bands), bands, Vec3d{0, 1, 0});
    return light;
}

Vec3d sun_radiance_for_irradiance(Vec3d irradiance, double radius_deg) {
    SHPRT_CHECK(radius_deg > 0.0 && radius_deg <= 90.0, invalid_argument,
                "sun radius {}° must be in (0, 90]", radius_deg);
    const double s = std::sin(radius_deg * kDeg);
    return irradiance / (kPi * s * s);
}

Sun make_sun(Vec3d direction, double radius_deg, Vec3d radiance) {
    const double len = length(direction);
    SHPRT_CHECK(std::isfinite(len) && len > 0.0, invalid_argument,
                "sun direction ({}, {}, {}) must be finite and non-zero", direction.x, direction.y,
                direction.z);
    SHPRT_CHECK(std::isfinite(radius_deg) && radius_deg > 0.0 && radius_deg <= 90.0,
                invalid_argument, "sun radius {}° must be in (0, 90]", radius_deg);
    check_radiance(radiance, "sun");
    return Sun{direction / len, radius_deg, radiance};
}

ShLight sun_light(const Sun& given, int K) {
    const Sun sun = make_sun(given.direction, given.radius_deg, given.radiance);  // the checks
    ShLight light = ShLight::zero(K);
    const int bands = sh_bands_for(K);
    const double cos_r = std::cos(sun.radius_deg * kDeg);
    const auto g = [&](double) { return sun.radiance; };
    add_zonal(light, zonal_coefficients(g, {cos_r, 1.0}, bands), bands, sun.direction);
    return light;
}

ShLight sun_light(Vec3d dir, double radius_deg, Vec3d radiance, int K) {
    // Through make_sun, as parse_sun does, so that `sun:` and this give the same bits.
    return sun_light(make_sun(dir, radius_deg, radiance), K);
}

Vec3d builtin_sun_direction() {
    const double el = 50.0 * kDeg, az = 35.0 * kDeg;
    return {std::cos(el) * std::sin(az), std::sin(el), -std::cos(el) * std::cos(az)};
}

Vec3d builtin_radiance(Vec3d d) {
    const Vec3d s = builtin_sun_direction();
    const double t = dot(d, s);
    Vec3d L = gradient_radiance(GradientSky{}, d);
    L += kBuiltinGlow * std::exp(kBuiltinGlowSharpness * (t - 1.0));
    if (t >= std::cos(kBuiltinSunRadiusDeg * kDeg))
        L += sun_radiance_for_irradiance(kBuiltinSunIrradiance, kBuiltinSunRadiusDeg);
    return L;
}

ShLight builtin_light(int K) {
    ShLight light = gradient_light(GradientSky{}, K);
    const int bands = sh_bands_for(K);
    const Vec3d s = builtin_sun_direction();
    const auto glow = [](double t) {
        return kBuiltinGlow * std::exp(kBuiltinGlowSharpness * (t - 1.0));
    };
    add_zonal(light, zonal_coefficients(glow, {-1.0, 1.0}, bands), bands, s);
    add_light(
        light,
        sun_light(s, kBuiltinSunRadiusDeg,
                  sun_radiance_for_irradiance(kBuiltinSunIrradiance, kBuiltinSunRadiusDeg), K));
    return light;
}

}  // namespace shprt
