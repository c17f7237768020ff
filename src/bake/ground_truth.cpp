// Ground-truth irradiance by direct Monte Carlo integration of L·V·cos per vertex, no SH.
//
// Estimators: cosine-weighted hemisphere sampling for the smooth sky and uniform cone sampling
// for constant-radiance discs (Pharr, Jakob & Humphreys, "Physically Based Rendering", 3rd ed.,
// §13.6: Shirley & Chiu 1997's concentric disc map, Malley's method, uniform cone sampling).
// Points: Sobol (0,2)-sequence with hash-based Owen scrambling (Burley 2020), as in sh/sampler.hpp.
// Frames: Duff, Burgess, Christensen, Hery, Kensler, Liani & Villemin, "Building an Orthonormal
// Basis, Revisited", JCGT 6(1), 2017.
#include "shprt/bake/ground_truth.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/sh/rng.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>

namespace shprt {
namespace {

using Clock = std::chrono::steady_clock;

// Vertices per task: small enough to balance, large enough that scheduling is free.
constexpr std::size_t kGrain = 64;

struct Disc {
    Vec3d axis, t, b;  // unit axis and its frame
    double cos_max = 1, solid_angle = 0;
    Vec3d radiance;
};

struct Scratch {
    std::vector<Vec3f> dirs;
    std::vector<double> weight;  // per ray: what a visible ray adds (sky: L; disc: cos)
    std::vector<Vec3d> sky_dir;  // the sky's directions in double (Ns)
    std::vector<std::uint8_t> occluded;
};

// Scrambled Sobol point j of the (0,2)-sequence with the two scramble words of `key`.
inline void sobol_point(std::uint32_t j, const RngBlock& key, double& u1, double& u2) {
    u1 = to_unit_double(owen_scramble(sobol_u32(j, 0), key.v[0]), key.v[2]);
    u2 = to_unit_double(owen_scramble(sobol_u32(j, 1), key.v[1]), key.v[3]);
}

void check_light(const GroundTruthLight& light, std::vector<Disc>& discs) {
    for (std::size_t d = 0; d < light.discs.size(); ++d) {
        const GroundTruthDisc& g = light.discs[d];
        const double len = length(g.direction);
        SHPRT_CHECK(std::isfinite(len) && len > 0, invalid_argument,
                    "ground truth: disc {} has direction ({}, {}, {}); it must be non-zero", d,
                    g.direction.x, g.direction.y, g.direction.z);
        SHPRT_CHECK(std::isfinite(g.radius_deg) && g.radius_deg > 0 && g.radius_deg <= 90,
                    invalid_argument, "ground truth: disc {} radius {}° must be in (0, 90]", d,
                    g.radius_deg);
        for (int c = 0; c < 3; ++c)
            SHPRT_CHECK(std::isfinite(g.radiance[c]) && g.radiance[c] >= 0, invalid_argument,
                        "ground truth: disc {} radiance ({}, {}, {}) must be finite and ≥ 0", d,
                        g.radiance.x, g.radiance.y, g.radiance.z);
        Disc out;
        out.axis = g.direction / len;
        orthonormal_frame(out.axis, out.t, out.b);
        out.cos_max = std::cos(g.radius_deg * kDeg);
        out.solid_angle = 2 * kPi * (1 - out.cos_max);
        out.radiance = g.radiance;
        discs.push_back(out);
    }
}

}  // namespace

void orthonormal_frame(Vec3d n, Vec3d& t, Vec3d& b) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double c = n.x * n.y * a;
    t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

Vec3d cosine_hemisphere_direction(double u1, double u2) {
    const double a = 2 * u1 - 1, b = 2 * u2 - 1;
    double x = 0, y = 0;
    if (a != 0 || b != 0) {
        double r, phi;
        if (std::fabs(a) > std::fabs(b)) {
            r = a;
            phi = 0.25 * kPi * (b / a);
        } else {
            r = b;
            phi = 0.5 * kPi - 0.25 * kPi * (a / b);
        }
        x = r * std::cos(phi);
        y = r * std::sin(phi);
    }
    return {x, y, std::sqrt(std::max(0.0, 1 - x * x - y * y))};
}

Vec3d uniform_cone_direction(double u1, double u2, double cos_max) {
    const double z = 1 - u1 * (1 - cos_max);
    const double s = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = 2 * kPi * u2;
    return {s * std::cos(phi), s * std::sin(phi), z};
}

GroundTruth ground_truth_irradiance(const Mesh& mesh, const GroundTruthLight& light,
                                    const GroundTruthOptions& options) {
    const auto start = Clock::now();
    SHPRT_CHECK(mesh.vertex_count() > 0 && !mesh.triangles.empty(), invalid_argument,
                "ground truth: mesh '{}' is empty", mesh.source);
    std::unique_ptr<Tracer> tracer;
    if (options.transfer == TransferKind::shadowed) {
        // Embree builds with TBB tasks in the caller's arena: keep it to our thread count.
        in_arena(options.threads, [&] { tracer = make_embree_tracer(mesh); });
    } else {
        // Unshadowed transfer never traces; any tracer object satisfies the interface.
        tracer = make_embree_tracer(mesh);
    }
    GroundTruth out = ground_truth_irradiance(mesh, light, options, *tracer);
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
}

GroundTruth ground_truth_irradiance(const Mesh& mesh, const GroundTruthLight& light,
                                    const GroundTruthOptions& options, const Tracer& tracer) {
    const auto start = Clock::now();
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(V > 0, invalid_argument, "ground truth: mesh '{}' has no vertices", mesh.source);
    SHPRT_CHECK(mesh.normals.size() == V, invalid_argument,
                "ground truth: mesh '{}' has {} normals for {} vertices", mesh.source,
                mesh.normals.size(), V);
    SHPRT_CHECK(options.threads >= 0, invalid_argument,
                "ground truth: threads = {} must be ≥ 0 (0 = all)", options.threads);
    const bool has_sky = static_cast<bool>(light.sky);
    SHPRT_CHECK(!has_sky || options.sky_samples > 0, invalid_argument,
                "ground truth: sky_samples must be ≥ 1");
    SHPRT_CHECK(light.discs.empty() || options.disc_samples > 0, invalid_argument,
                "ground truth: disc_samples must be ≥ 1");
    std::vector<Disc> discs;
    check_light(light, discs);
    const bool shadowed = options.transfer == TransferKind::shadowed;
    const std::uint32_t Ns = has_sky ? options.sky_samples : 0u;
    const std::uint32_t Nd = options.disc_samples;
    const std::size_t D = discs.size();

    GroundTruth out;
    out.irradiance.assign(V, Vec3d{0, 0, 0});
    out.sky_irradiance.assign(V, Vec3d{0, 0, 0});
    out.disc_visibility.assign(D * V, -1.0f);

    std::atomic<std::uint64_t> rays{0};
    std::atomic<std::size_t> done{0};
    std::atomic<bool> stop{false};
    const auto caller = std::this_thread::get_id();
    auto last_report = Clock::now();
    const auto report = [&]() {
        return options.progress(
            ProgressInfo{"ground truth", done.load(), static_cast<std::uint64_t>(V), "vertices"});
    };
    const std::size_t max_rays = std::max<std::size_t>(Ns, Nd);
    tbb::enumerable_thread_specific<Scratch> scratch([&] {
        Scratch s;
        s.dirs.resize(max_rays);
        s.weight.resize(max_rays);
        s.sky_dir.resize(Ns);
        s.occluded.assign(max_rays, 0);
        return s;
    });
    constexpr float kInf = std::numeric_limits<float>::infinity();

    const auto run_vertex = [&](std::size_t v, Scratch& sc) {
        const Vec3d n = normalize(cast<double>(mesh.normals[v]));
        Vec3d t, b;
        orthonormal_frame(n, t, b);
        const Vec3f origin = offset_ray_origin(mesh.positions[v], mesh.normals[v]);
        std::uint64_t cast_here = 0;

        // Sky: cosine-weighted directions, E = π/N Σ L·V.
        if (Ns > 0) {
            const RngBlock key = rng_block(options.seed, v, kStreamGroundTruthSky);
            for (std::uint32_t j = 0; j < Ns; ++j) {
                double u1, u2;
                sobol_point(j, key, u1, u2);
                const Vec3d l = cosine_hemisphere_direction(u1, u2);
                sc.sky_dir[j] = normalize(t * l.x + b * l.y + n * l.z);
                sc.dirs[j] = cast<float>(sc.sky_dir[j]);
            }
            if (shadowed) {
                tracer.occluded(origin, sc.dirs.data(), static_cast<int>(Ns), 0.0f, kInf,
                                sc.occluded.data());
                cast_here += Ns;
            }
            // The sky is evaluated only where it is seen (it may be costly).
            Vec3d sum{0, 0, 0};
            for (std::uint32_t j = 0; j < Ns; ++j) {
                if (shadowed && sc.occluded[j]) continue;
                const Vec3d w = sc.sky_dir[j];
                const Vec3d L = light.sky(w);
                SHPRT_CHECK(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z) &&
                                L.x >= 0 && L.y >= 0 && L.z >= 0,
                            invalid_argument,
                            "ground truth: the sky returned ({}, {}, {}) for direction ({}, {}, "
                            "{}); radiance must be finite and ≥ 0",
                            L.x, L.y, L.z, w.x, w.y, w.z);
                sum += L;
            }
            out.sky_irradiance[v] = sum * (kPi / Ns);
        }
        Vec3d E = out.sky_irradiance[v];

        // Discs: uniform in the cone, E = Ω/N Σ L·V·max(0, n·w).
        for (std::size_t d = 0; d < D; ++d) {
            const Disc& disc = discs[d];
            const RngBlock key =
                rng_block(options.seed, v, kStreamGroundTruthDisc + static_cast<std::uint32_t>(d));
            std::uint32_t m = 0;
            double cos_sum = 0;
            for (std::uint32_t j = 0; j < Nd; ++j) {
                double u1, u2;
                sobol_point(j, key, u1, u2);
                const Vec3d l = uniform_cone_direction(u1, u2, disc.cos_max);
                const Vec3d w = normalize(disc.t * l.x + disc.b * l.y + disc.axis * l.z);
                const double c = dot(n, w);
                if (c <= 0) continue;  // below the horizon: no contribution, no ray
                sc.dirs[m] = cast<float>(w);
                sc.weight[m] = c;
                cos_sum += c;
                ++m;
            }
            if (m == 0) continue;  // visibility stays −1: the disc is below the horizon
            double visible_sum = cos_sum;
            if (shadowed) {
                tracer.occluded(origin, sc.dirs.data(), static_cast<int>(m), 0.0f, kInf,
                                sc.occluded.data());
                cast_here += m;
                visible_sum = 0;
                for (std::uint32_t r = 0; r < m; ++r)
                    if (!sc.occluded[r]) visible_sum += sc.weight[r];
            }
            E += disc.radiance * (disc.solid_angle / Nd * visible_sum);
            out.disc_visibility[d * V + v] = static_cast<float>(visible_sum / cos_sum);
        }
        out.irradiance[v] = E;
        rays.fetch_add(cast_here, std::memory_order_relaxed);
    };

    in_arena(options.threads, [&] {
        parallel_for(0, V, kGrain, Split::automatic, [&](std::size_t first, std::size_t last) {
            if (stop.load(std::memory_order_relaxed)) return;
            Scratch& sc = scratch.local();
            for (std::size_t v = first; v != last; ++v) run_vertex(v, sc);
            done.fetch_add(last - first, std::memory_order_relaxed);
            if (options.progress && std::this_thread::get_id() == caller) {
                const auto now = Clock::now();
                if (now - last_report >= std::chrono::milliseconds(200)) {
                    last_report = now;
                    if (!report()) stop.store(true);
                }
            }
        });
    });
    if (!stop.load() && options.progress && !report()) stop.store(true);
    SHPRT_CHECK(!stop.load(), cancelled, "ground truth cancelled after {} of {} vertices",
                done.load(), V);
    out.rays_cast = rays.load();
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
}

}  // namespace shprt
