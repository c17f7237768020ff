// Transfer probes (bake/probe_bake.hpp): at probe points in a room built the way real assets are
// (builtin:leaky_room: overlapping, interpenetrating, open-backed parts), the incident radiance
// M·L under a test light agrees with a brute-force integration written here — rays from the
// point, closest hits by Embree, the light's SH evaluated per ray; for interreflected probes the
// light a hit sends, ρ/π times its irradiance gathered by rays of its own — to within Monte
// Carlo noise. A probe inside a closed box is invalid; the bits do not depend on the threads;
// bad specs are one clear line.
#include "shprt/bake/probe_bake.hpp"
#include "shprt/bake/request.hpp"
#include "shprt/core/error.hpp"
#include "shprt/scene/leaky_room.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace shprt {
namespace {

constexpr int kK = 9;  // 3 bands
constexpr double kPi = 3.14159265358979323846;

// The test light: a bright lobe toward the upper +x, +z sky on a dim ambient, as SH coefficients
// (a clamped-cosine-like zonal lobe, c_lm = a_l · y_lm(d)).
std::vector<double> test_light() {
    const Vec3d d = normalize(Vec3d{0.5, 1.0, 0.3});
    double y[kK];
    sh_eval_k(kK, d.x, d.y, d.z, y);
    const double a[3] = {2.0, 1.6, 0.7};
    std::vector<double> L(kK);
    for (int l = 0, i = 0; l < 3; ++l)
        for (int m = -l; m <= l; ++m, ++i) L[std::size_t(i)] = a[l] * y[i];
    L[0] += 0.4;
    return L;
}

double radiance(const std::vector<double>& L, Vec3d w) {
    double y[kK];
    sh_eval_k(kK, w.x, w.y, w.z, y);
    double r = 0;
    for (int i = 0; i < kK; ++i) r += L[std::size_t(i)] * y[i];
    return r;
}

// A uniform direction on the sphere.
Vec3d uniform_sphere(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double z = 1.0 - 2.0 * u(rng), phi = 2.0 * kPi * u(rng);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// A cosine-distributed direction around the unit normal n.
Vec3d cosine_hemisphere(std::mt19937_64& rng, Vec3d n) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double r = std::sqrt(u(rng)), phi = 2.0 * kPi * u(rng);
    const Vec3d t =
        normalize(std::abs(n.x) > 0.5 ? cross(n, Vec3d{0, 1, 0}) : cross(n, Vec3d{1, 0, 0}));
    const Vec3d b = cross(n, t);
    const double z = std::sqrt(std::max(0.0, 1.0 - r * r));
    return normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

struct HitFace {
    Vec3f normal;  // unit, geometric
    bool front;
    Vec3d albedo;
};
HitFace face_of(const Mesh& mesh, const Hit& h, Vec3d dir) {
    const auto& t = mesh.triangles[h.triangle];
    const Vec3f a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    const Vec3f n = normalize(cross(b - a, c - a));
    const double bary[3] = {1.0 - h.u - h.v, h.u, h.v};
    Vec3d rho{0, 0, 0};
    for (int k = 0; k < 3; ++k) rho = rho + cast<double>(mesh.albedo[t[std::size_t(k)]]) * bary[k];
    return {n, dot(cast<double>(n), dir) < 0, rho};
}

// The brute force: L_in,c = ∫ y_i(ω) L_c(ω) dω at p with `rays` uniform directions; a ray that
// escapes brings the light, one that hits a front face (when `bounce`) ρ_c/π · E(h), E gathered
// by `gather` cosine-distributed rays from the hit; anything else nothing. Returns the estimate
// and, per coefficient, the standard deviation of one ray's term (its noise is that / √rays).
struct Estimate {
    std::vector<double> mean, sigma;  // 3 channels × K
};
Estimate brute_force(const Mesh& mesh, const Tracer& tracer, Vec3f p, const std::vector<double>& L,
                     int rays, bool bounce, int gather, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    std::vector<double> sum(3 * kK, 0.0), sum2(3 * kK, 0.0);
    for (int r = 0; r < rays; ++r) {
        const Vec3d w = uniform_sphere(rng);
        const Hit h = tracer.intersect(p, cast<float>(w), 0.0f, kInf);
        Vec3d light{0, 0, 0};
        if (!h.hit) {
            const double e = radiance(L, w);
            light = {e, e, e};
        } else if (bounce) {
            const HitFace f = face_of(mesh, h, w);
            if (f.front) {
                const Vec3f hp = p + cast<float>(w) * h.t;
                const Vec3d n = cast<double>(f.normal);
                double E = 0;
                for (int g = 0; g < gather; ++g) {
                    const Vec3d v = cosine_hemisphere(rng, n);
                    if (!tracer
                             .intersect(offset_ray_origin(hp, f.normal), cast<float>(v), 0.0f, kInf)
                             .hit)
                        E += radiance(L, v);
                }
                E *= kPi / gather;
                light = f.albedo * (E / kPi);
            }
        }
        double y[kK];
        sh_eval_k(kK, w.x, w.y, w.z, y);
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < kK; ++i) {
                const double term = 4.0 * kPi * y[i] * light[c];
                sum[std::size_t(c * kK + i)] += term;
                sum2[std::size_t(c * kK + i)] += term * term;
            }
    }
    Estimate e{std::vector<double>(3 * kK), std::vector<double>(3 * kK)};
    for (std::size_t k = 0; k < sum.size(); ++k) {
        e.mean[k] = sum[k] / rays;
        e.sigma[k] = std::sqrt(std::max(0.0, sum2[k] / rays - e.mean[k] * e.mean[k]));
    }
    return e;
}

// How far the probe's M·L is from the brute force, in units of the two estimates' combined
// Monte Carlo noise: max over coefficients of |got − want| / (σ·√(1/rays + 1/S)) (the bake's S
// directions counted as uniform ones: Sobol's error is lower).
double noise_units(const std::vector<double>& got, const Estimate& want, int rays, int S) {
    double worst = 0;
    for (std::size_t k = 0; k < got.size(); ++k) {
        const double noise = want.sigma[k] * std::sqrt(1.0 / rays + 1.0 / S) + 1e-6;
        worst = std::max(worst, std::abs(got[k] - want.mean[k]) / noise);
    }
    return worst;
}

// The probe's incident radiance M_c·L, channel c (a one-channel grid: its channel for every c).
std::vector<double> probe_radiance(const ProbeGrid& g, std::size_t probe,
                                   const std::vector<double>& L) {
    std::vector<double> out(3 * kK, 0.0);
    for (int c = 0; c < 3; ++c) {
        const float* M = g.matrix(probe, g.channels == 3 ? c : 0);
        for (int i = 0; i < kK; ++i)
            for (int j = 0; j < kK; ++j)
                out[std::size_t(c * kK + i)] += double(M[i * kK + j]) * L[std::size_t(j)];
    }
    return out;
}

// The room's probes through the bake request: 2×2×2 at the centres of cells of the box (x, z in
// [-1.2, 1.2], y in [0.3, 1.5]) — one of them, (0.6, 0.6, 0.6), under the table.
BakeResult bake_room_probes(const Mesh& room, TransferKind kind, std::uint32_t samples,
                            int threads = 0) {
    BakeRequest r;
    r.options.transfer = kind;
    // Interreflected probes read the bounce sources' light in the probes' K coefficients.
    r.options.K = kind == TransferKind::interreflected ? kK : 1;
    r.options.samples = samples;
    r.options.threads = threads;
    r.probes = parse_probes("2,2,2", "-1.2,0.3,-1.2,1.2,1.5,1.2", 3);
    return run(r, room);
}

const Mesh& room() {
    static const Mesh mesh = generate_leaky_room(LeakyRoomOptions{1.0f});
    return mesh;
}

TEST(BakeProbes, ShadowedProbesAgreeWithBruteForce) {
    constexpr int kS = 4096, kRays = 20000;
    const BakeResult result = bake_room_probes(room(), TransferKind::shadowed, kS);
    const ProbeGrid& g = result.transfer.probes;
    ASSERT_EQ(g.count(), 8u);
    EXPECT_EQ(g.K, kK);
    EXPECT_EQ(g.channels, 1);
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(room());
    const std::vector<double> L = test_light();
    std::vector<double> sky(3 * kK);  // the incident radiance with nothing around: L itself
    for (std::size_t k = 0; k < sky.size(); ++k) sky[k] = L[k % kK];
    double worst = 0, worst_sky = 0;
    for (std::size_t probe = 0; probe < g.count(); ++probe) {
        ASSERT_EQ(g.valid[probe], 1) << probe;
        const Vec3f p = g.position(int(probe % 2), int(probe / 2 % 2), int(probe / 4));
        const Estimate want = brute_force(room(), *tracer, p, L, kRays, false, 0, probe);
        const double units = noise_units(probe_radiance(g, probe, L), want, kRays, kS);
        worst = std::max(worst, units);
        // What the test can see: the unoccluded sky (M = identity) is many noise units off.
        worst_sky = std::max(worst_sky, noise_units(sky, want, kRays, kS));
        EXPECT_LT(units, 4.5) << "probe " << probe;
    }
    EXPECT_GT(worst_sky, 50.0);
    std::printf("shadowed probes: worst %.2f noise units (open sky: %.0f)\n", worst, worst_sky);
}

TEST(BakeProbes, InterreflectedProbesAgreeWithBruteForce) {
    constexpr int kS = 2048, kRays = 4000;
    const BakeResult result = bake_room_probes(room(), TransferKind::interreflected, kS);
    const ProbeGrid& g = result.transfer.probes;
    ASSERT_EQ(g.count(), 8u);
    EXPECT_EQ(g.channels, 3);
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(room());
    const std::vector<double> L = test_light();
    double worst = 0, worst_direct = 0;
    for (std::size_t probe = 0; probe < g.count(); ++probe) {
        ASSERT_EQ(g.valid[probe], 1) << probe;
        const Vec3f p = g.position(int(probe % 2), int(probe / 2 % 2), int(probe / 4));
        const Estimate want = brute_force(room(), *tracer, p, L, kRays, true, 24, probe);
        const Estimate direct = brute_force(room(), *tracer, p, L, kRays, false, 0, probe + 100);
        const double units = noise_units(probe_radiance(g, probe, L), want, kRays, kS);
        worst = std::max(worst, units);
        worst_direct = std::max(worst_direct, noise_units(direct.mean, want, kRays, kS));
        EXPECT_LT(units, 4.5) << "probe " << probe;
    }
    // The bounced light matters here: without it the probes would be this far off.
    EXPECT_GT(worst_direct, 20.0);
    std::printf("interreflected probes: worst %.2f noise units (without bounce: %.0f)\n", worst,
                worst_direct);
}

TEST(BakeProbes, ProbesInsideGeometryAreInvalidAndZero) {
    // Inside the closed box [-0.9, -0.45] x [0.35, 0.75] x [-1.15, -0.7]; inside the bottomless
    // box [-1.5, -0.7] x [-0.05, 0.6] x [-1.4, -0.6] (it sees the floor through its open
    // bottom); and in the room.
    const Vec3f points[] = {{-0.675f, 0.55f, -0.925f}, {-1.2f, 0.3f, -1.2f}, {0.0f, 1.2f, 0.0f}};
    const int expected[] = {0, 0, 1};
    for (int k = 0; k < 3; ++k) {
        const Vec3f p = points[k];
        BakeRequest r;
        r.options.K = 1;
        r.options.samples = 512;
        r.probes = parse_probes(
            "1,1,1", fmt::format("{},{},{},{},{},{}", p.x, p.y, p.z, p.x, p.y, p.z), std::nullopt);
        const ProbeGrid g = run(r, room()).transfer.probes;
        ASSERT_EQ(g.count(), 1u);
        EXPECT_EQ(g.valid[0], expected[k]) << k;
        float largest = 0;
        for (float v : g.matrices) largest = std::max(largest, std::abs(v));
        if (expected[k] == 0)
            EXPECT_EQ(largest, 0.0f) << k;
        else
            EXPECT_GT(largest, 0.0f) << k;
    }
}

TEST(BakeProbes, SameBitsForAnyThreadCount) {
    for (TransferKind kind : {TransferKind::shadowed, TransferKind::interreflected}) {
        const ProbeGrid one = bake_room_probes(room(), kind, 256, 1).transfer.probes;
        const ProbeGrid two = bake_room_probes(room(), kind, 256, 2).transfer.probes;
        EXPECT_TRUE(one == two) << to_string(kind);
    }
}

TEST(BakeProbes, GridLayout) {
    // auto: the default spacing, centred on the bounds; counts alone: cell centres.
    const ProbeGrid a =
        probe_grid_layout(*parse_probes("auto", "0,0,0,4,1,2", std::nullopt), room(), false);
    EXPECT_EQ(a.counts, (std::array<int, 3>{8, 2, 4}));
    EXPECT_FLOAT_EQ(a.spacing.x, kDefaultProbeSpacing);
    EXPECT_FLOAT_EQ(a.origin.x, 0.25f);
    EXPECT_FLOAT_EQ(a.far_corner().z, 1.75f);
    const ProbeGrid b = probe_grid_layout(*parse_probes("4,1,2", "0,0,0,4,1,2", 2), room(), true);
    EXPECT_EQ(b.counts, (std::array<int, 3>{4, 1, 2}));
    EXPECT_FLOAT_EQ(b.spacing.x, 1.0f);
    EXPECT_FLOAT_EQ(b.origin.y, 0.5f);
    EXPECT_EQ(b.K, 4);
    EXPECT_EQ(b.channels, 3);
    // A huge scene's auto grid is capped.
    const ProbeGrid c =
        probe_grid_layout(*parse_probes("auto", "0,0,0,1000,10,1000", std::nullopt), room(), false);
    EXPECT_LE(c.count(), kMaxAutoProbes);
}

TEST(BakeProbes, BadSpecsAreOneClearLine) {
    const struct {
        const char *probes, *box;
        std::optional<long long> bands;
        const char* message;
    } cases[] = {
        {"", "0,0,0,1,1,1", std::nullopt, "--probe-box needs --probes"},
        {"", "", 3, "--probe-bands needs --probes"},
        {"x", "", std::nullopt, "expected auto"},
        {"1,x,3", "", std::nullopt, "'x' is not a whole number"},
        {"1,2", "", std::nullopt, "expected auto"},
        {"1,2,3,4", "", std::nullopt, "expected auto"},
        {"0,1,1", "", std::nullopt, "each count must be 1 to 1024"},
        {"1025,1,1", "", std::nullopt, "each count must be 1 to 1024"},
        {"1024,1024,8", "", std::nullopt, "more than the"},
        {"auto:0", "", std::nullopt, "the spacing must be a positive number"},
        {"auto:-1", "", std::nullopt, "the spacing must be a positive number"},
        {"2,2,2:x", "", std::nullopt, "the spacing must be a positive number"},
        {"auto", "1,2,3", std::nullopt, "--probe-box"},
        {"auto", "1,0,0,0,1,1", std::nullopt, "at most the high one's"},
        {"auto", "", 0, "--probe-bands 0: must be 1 to 8"},
        {"auto", "", 9, "--probe-bands 9: must be 1 to 8"},
    };
    for (const auto& c : cases) {
        try {
            parse_probes(c.probes, c.box, c.bands);
            ADD_FAILURE() << "accepted --probes '" << c.probes << "' --probe-box '" << c.box << "'";
        } catch (const Error& e) {
            const std::string message = e.what();
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << message;
            EXPECT_NE(message.find(c.message), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    }
}

TEST(BakeProbes, RequestsThatCannotCarryProbesAreRefused) {
    BakeRequest r;
    r.probes = ProbeSpec{};
    r.receivers = VertexShard{0, 2};
    ASSERT_TRUE(request_refusal(r));
    EXPECT_NE(request_refusal(r)->find("--probes does not go with --shard"), std::string::npos);
    r.receivers = AllVertices{};
    r.output.emplace();
    r.output->path = "x.shprt";
    r.output->stream = true;
    EXPECT_NE(request_refusal(r)->find("--stream"), std::string::npos);
    r.output->stream = false;
    EXPECT_FALSE(request_refusal(r));
    // Interreflected probes read the bounce light in their K: the bake needs as many.
    r.options.transfer = TransferKind::interreflected;
    r.options.K = 4;
    try {
        check(r);
        ADD_FAILURE() << "3-band interreflected probes of a K = 4 bake were accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("give --bands 3 or more"), std::string::npos)
            << e.what();
    }
    r.options.K = 9;
    EXPECT_NO_THROW(check(r));
}

}  // namespace
}  // namespace shprt
