// Ground-truth irradiance by direct Monte Carlo integration of L·V·cos per vertex, no SH.
//
// Estimators: cosine-weighted hemisphere sampling for the smooth sky and uniform cone sampling
// for constant-radiance discs (Pharr, Jakob & Humphreys, "Physically Based Rendering", 3rd ed.,
// §13.6: Shirley & Chiu 1997's concentric disc map, Malley's method, uniform cone sampling).
// Points: Sobol (0,2)-sequence with hash-based Owen scrambling (Burley 2020), as in sh/sampler.hpp.
// Frames: Duff, Burgess, Christensen, Hery, Kensler, Liani & Villemin, "Building an Orthonormal
// Basis, Revisited", JCGT 6(1), 2017. The path tracer: Kajiya, "The Rendering Equation",
// SIGGRAPH 1986, with next-event estimation of the distant light by cosine-weighted rays (PBRT
// 3rd ed., §14.5).
#include "shprt/bake/ground_truth.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/basis.hpp"
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
#include <utility>
#include <vector>

namespace shprt {
namespace {

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

// Runs body(first, last, done) over [0, count) in ranges of about `grain` on `threads` threads,
// reporting ProgressInfo{stage, done, count, "vertices"} from the calling thread at most five
// times a second and once at the end; stops early and throws Error(cancelled) when it returns
// false.
template <class Body>
void for_vertices(std::size_t count, std::size_t grain, int threads, const ProgressFn& progress,
                  const char* stage, Body&& body) {
    std::atomic<std::size_t> done{0};
    std::atomic<bool> stop{false};
    const auto caller = std::this_thread::get_id();
    auto last_report = Clock::now();
    const auto report = [&]() {
        return progress(
            ProgressInfo{stage, done.load(), static_cast<std::uint64_t>(count), "vertices"});
    };
    in_arena(threads, [&] {
        parallel_for(0, count, grain, Split::automatic, [&](std::size_t first, std::size_t last) {
            if (stop.load(std::memory_order_relaxed)) return;
            body(first, last);
            done.fetch_add(last - first, std::memory_order_relaxed);
            if (progress && std::this_thread::get_id() == caller) {
                const auto now = Clock::now();
                if (now - last_report >= std::chrono::milliseconds(200)) {
                    last_report = now;
                    if (!report()) stop.store(true);
                }
            }
        });
    });
    if (!stop.load() && progress && !report()) stop.store(true);
    SHPRT_CHECK(!stop.load(), cancelled, "{} cancelled after {} of {} vertices", stage, done.load(),
                count);
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

    for_vertices(V, kGrain, options.threads, options.progress, "ground truth",
                 [&](std::size_t first, std::size_t last) {
                     Scratch& sc = scratch.local();
                     for (std::size_t v = first; v != last; ++v) run_vertex(v, sc);
                 });
    out.rays_cast = rays.load();
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
}

std::vector<PathTraceIrradiance> path_trace_irradiance(const Mesh& mesh,
                                                       std::span<const std::uint32_t> vertices,
                                                       int K,
                                                       std::span<const std::vector<double>> lights,
                                                       const PathTraceOptions& options,
                                                       const Tracer& tracer) {
    const auto start = Clock::now();
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(V > 0 && !mesh.triangles.empty(), invalid_argument,
                "path trace: mesh '{}' is empty", mesh.source);
    SHPRT_CHECK(mesh.normals.size() == V && mesh.albedo.size() == V, invalid_argument,
                "path trace: mesh '{}' has {} normals and {} albedos for {} vertices", mesh.source,
                mesh.normals.size(), mesh.albedo.size(), V);
    for (const std::uint32_t v : vertices)
        SHPRT_CHECK(v < V, invalid_argument, "path trace: vertex {} is out of range ({} vertices)",
                    v, V);
    SHPRT_CHECK(K >= 1 && K <= sh_count(kMaxComputeBands), invalid_argument,
                "path trace: K = {} must be in [1, {}]", K, sh_count(kMaxComputeBands));
    SHPRT_CHECK(!lights.empty(), invalid_argument, "path trace: no light");
    for (const std::vector<double>& light : lights) {
        SHPRT_CHECK(light.size() == 3 * std::size_t(K), invalid_argument,
                    "path trace: a light has {} coefficients; 3·K = {} expected", light.size(),
                    3 * K);
        for (const double l : light)
            SHPRT_CHECK(std::isfinite(l), invalid_argument, "path trace: light coefficient {}", l);
    }
    const int N = options.bounces;
    const std::uint32_t M = options.escape_rays, G = kPathTraceReplicates;
    SHPRT_CHECK(N >= 0 && N <= kMaxPathTraceBounces, invalid_argument,
                "path trace: bounces = {} must be in [0, {}]", N, kMaxPathTraceBounces);
    SHPRT_CHECK(M >= 1 && M <= kMaxPathTraceEscapeRays, invalid_argument,
                "path trace: escape_rays = {} must be in [1, {}]", M, kMaxPathTraceEscapeRays);
    SHPRT_CHECK(options.paths >= 2 * G && options.paths % G == 0 &&
                    std::uint64_t(options.paths / G) * M <= 0xFFFFFFFFull,
                invalid_argument,
                "path trace: paths = {} must be a multiple of {} (at least {}), with paths/{}·M "
                "under 2^32",
                options.paths, G, 2 * G, G);
    SHPRT_CHECK(options.threads >= 0, invalid_argument,
                "path trace: threads = {} must be ≥ 0 (0 = all)", options.threads);

    const std::size_t R = vertices.size(), B = std::size_t(N) + 1, NL = lights.size();
    std::vector<PathTraceIrradiance> out(NL);
    for (PathTraceIrradiance& o : out) {
        o.bounces = N;
        o.receivers = R;
        for (auto* v : {&o.mean, &o.std_error, &o.indirect_std_error, &o.total_std_error})
            v->assign(R * B * 3, 0.0);
    }
    std::atomic<std::uint64_t> rays{0};
    constexpr float kInf = std::numeric_limits<float>::infinity();

    const auto run_receiver = [&](std::size_t r) {
        const std::uint32_t v = vertices[r];
        std::vector<double> y(std::size_t(K), 0.0);
        std::vector<Vec3d> w(M);
        std::vector<Vec3f> dirs(M);
        std::vector<std::uint8_t> occluded(M);
        // x[(l·B + b)·3 + c]: one path's E_b under light l. Per replicate g the sums over its paths
        // of E_b, E_1 + … + E_b and E_0 + … + E_b, at [((l·G + g)·B + b)·3 + c].
        std::vector<double> x(NL * B * 3);
        std::vector<double> sum(NL * G * B * 3, 0.0), ind(sum.size(), 0.0), tot(sum.size(), 0.0);
        std::uint64_t cast_here = 0;
        const std::uint64_t v_high = std::uint64_t(v) << 32;
        // Depth 0's scrambles, per replicate: the light rays', the first direction's.
        std::vector<RngBlock> scramble_light(G), scramble_on(G);
        for (std::uint32_t g = 0; g < G; ++g) {
            scramble_light[g] = rng_block(options.seed, v_high | g, kStreamPathTraceScramble);
            scramble_on[g] = rng_block(options.seed, v_high | g, kStreamPathTraceScramble + 1);
        }
        // A cosine-weighted direction about the frame (t, b, n) for the point (u1, u2).
        const auto direction = [](Vec3d n, Vec3d t, Vec3d b, double u1, double u2) {
            const Vec3d l = cosine_hemisphere_direction(u1, u2);
            return normalize(t * l.x + b * l.y + n * l.z);
        };
        // The point for ray k (k = M: the direction on) at `depth` of path p (replicate g, j-th).
        const auto point = [&](std::uint32_t p, std::uint32_t g, std::uint32_t j, int depth,
                               std::uint32_t k, double& u1, double& u2) {
            if (depth == 0) {
                if (k < M)
                    sobol_point(j * M + k, scramble_light[g], u1, u2);
                else
                    sobol_point(j, scramble_on[g], u1, u2);
                return;
            }
            // Deeper, per path: the light rays are one scrambled (0,2)-net (stratified among
            // themselves, each uniform), the direction on an independent uniform point.
            const std::uint32_t stream = kStreamPathTrace + 256u * std::uint32_t(depth);
            if (k < M) {
                sobol_point(k, rng_block(options.seed, v_high | p, stream), u1, u2);
                return;
            }
            const RngBlock u = rng_block(options.seed, v_high | p, stream + 1);
            u1 = to_unit_double(u.v[0], u.v[1]);
            u2 = to_unit_double(u.v[2], u.v[3]);
        };
        for (std::uint32_t p = 0; p < options.paths; ++p) {
            const std::uint32_t g = p % G, j = p / G;
            std::fill(x.begin(), x.end(), 0.0);
            Vec3f origin = offset_ray_origin(mesh.positions[v], mesh.normals[v]);
            Vec3d n = normalize(cast<double>(mesh.normals[v]));
            Vec3d throughput{1, 1, 1};
            for (int depth = 0; depth <= N; ++depth) {
                Vec3d t, b;
                orthonormal_frame(n, t, b);
                double u1, u2;
                // Next event: the light reaching this point, E ≈ π/M Σ L(w_k)·V(w_k).
                for (std::uint32_t k = 0; k < M; ++k) {
                    point(p, g, j, depth, k, u1, u2);
                    w[k] = direction(n, t, b, u1, u2);
                    dirs[k] = cast<float>(w[k]);
                }
                tracer.occluded(origin, dirs.data(), int(M), 0.0f, kInf, occluded.data());
                cast_here += M;
                for (std::uint32_t k = 0; k < M; ++k) {
                    if (occluded[k]) continue;
                    sh_eval_k<double>(K, w[k].x, w[k].y, w[k].z, y.data());
                    for (std::size_t l = 0; l < NL; ++l)
                        for (int c = 0; c < 3; ++c) {
                            double L = 0;
                            const double* coeffs = lights[l].data() + std::size_t(c * K);
                            for (int i = 0; i < K; ++i) L += coeffs[i] * y[std::size_t(i)];
                            x[(l * B + std::size_t(depth)) * 3 + std::size_t(c)] +=
                                throughput[c] * L * (kPi / M);
                        }
                }
                if (depth == N) break;
                // On: one more cosine-weighted direction; its escape was counted above.
                point(p, g, j, depth, M, u1, u2);
                const Vec3d wc = direction(n, t, b, u1, u2);
                const Vec3f wf = cast<float>(wc);
                const Hit h = tracer.intersect(origin, wf, 0.0f, kInf);
                ++cast_here;
                if (!h.hit) break;
                const auto& tri = mesh.triangles[h.triangle];
                const double bary[3] = {1.0 - double(h.u) - double(h.v), double(h.u), double(h.v)};
                Vec3d ph{0, 0, 0}, rho{0, 0, 0};
                for (int k = 0; k < 3; ++k) {
                    ph += cast<double>(mesh.positions[tri[k]]) * bary[k];
                    rho += cast<double>(mesh.albedo[tri[k]]) * bary[k];
                }
                const Vec3d p0 = cast<double>(mesh.positions[tri[0]]);
                const Vec3d face = cross(cast<double>(mesh.positions[tri[1]]) - p0,
                                         cast<double>(mesh.positions[tri[2]]) - p0);
                // Two-sided: the side the ray arrives on is the side that reflects.
                n = normalize(dot(face, wc) > 0 ? -face : face);
                throughput = {throughput.x * rho.x, throughput.y * rho.y, throughput.z * rho.z};
                if (throughput.x == 0 && throughput.y == 0 && throughput.z == 0) break;
                origin = offset_ray_origin(cast<float>(ph), cast<float>(n));
            }
            for (std::size_t l = 0; l < NL; ++l)
                for (std::size_t c = 0; c < 3; ++c) {
                    double indirect = 0, total = 0;
                    for (std::size_t bb = 0; bb < B; ++bb) {
                        const double xb = x[(l * B + bb) * 3 + c];
                        if (bb > 0) indirect += xb;
                        total += xb;
                        const std::size_t i = ((l * G + g) * B + bb) * 3 + c;
                        sum[i] += xb;
                        ind[i] += indirect;
                        tot[i] += total;
                    }
                }
        }
        // Mean and standard error from the replicates' means (each of paths/G paths).
        const double per_replicate = double(options.paths / G);
        const auto mean_and_error = [&](const std::vector<double>& s, std::size_t l, std::size_t bb,
                                        std::size_t c, double& mean) {
            const auto replicate_mean = [&](std::uint32_t g) {
                return s[((l * G + g) * B + bb) * 3 + c] / per_replicate;
            };
            double m = 0, var = 0;
            for (std::uint32_t g = 0; g < G; ++g) m += replicate_mean(g);
            mean = m / G;
            for (std::uint32_t g = 0; g < G; ++g)
                var += (replicate_mean(g) - mean) * (replicate_mean(g) - mean);
            return std::sqrt(var / (G * (G - 1.0)));
        };
        for (std::size_t l = 0; l < NL; ++l)
            for (std::size_t c = 0; c < 3; ++c)
                for (std::size_t bb = 0; bb < B; ++bb) {
                    PathTraceIrradiance& o = out[l];
                    const std::size_t i = o.index(r, int(bb), int(c));
                    double unused;
                    o.std_error[i] = mean_and_error(sum, l, bb, c, o.mean[i]);
                    o.indirect_std_error[i] = bb > 0 ? mean_and_error(ind, l, bb, c, unused) : 0;
                    o.total_std_error[i] = mean_and_error(tot, l, bb, c, unused);
                }
        rays.fetch_add(cast_here, std::memory_order_relaxed);
    };

    for_vertices(R, 1, options.threads, options.progress, "path trace",
                 [&](std::size_t first, std::size_t last) {
                     for (std::size_t r = first; r != last; ++r) run_receiver(r);
                 });
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    for (PathTraceIrradiance& o : out) {
        o.rays_cast = rays.load();
        o.seconds = seconds;
    }
    return out;
}

PathTraceIrradiance path_trace_irradiance(const Mesh& mesh, std::span<const std::uint32_t> vertices,
                                          int K, std::span<const double> light,
                                          const PathTraceOptions& options, const Tracer& tracer) {
    const std::vector<double> one[1] = {std::vector<double>(light.begin(), light.end())};
    return std::move(path_trace_irradiance(mesh, vertices, K, one, options, tracer).front());
}

}  // namespace shprt
