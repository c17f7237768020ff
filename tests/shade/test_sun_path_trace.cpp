// The sun kept out of the SH sum (shade/sun_shade.hpp) against an independent path tracer of the
// true scene: a disc sun and a band-limited sky, the direct light and one bounce, integrated here
// with Embree rays and this file's own random numbers — no SH for the sun anywhere, so the
// hybrid's approximations (the bake's Monte Carlo transfer and bounce sources, the sun's bounce
// through its K-coefficient projection) all show in the difference.
#include "shade_test_util.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/math.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/shade/sun_shade.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

namespace shprt {
namespace {

// The largest relative error of the hybrid's E at the receivers below (measured: see the test's
// output and docs/lights.md).
constexpr double kHybridTolerance = 0.015;

// An orthonormal frame about unit n: directions in it are t·x + b·y + n·z.
void frame(Vec3d n, Vec3d& t, Vec3d& b) {
    const Vec3d a = std::abs(n.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    t = normalize(cross(a, n));
    b = cross(n, t);
}

class PathTracer {
public:
    PathTracer(const Mesh& mesh, const ShLight& sky, const Sun& sun)
        : m_mesh(mesh), m_sky(sky), m_sun(sun), m_tracer(make_embree_tracer(mesh)) {}

    // E at (p, n): the direct sky and sun, and, with `bounce`, the light they bring after one
    // diffuse bounce off the scene (albedo and normal interpolated at the hit).
    Vec3d irradiance(Vec3d p, Vec3d n, bool bounce, std::mt19937_64& rng, int paths) const {
        Vec3d E = direct(p, n, rng, paths);
        if (!bounce) return E;
        Vec3d t, b;
        frame(n, t, b);
        Vec3d indirect{0, 0, 0};
        std::uniform_real_distribution<double> u(0, 1);
        for (int i = 0; i < paths; ++i) {
            // Cosine-weighted: E = π · mean of the radiance seen.
            const double r = std::sqrt(u(rng)), phi = 2 * kPi * u(rng);
            const Vec3d d = t * (r * std::cos(phi)) + b * (r * std::sin(phi)) +
                            n * std::sqrt(std::max(0.0, 1 - r * r));
            const Vec3f o = offset_ray_origin(cast<float>(p), cast<float>(n));
            const Hit hit = m_tracer->intersect(o, cast<float>(d), 0.0f, 1e30f);
            if (!hit.hit) continue;  // the sky: counted in the direct part
            const auto& tri = m_mesh.triangles[hit.triangle];
            const double a = 1.0 - hit.u - hit.v;
            auto lerp = [&](const std::vector<Vec3f>& v) {
                return cast<double>(v[tri[0]]) * a + cast<double>(v[tri[1]]) * double(hit.u) +
                       cast<double>(v[tri[2]]) * double(hit.v);
            };
            Vec3d hn = normalize(lerp(m_mesh.normals));
            if (dot(hn, d) > 0) hn = -hn;  // the side the ray arrives on
            const Vec3d hp = cast<double>(o) + d * double(hit.t);
            const Vec3d rho = lerp(m_mesh.albedo);
            const Vec3d Eh = direct(hp, hn, rng, 4);
            indirect += Vec3d{rho.x * Eh.x, rho.y * Eh.y, rho.z * Eh.z} / kPi;
        }
        return E + indirect * (kPi / paths);
    }

private:
    // The sky (cosine-weighted directions) and the sun (uniform on its cone) that reach (p, n).
    Vec3d direct(Vec3d p, Vec3d n, std::mt19937_64& rng, int paths) const {
        std::uniform_real_distribution<double> u(0, 1);
        Vec3d t, b;
        frame(n, t, b);
        const Vec3f o = offset_ray_origin(cast<float>(p), cast<float>(n));
        const float inf = 1e30f;
        Vec3d sky{0, 0, 0};
        for (int i = 0; i < paths; ++i) {
            const double r = std::sqrt(u(rng)), phi = 2 * kPi * u(rng);
            const Vec3d d = t * (r * std::cos(phi)) + b * (r * std::sin(phi)) +
                            n * std::sqrt(std::max(0.0, 1 - r * r));
            const Vec3f df = cast<float>(d);
            std::uint8_t hit = 0;
            m_tracer->occluded(o, &df, 1, 0.0f, inf, &hit);
            if (!hit) sky += light_radiance(m_sky, d);
        }
        Vec3d st, sb;
        const Vec3d s = normalize(m_sun.direction);
        frame(s, st, sb);
        const double cos_max = std::cos(m_sun.radius_deg * kPi / 180);
        double sun = 0;
        for (int i = 0; i < paths; ++i) {
            const double c = 1 - u(rng) * (1 - cos_max), phi = 2 * kPi * u(rng);
            const double sn = std::sqrt(std::max(0.0, 1 - c * c));
            const Vec3d d = st * (sn * std::cos(phi)) + sb * (sn * std::sin(phi)) + s * c;
            const double cn = dot(n, d);
            if (cn <= 0) continue;
            const Vec3f df = cast<float>(d);
            std::uint8_t hit = 0;
            m_tracer->occluded(o, &df, 1, 0.0f, inf, &hit);
            if (!hit) sun += cn;
        }
        return sky * (kPi / paths) + m_sun.radiance * (sun * sun_solid_angle(m_sun) / paths);
    }

    const Mesh& m_mesh;
    const ShLight& m_sky;
    Sun m_sun;
    std::unique_ptr<Tracer> m_tracer;
};

// builtin:box_on_plane, its interreflected bake with one bounce (K = 64), a gradient sky and a
// 3° sun 50° up: at floor vertices in and beside the box's shadow and on the box's sunlit and
// shaded faces, shade_with_sun's E (traced direct sun + sky through T + the sun's bounce through
// T − T_0) against the path tracer's E with the direct light and one bounce of the true disc.
TEST(ShadeSunPathTrace, TheHybridMatchesAPathTracedSunAndSkyWithOneBounce) {
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions options;
    options.transfer = TransferKind::interreflected;
    options.K = 64;
    options.samples = 8192;
    options.bounces = 1;
    const TransferSet T = bake(mesh, options);
    ASSERT_FALSE(T.direct.empty());
    const Sun sun = make_sun({1, 1.2, 0.3}, 3, sun_radiance_for_irradiance({3, 2.8, 2.4}, 3));
    const ShLight sky = gradient_light(GradientSky{}, 64);
    SunShadeOptions sun_options;
    sun_options.disc_samples = 256;
    const SunShadeResult hybrid = shade_with_sun(mesh, T, sky, PreparedSun{sun, sun_light(sun, 64)},
                                                 ShadeOptions{}, sun_options);
    // The same without the bounce (shade the direct part T_0): the test must see the bounce.
    const TransferSet direct_only = T.direct_only();
    const SunShadeResult hybrid0 = shade_with_sun(
        mesh, direct_only, sky, PreparedSun{sun, sun_light(sun, 64)}, ShadeOptions{}, sun_options);

    // Receivers: floor vertices in the shadow (−x of the box), beside it, and the box's faces.
    std::vector<std::size_t> receivers;
    const Vec3f wanted[][2] = {{{-1.0f, 0, -0.25f}, {0, 1, 0}},     // in the box's shadow
                               {{-0.75f, 0, 0.0f}, {0, 1, 0}},      // in the shadow, near the box
                               {{0.75f, 0, 0.0f}, {0, 1, 0}},       // lit, facing the lit box face
                               {{-1.0f, 0, 1.0f}, {0, 1, 0}},       // lit, beside the shadow
                               {{0.5f, 0.5f, 0.0f}, {1, 0, 0}},     // the box's sunlit face
                               {{-0.5f, 0.5f, 0.0f}, {-1, 0, 0}}};  // its shaded face
    for (const auto& w : wanted) {
        std::size_t best = mesh.vertex_count();
        float best_d = 1e30f;
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            if (dot(mesh.normals[v], w[1]) < 0.99f) continue;
            const float d = length(mesh.positions[v] - w[0]);
            if (d < best_d) best_d = d, best = v;
        }
        ASSERT_LT(best_d, 0.2f);
        receivers.push_back(best);
    }

    const PathTracer tracer(mesh, sky, sun);
    double worst = 0, worst_without_bounce = 0, sum_sq = 0, sum_ref = 0;
    for (std::size_t i = 0; i < receivers.size(); ++i) {
        const std::size_t v = receivers[i];
        std::mt19937_64 rng(1000 + i);
        const Vec3d ref = tracer.irradiance(cast<double>(mesh.positions[v]),
                                            cast<double>(mesh.normals[v]), true, rng, 16384);
        const double e = double(hybrid.irradiance[v].y), e0 = double(hybrid0.irradiance[v].y);
        const double rel = std::abs(e - ref.y) / ref.y, rel0 = std::abs(e0 - ref.y) / ref.y;
        std::printf(
            "vertex %zu (%.2f, %.2f, %.2f): path traced E_G %.4f, hybrid %.4f (%+.2f %%), "
            "without the bounce %.4f (%+.2f %%)\n",
            v, mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z, ref.y, e,
            100 * (e - ref.y) / ref.y, e0, 100 * (e0 - ref.y) / ref.y);
        worst = std::max(worst, rel);
        worst_without_bounce = std::max(worst_without_bounce, rel0);
        sum_sq += (e - ref.y) * (e - ref.y);
        sum_ref += ref.y * ref.y;
    }
    std::printf(
        "hybrid against the path tracer: worst %.2f %%, RMS %.2f %% (without the bounce: "
        "worst %.2f %%)\n",
        100 * worst, 100 * std::sqrt(sum_sq / sum_ref), 100 * worst_without_bounce);
    EXPECT_LT(worst, kHybridTolerance);
    EXPECT_GT(worst_without_bounce, 3 * kHybridTolerance) << "the bounce must matter here";
}

}  // namespace
}  // namespace shprt
