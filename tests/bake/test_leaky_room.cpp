// Issue 34: the interreflected bake on an asset built like a real one (builtin:leaky_room: walls,
// floor slabs and furniture that overlap, interpenetrate and reach below the floor) against a
// renderer-like path tracer (path_trace_irradiance, bake/ground_truth.hpp) on the exact tracer
// (common/brute_force_tracer.hpp), at receivers spread over the floor, the walls, the table, the
// boxes, the die and the rug, many of them near contacts.
//
// Lights, both band-limited to K = 16 so that the bake's E_c = Σ_i T_c[i]·L_c[i] is exact but for
// its own sampling: a constant sky, and a sky with a "sun", a constant plus the smooth lobe
// ((1 + w·d)/2)^3 toward d = (0.4, 0.8, -0.3), exactly four bands (zonal harmonics rotated to d).
// Metrics, per light and bounce count N ∈ {1, 3}: the relative RMSE
//     sqrt(Σ_r Σ_c (x − ref)²) / sqrt(Σ_r Σ_c ref²)
// of the indirect part (bounces 1..N: the bake's total minus its direct part, against the path
// tracer's E_1 + … + E_N) and of the total (E_0 + … + E_N), over
//   * the one-sided bake and the receivers that do not see back faces (no ray of 4096 cosine-
//     distributed ones from the receiver's offset origin first meets a triangle from behind:
//     there the one-sided bake's "a back face sends nothing" is no different from a renderer's),
//   * the two-sided bake (BakeOptions::two_sided) and all the receivers.
// Thresholds (the issue's): indirect within 5 %, total within 2 %. The numbers are printed to be
// quoted, with the signed bias Σ(x − ref) / Σ ref, the path tracer's own noise on the RMSE's scale
// (sqrt(Σ s.e.²) / sqrt(Σ ref²)), and per receiver the bake's indirect part over the reference's.
#include "bake_test_util.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/bake/ground_truth.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rng.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/trace/ray.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace shprt {
namespace {

constexpr int kK = 16;
constexpr double kIndirectThreshold = 0.05;  // issue 34
constexpr double kTotalThreshold = 0.02;     // issue 34
// Paths per receiver and light rays per path point: the path tracer's relative standard error
// over the receivers is about 0.7-1.0 % for the indirect part and 0.2-0.4 % for the total
// (printed with the results), well under the thresholds' margins (the bake is 1.6-2.6 % from
// 8192 paths); 4096 paths halve the test's longest part (2 minutes under the sanitizers).
constexpr std::uint32_t kPaths = 4096;
constexpr std::uint32_t kEscapeRays = 16;
constexpr std::uint32_t kBakeSamples = 4096;
constexpr std::uint32_t kBackFaceRays = 4096;

// A receiver: the vertex nearest `position` whose normal is `normal`.
struct Target {
    const char* what;
    Vec3f position, normal;
};

// Spread over the parts, with vertices near the contacts the issue is about.
const Target kTargets[] = {
    {"floor, NW corner, under the ceiling", {-1.57f, 0, -1.59f}, {0, 1, 0}},
    {"floor, N, under the ceiling", {-0.13f, 0, -1.59f}, {0, 1, 0}},
    {"floor, NE corner, under the ceiling", {1.57f, 0, -1.59f}, {0, 1, 0}},
    {"floor, in front of the box", {-1.09f, 0, -0.23f}, {0, 1, 0}},
    {"floor, 9 cm from the box", {-0.61f, 0, -0.68f}, {0, 1, 0}},
    {"floor, centre, slabs' overlap", {0.13f, 0, 0.23f}, {0, 1, 0}},
    {"floor, under the table", {0.61f, 0, 0.23f}, {0, 1, 0}},
    {"floor, at the table's edge", {1.09f, 0, 0.68f}, {0, 1, 0}},
    {"floor, SE corner", {1.57f, 0, 1.59f}, {0, 1, 0}},
    {"floor, 7 cm from the rug", {-1.57f, 0, 1.59f}, {0, 1, 0}},
    {"floor, E", {1.57f, 0, -0.23f}, {0, 1, 0}},
    {"west wall, low", {-2, 0.38f, 0.23f}, {1, 0, 0}},
    {"west wall, under the ceiling", {-2, 1.34f, -1.14f}, {1, 0, 0}},
    {"west wall, high", {-2, 1.82f, 1.14f}, {1, 0, 0}},
    {"north wall, low", {-0.23f, 0.38f, -2}, {0, 0, 1}},
    {"north wall, mid", {1.14f, 1.34f, -2}, {0, 0, 1}},
    {"north wall, behind the box", {-1.14f, 0.86f, -2}, {0, 0, 1}},
    {"east wall, low", {2, 0.38f, -0.23f}, {-1, 0, 0}},
    {"east wall, mid", {2, 0.86f, 1.14f}, {-1, 0, 0}},
    {"east wall, high, under the ceiling", {2, 1.82f, -1.14f}, {-1, 0, 0}},
    {"south wall, low", {0.23f, 0.38f, 2}, {0, 0, -1}},
    {"south wall, mid", {-1.14f, 1.34f, 2}, {0, 0, -1}},
    {"south wall, by the table", {1.14f, 0.86f, 2}, {0, 0, -1}},
    {"table top, corner", {0.4f, 0.76f, -0.3f}, {0, 1, 0}},
    {"table top, far corner", {1.6f, 0.76f, 0.7f}, {0, 1, 0}},
    {"table underside, corner", {1.6f, 0.72f, -0.3f}, {0, -1, 0}},
    {"table front, lower corner", {0.4f, 0.72f, 0.7f}, {0, 0, 1}},
    {"die, side, on the table", {1.0f, 0.76f, 0.1f}, {-1, 0, 0}},
    {"die, top", {1.02f, 0.78f, 0.12f}, {0, 1, 0}},
    {"box, top corner", {-0.7f, 0.6f, -0.6f}, {0, 1, 0}},
    {"box, front, upper corner", {-1.5f, 0.6f, -0.6f}, {0, 0, 1}},
    {"box, west side, upper corner", {-1.5f, 0.6f, -1.4f}, {-1, 0, 0}},
    {"small box, top corner", {-0.45f, 0.75f, -0.7f}, {0, 1, 0}},
    {"small box, underside, over the floor", {-0.45f, 0.35f, -0.7f}, {0, -1, 0}},
    {"small box, east side, lower corner", {-0.45f, 0.35f, -1.15f}, {1, 0, 0}},
    {"rug, top corner", {-0.2f, 0.01f, 0.4f}, {0, 1, 0}},
    {"rug, west side, upper corner", {-1.5f, 0.01f, 1.6f}, {-1, 0, 0}},
};

std::uint32_t find_receiver(const Mesh& m, const Target& t) {
    std::uint32_t best = 0;
    float best_d = std::numeric_limits<float>::infinity();
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        if (dot(m.normals[v], t.normal) < 0.99f) continue;
        const float d = length(m.positions[v] - t.position);
        if (d < best_d) {
            best_d = d;
            best = std::uint32_t(v);
        }
    }
    EXPECT_LT(best_d, 0.05f) << t.what;
    return best;
}

// Whether any of `rays` cosine-distributed rays from v's offset origin first meets the back of
// a triangle.
bool sees_back_faces(const Mesh& m, const Tracer& tracer, std::uint32_t v, std::uint32_t rays) {
    const Vec3d n = normalize(cast<double>(m.normals[v]));
    Vec3d t, b;
    orthonormal_frame(n, t, b);
    const Vec3f origin = offset_ray_origin(m.positions[v], m.normals[v]);
    for (std::uint32_t j = 0; j < rays; ++j) {
        const RngBlock u = rng_block(1, (std::uint64_t(v) << 32) | j, 0x42414346u);  // "BACF"
        const Vec3d l = cosine_hemisphere_direction(to_unit_double(u.v[0], u.v[1]),
                                                    to_unit_double(u.v[2], u.v[3]));
        const Vec3f w = cast<float>(t * l.x + b * l.y + n * l.z);
        const Hit h = tracer.intersect(origin, w, 0.0f, std::numeric_limits<float>::infinity());
        if (!h.hit) continue;
        const auto& tri = m.triangles[h.triangle];
        const Vec3f p0 = m.positions[tri[0]];
        if (dot(cross(m.positions[tri[1]] - p0, m.positions[tri[2]] - p0), w) > 0) return true;
    }
    return false;
}

struct Light {
    const char* name;
    std::vector<double> coeffs;  // 3K
};

// A constant sky of radiance (0.6, 0.7, 0.9) plus, when `sun`, sun_colour · 8 · ((1 + w·d)/2)^3: a
// smooth lobe toward d (half its peak 54° away) that is a cubic in w·d, so its four bands are
// exact (zonal harmonics rotated to d, sh/zonal.hpp): no ringing, nowhere negative.
Light make_light(bool sun) {
    Light l{sun ? "sky + sun" : "constant sky", std::vector<double>(3 * kK, 0.0)};
    const double sky[3] = {0.6, 0.7, 0.9}, sun_colour[3] = {1.0, 0.9, 0.7};
    const double y0 = 0.5 / std::sqrt(kPi);
    std::vector<double> lobe(kK, 0.0);
    if (sun) {
        const std::vector<double> z =
            project_zonal([](double x) { return std::pow((1 + x) / 2, 3); }, 4);
        rotate_zonal(z.data(), kK, normalize(Vec3d{0.4, 0.8, -0.3}), lobe.data());
    }
    for (int c = 0; c < 3; ++c) {
        l.coeffs[c * kK] = sky[c] / y0;
        for (int i = 0; i < kK; ++i) l.coeffs[c * kK + i] += 8.0 * sun_colour[c] * lobe[i];
    }
    return l;
}

// E_c = Σ_i T[i]·L_c[i].
double shade(const float* T, const Light& light, int c) {
    double e = 0;
    for (int i = 0; i < kK; ++i) e += double(T[i]) * light.coeffs[c * kK + i];
    return e;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(BakeLeakyRoom, InterreflectionMatchesAPathTracer) {
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh room = make_builtin("leaky_room");
    const test::BruteForceTracer exact(room);
    std::vector<std::uint32_t> receivers;
    std::vector<bool> back;
    std::size_t seeing_back = 0;
    for (const Target& t : kTargets) {
        receivers.push_back(find_receiver(room, t));
        back.push_back(sees_back_faces(room, exact, receivers.back(), kBackFaceRays));
        seeing_back += back.back();
        if (back.back()) std::printf("sees back faces: %s\n", t.what);
    }
    const std::size_t R = receivers.size();
    std::printf("receivers: %zu, %zu of them see back faces (%zu one-sided)\n", R, seeing_back,
                R - seeing_back);
    EXPECT_LT(seeing_back, R / 4);

    // The lights are physical: non-negative everywhere (checked on a grid of directions).
    const Light lights[2] = {make_light(false), make_light(true)};
    for (const Light& light : lights) {
        double lowest = 1e30;
        std::vector<double> y(kK);
        for (int i = 0; i <= 64; ++i)
            for (int j = 0; j < 128; ++j) {
                const double th = kPi * i / 64, ph = 2 * kPi * j / 128;
                sh_eval_k<double>(kK, std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                                  std::cos(th), y.data());
                for (int c = 0; c < 3; ++c) {
                    double L = 0;
                    for (int k = 0; k < kK; ++k) L += light.coeffs[c * kK + k] * y[k];
                    lowest = std::min(lowest, L);
                }
            }
        EXPECT_GE(lowest, 0.0) << light.name;
    }

    // The bakes: N = 1 and 3, one- and two-sided.
    TransferSet bakes[2][2];  // [N = 1, 3][two_sided]
    for (int n = 0; n < 2; ++n)
        for (int two = 0; two < 2; ++two) {
            BakeOptions o;
            o.transfer = TransferKind::interreflected;
            o.K = kK;
            o.samples = kBakeSamples;
            o.sampler = SamplerKind::sobol;
            o.seed = 3;
            o.threads = 2;
            o.bounces = n == 0 ? 1 : 3;
            o.two_sided = two == 1;
            bakes[n][two] = bake(room, o);
            ASSERT_EQ(bakes[n][two].direct.size(), room.vertex_count() * kK);
        }
    const double bake_seconds = seconds_since(t0);

    PathTraceOptions po;
    po.bounces = 3;
    po.paths = kPaths;
    po.escape_rays = kEscapeRays;
    po.seed = 9;
    po.threads = 2;
    const auto t1 = std::chrono::steady_clock::now();
    const std::vector<std::vector<double>> coeffs = {lights[0].coeffs, lights[1].coeffs};
    const std::vector<PathTraceIrradiance> refs =
        path_trace_irradiance(room, receivers, kK, coeffs, po, exact);
    std::printf("path traced %zu receivers x %u paths, both lights, in %.1f s (%.2f M rays)\n", R,
                po.paths, seconds_since(t1), double(refs[0].rays_cast) * 1e-6);
    for (int li = 0; li < 2; ++li) {
        const Light& light = lights[li];
        const PathTraceIrradiance& ref = refs[std::size_t(li)];
        // The bake's direct and total irradiance at receiver r, channel c.
        const auto direct = [&](const TransferSet& set, std::size_t r, int c) {
            return shade(&set.direct[std::size_t(receivers[r]) * kK], light, c);
        };
        const auto total = [&](const TransferSet& set, std::size_t r, int c) {
            return shade(set.receiver(receivers[r], c), light, c);
        };
        // Where it goes wrong, at N = 3: the bake's indirect part over the path tracer's, per
        // receiver (green channel), one- and two-sided, and the path tracer's standard error.
        std::printf(
            "%s, N = 3, bake / path tracer, indirect (green):  one-sided  two-sided  s.e.\n",
            light.name);
        for (std::size_t r = 0; r < R; ++r) {
            const double ref_ind = ref.sum(r, 1, 3, 1);
            std::printf("    %-40s %9.3f %10.3f %5.3f%s\n", kTargets[r].what,
                        (total(bakes[1][0], r, 1) - direct(bakes[1][0], r, 1)) / ref_ind,
                        (total(bakes[1][1], r, 1) - direct(bakes[1][1], r, 1)) / ref_ind,
                        ref.indirect_std_error[ref.index(r, 3, 1)] / ref_ind,
                        back[r] ? "  sees back faces" : "");
        }
        for (int n = 0; n < 2; ++n) {
            const int N = n == 0 ? 1 : 3;
            for (int two = 0; two < 2; ++two) {
                const TransferSet& set = bakes[n][two];
                // Per part (indirect, total, direct): Σ (x − ref)², Σ ref², Σ (x − ref), Σ ref and
                // the path tracer's Σ s.e.².
                struct Sums {
                    double err2 = 0, ref2 = 0, err = 0, ref = 0, var = 0;
                    void add(double x, double r, double se) {
                        err2 += (x - r) * (x - r);
                        ref2 += r * r;
                        err += x - r;
                        ref += r;
                        var += se * se;
                    }
                    double rmse() const { return std::sqrt(err2 / ref2); }
                    double bias() const { return err / ref; }
                    double noise() const { return std::sqrt(var / ref2); }
                } ind, tot, dir;
                std::size_t used = 0;
                for (std::size_t r = 0; r < R; ++r) {
                    if (!two && back[r]) continue;
                    ++used;
                    for (int c = 0; c < 3; ++c) {
                        const double d = direct(set, r, c), t = total(set, r, c);
                        ind.add(t - d, ref.sum(r, 1, N, c),
                                ref.indirect_std_error[ref.index(r, N, c)]);
                        tot.add(t, ref.sum(r, 0, N, c), ref.total_std_error[ref.index(r, N, c)]);
                        dir.add(d, ref.mean[ref.index(r, 0, c)], ref.std_error[ref.index(r, 0, c)]);
                    }
                }
                std::printf(
                    "  %-12s N = %d %-9s %2zu receivers: indirect %5.1f %% (bias %+5.1f %%, "
                    "s.e. %.2f %%), total %5.2f %% (bias %+5.2f %%, s.e. %.2f %%), direct "
                    "%.2f %% (s.e. %.2f %%)\n",
                    light.name, N, two ? "two-sided" : "one-sided", used, 100 * ind.rmse(),
                    100 * ind.bias(), 100 * ind.noise(), 100 * tot.rmse(), 100 * tot.bias(),
                    100 * tot.noise(), 100 * dir.rmse(), 100 * dir.noise());
                const std::string what = std::string(light.name) + ", N = " + std::to_string(N) +
                                         (two ? ", two-sided" : ", one-sided");
                EXPECT_LT(ind.rmse(), kIndirectThreshold) << what;
                EXPECT_LT(tot.rmse(), kTotalThreshold) << what;
                // The test's own machinery: the direct part is the bake's shadowed transfer, which
                // only its 4096-direction quadrature separates from the path tracer's (measured
                // 0.6 %).
                EXPECT_LT(dir.rmse(), 0.015) << what;
                EXPECT_LT(ind.noise(), 0.01) << what << ": the path tracer is too noisy";
                EXPECT_LT(tot.noise(), 0.005) << what << ": the path tracer is too noisy";
            }
        }
    }
    std::printf("bakes %.1f s, all %.1f s\n", bake_seconds, seconds_since(t0));
}

// The contact zone of a box on a floor (issue 34: the vertices' interpolation was +12 % there on
// the reporter's room): builtin:box_on_plane's floor vertices within 15 cm of the box's foot, the
// bake's indirect part (N = 3, constant sky, RGB albedo) against the path tracer on Embree (the
// scene has 2 000 triangles), with the mesh's vertices as the bounce sources (the discretisation
// before the sources had cells) and with the default sources. The default must be the closer and
// within the 5 %.
TEST(BakeLeakyRoom, ContactBandOfABoxOnAFloor) {
    Mesh mesh = make_builtin("box_on_plane");
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        mesh.albedo[v] =
            mesh.positions[v].y > 1e-4f ? Vec3f{0.2f, 0.4f, 0.9f} : Vec3f{0.9f, 0.6f, 0.3f};
    std::vector<std::uint32_t> band;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const Vec3f p = mesh.positions[v];
        if (p.y != 0.0f || mesh.normals[v].y < 0.99f) continue;
        const float dx = std::max(std::abs(p.x) - 0.5f, 0.0f);
        const float dz = std::max(std::abs(p.z) - 0.5f, 0.0f);
        const float d = std::sqrt(dx * dx + dz * dz);
        if ((dx > 0 || dz > 0 || std::abs(p.x) == 0.5f || std::abs(p.z) == 0.5f) && d <= 0.15f)
            band.push_back(std::uint32_t(v));
    }
    ASSERT_GT(band.size(), 40u);
    const Light sky = make_light(false);
    PathTraceOptions po;
    po.bounces = 3;
    po.paths = 2048;
    po.escape_rays = 8;
    po.seed = 5;
    po.threads = 2;
    const auto tracer = make_embree_tracer(mesh);
    const PathTraceIrradiance ref = path_trace_irradiance(mesh, band, kK, sky.coeffs, po, *tracer);
    double err[2] = {}, noise = 0;
    for (int sources = 0; sources < 2; ++sources) {
        BakeOptions o;
        o.transfer = TransferKind::interreflected;
        o.K = kK;
        o.samples = kBakeSamples;
        o.seed = 3;
        o.threads = 2;
        o.bounces = 3;
        if (sources == 0) {  // before: the vertices, every direction
            o.source_spacing = std::numeric_limits<float>::infinity();
            o.indirect_samples = kBakeSamples;
        }
        const TransferSet t = bake(mesh, o);
        double err2 = 0, ref2 = 0, var = 0;
        for (std::size_t r = 0; r < band.size(); ++r)
            for (int c = 0; c < 3; ++c) {
                const double ind = shade(t.receiver(band[r], c), sky, c) -
                                   shade(&t.direct[std::size_t(band[r]) * kK], sky, c);
                const double x = ref.sum(r, 1, 3, c);
                err2 += (ind - x) * (ind - x);
                ref2 += x * x;
                var += std::pow(ref.indirect_std_error[ref.index(r, 3, c)], 2);
            }
        err[sources] = std::sqrt(err2 / ref2);
        noise = std::sqrt(var / ref2);
    }
    std::printf(
        "box on a floor, %zu floor vertices within 15 cm of the box, N = 3, constant sky: "
        "indirect %.1f %% with the vertices as sources, %.1f %% with the default sources "
        "(path tracer s.e. %.2f %%)\n",
        band.size(), 100 * err[0], 100 * err[1], 100 * noise);
    EXPECT_LT(err[1], err[0]);
    EXPECT_LT(err[1], kIndirectThreshold);
}

}  // namespace
}  // namespace shprt
