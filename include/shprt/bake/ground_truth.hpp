// Ground truth for diffuse transfer without spherical harmonics: per vertex, the irradiance
//
//     E(v) = ∫_{S²} L(w) · V(p_v, w) · max(0, n_v·w) dω                  (RGB, per channel)
//
// under a distant light L, integrated directly by Monte Carlo with many samples, so that the SH
// approximation Σ_i c_T^i c_L^i of a bake (bake.hpp) can be judged against the thing it
// approximates. V, n, the ray origin (offset_ray_origin(p, n), tnear 0, tfar ∞) and the clamped
// cosine are exactly those of bake(); only the SH projection is missing. For unshadowed transfer
// V = 1.
//
// The light is split into a smooth sky and constant-radiance discs (a sun of small angular
// radius), because a small disc is invisible to hemisphere sampling: a 2° sun covers 1/3300 of
// the hemisphere, so most vertices would never see a sample in it. Each part gets the sampling
// that makes its estimator converge:
//   * sky:   cosine-weighted hemisphere directions about n (pdf cos θ / π), so
//            E_sky ≈ π/N · Σ_j L_sky(w_j) · V(w_j);
//   * disc:  directions uniform in the disc's cone of solid angle Ω = 2π(1 − cos r), so
//            E_disc ≈ Ω/N · Σ_j L_disc · V(w_j) · max(0, n·w_j).
// The N points of each part are an Owen-scrambled Sobol (0,2)-sequence (sampler.hpp), scrambled
// per vertex and per part by Philox(seed, vertex, stream): low-discrepancy within a vertex,
// independent between vertices. The integrand is smooth except at visibility edges, so the error
// falls roughly as N^-3/4 there and faster elsewhere; use powers of two for N.
//
// Determinism: every vertex's value depends only on (mesh, light, options.seed, sample counts),
// never on the thread count or the order in which vertices are computed.
//
// Interreflected ground truth (path_trace_irradiance, below): the irradiance per bounce,
//
//     E_0(v) as above,   E_b(v) = ∫ max(0, n_v·w) · ρ(h)/π · E_{b−1}(h) dω    (h = h(p_v, w)),
//
// estimated by a path tracer that shades like a renderer and shares nothing with the bake's
// discretisation (bake/interreflect.hpp reads E_{b−1} from the hit triangle's vertices):
//   * E_{b−1}(h) is estimated AT the hit point h, by rays leaving h itself; ρ(h) is the vertex
//     albedo interpolated with the hit's barycentrics;
//   * surfaces are two-sided: at h the normal is the triangle's geometric normal turned toward
//     the arriving ray, and the rays leaving h start at offset_ray_origin(h, that normal), so a
//     back face reflects like a front one and light never passes through a surface;
//   * the receiver's own rays start at offset_ray_origin(p_v, n_v) about its vertex normal, as
//     the bake's do.
// Estimator: at each point of a path (the receiver, then each hit) M cosine-weighted rays look
// for the light ("next event" for a distant light): those that escape add throughput·π/M·Σ L(w_j)
// to E_b, b the point's depth; the path then continues along one more cosine-weighted direction,
// whose own escape adds nothing (the M rays counted it), and the throughput is multiplied by ρ(h)
// at the hit (with pdf cos/π the cosine and 1/π cancel). Fixed depth N, no Russian roulette.
// Randomised quasi-Monte Carlo (Owen 1997; L'Ecuyer & Lemieux 2002): the paths are dealt into
// kPathTraceReplicates independent replicates; within one, the receiver's light rays and the
// paths' first directions are Owen-scrambled Sobol points (as above). Deeper, each path's M light
// rays at a point are one scrambled Sobol net of their own and the direction on is an independent
// Philox point: every point is uniform and independent of what decided where the path is, so each
// replicate's mean is unbiased; the replicates are independent, so the standard error is the
// spread of the replicates' means: honest, though itself known to about ±20 %.
#pragma once

#include "shprt/core/progress.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace shprt {

class Tracer;

// A disc of constant radiance around a direction (e.g. a sun), added on top of the sky.
struct GroundTruthDisc {
    Vec3d direction{0, 1, 0};  // toward the disc's centre; any non-zero length (normalised)
    double radius_deg = 2.0;   // angular radius, in (0, 90]
    Vec3d radiance{1, 1, 1};   // RGB radiance inside the disc, ≥ 0
};

// A distant light for the ground truth: L(w) = sky(w) + Σ_discs radiance·[w inside the disc].
// `sky` takes a unit world vector (+Y up, pointing from the scene toward the source) and must not
// contain the discs again; an empty function means a black sky.
struct GroundTruthLight {
    std::function<Vec3d(Vec3d)> sky;
    std::vector<GroundTruthDisc> discs;
};

struct GroundTruthOptions {
    TransferKind transfer = TransferKind::shadowed;
    std::uint32_t sky_samples = 4096;   // N per vertex for the sky (skipped if the sky is empty)
    std::uint32_t disc_samples = 1024;  // N per vertex for each disc
    std::uint64_t seed = 1;
    int threads = 0;  // 0 = all hardware threads
    // Called with ProgressInfo{"ground truth", vertices done, vertex count, "vertices"} from the
    // calling thread, a few times a second and once at the end. Returning false cancels:
    // ground_truth_irradiance then throws Error(cancelled).
    ProgressFn progress;
};

// Philox streams of the ground truth's scrambles (distinct from the samplers' kStream*).
inline constexpr std::uint32_t kStreamGroundTruthSky = 0x47540001u;
inline constexpr std::uint32_t kStreamGroundTruthDisc = 0x47540100u;  // + disc index

struct GroundTruth {
    std::vector<Vec3d> irradiance;      // E per vertex (input order), RGB: sky plus every disc
    std::vector<Vec3d> sky_irradiance;  // the sky's part alone
    // Per disc d and vertex v, disc_visibility[d·V + v] = the disc's irradiance over what it
    // would be with V ≡ 1 (same samples): 1 = fully lit, 0 = fully shadowed, in between in the
    // penumbra. −1 where the whole disc is below the vertex's horizon (no irradiance either way).
    std::vector<float> disc_visibility;
    std::uint64_t rays_cast = 0;  // rays traced (shadowed transfer); below-horizon ones are not
    double seconds = 0;           // wall time, tracer build included
};

// Integrates E for every vertex of `mesh` (see the top of this file), building an Embree tracer.
// CPU, TBB over vertices. Throws Error(invalid_argument) for an empty mesh, a normal count
// that differs from the vertex count, a disc with a zero direction, a radius outside (0, 90] or a
// negative/non-finite radiance, zero sample counts (for a sky that is present, and for any disc),
// or a sky that returns a negative or non-finite value where it is seen (it is evaluated only for
// unoccluded directions); Error(cancelled) when progress returns false.
GroundTruth ground_truth_irradiance(const Mesh& mesh, const GroundTruthLight& light,
                                    const GroundTruthOptions& options);

// The same with a caller-owned tracer built over `mesh`.
GroundTruth ground_truth_irradiance(const Mesh& mesh, const GroundTruthLight& light,
                                    const GroundTruthOptions& options, const Tracer& tracer);

// ---- Interreflected ground truth: a path tracer (see the top of this file) ----

inline constexpr int kMaxPathTraceBounces = 64;
inline constexpr std::uint32_t kMaxPathTraceEscapeRays = 255;
inline constexpr std::uint32_t kPathTraceReplicates = 16;

struct PathTraceOptions {
    int bounces = 3;  // N: E_0 .. E_N are estimated, 0 ≤ N ≤ kMaxPathTraceBounces
    // Per receiver: a multiple of kPathTraceReplicates, ≥ 2 of them.
    std::uint32_t paths = 4096;
    std::uint32_t escape_rays = 4;  // M at every path point, 1 ≤ M ≤ kMaxPathTraceEscapeRays
    std::uint64_t seed = 1;
    int threads = 0;  // 0 = all hardware threads
    // Called with ProgressInfo{"path trace", receivers done, receiver count, "vertices"} from the
    // calling thread, a few times a second and once at the end. Returning false cancels:
    // path_trace_irradiance then throws Error(cancelled).
    ProgressFn progress;
};

// The random numbers of path p = kPathTraceReplicates·j + g (replicate g, its j-th path) of
// vertex v. Depth 0: the Sobol points M·j + k (light ray k) and j (the direction on), scrambled by
// Philox(seed, v·2^32 + g, kStreamPathTraceScramble + 0 and + 1). Depth d ≥ 1: the Sobol points
// k < M scrambled by Philox(seed, v·2^32 + p, kStreamPathTrace + 256·d) (light ray k), and the
// uniform point Philox(seed, v·2^32 + p, kStreamPathTrace + 256·d + 1) (the direction on).
// Distinct from the samplers' and the ground truth's streams.
inline constexpr std::uint32_t kStreamPathTrace = 0x50540000u;
inline constexpr std::uint32_t kStreamPathTraceScramble = 0x50550000u;

// One light's estimate. Per receiver r (the position in the `vertices` asked for), bounce
// b ∈ [0, N] and channel c, at index (r·(N+1) + b)·3 + c (index()).
struct PathTraceIrradiance {
    int bounces = 0;  // N
    std::size_t receivers = 0;
    std::vector<double> mean;       // E_b, RGB: the light that arrives after exactly b bounces
    std::vector<double> std_error;  // its standard error
    // The standard errors of the partial sums E_1 + … + E_b (0 at b = 0) and E_0 + … + E_b (a
    // path's bounces are correlated, so these do not follow from std_error).
    std::vector<double> indirect_std_error;
    std::vector<double> total_std_error;
    std::uint64_t rays_cast = 0;  // for all the lights together
    double seconds = 0;           // wall time, all the lights together

    std::size_t index(std::size_t r, int b, int c) const {
        return (r * static_cast<std::size_t>(bounces + 1) + static_cast<std::size_t>(b)) * 3 +
               static_cast<std::size_t>(c);
    }
    // E_first + … + E_last of receiver r, channel c.
    double sum(std::size_t r, int first, int last, int c) const {
        double s = 0;
        for (int b = first; b <= last; ++b) s += mean[index(r, b, c)];
        return s;
    }
};

// Path-traces E_0 .. E_N (RGB) at the given vertices of `mesh` under each distant light
// L_c(w) = Σ_{i<K} lights[l][c·K + i]·y_i(w) (real SH, sh/basis.hpp; a light may be negative in
// places, as band-limited lights are: the estimate is linear in it). The lights share the paths:
// one call for several lights costs what one light does. The albedo is mesh.albedo. `tracer` is
// built over `mesh` (Embree for large scenes, an exact tracer in tests). CPU, TBB over receivers,
// each receiver's paths in order on one thread: a receiver's numbers depend on (mesh, its vertex
// index, lights, options but threads and progress), not on the thread count or the other
// receivers asked for. Throws Error(invalid_argument) for an empty mesh, normal or albedo counts
// that differ from the vertex count, a vertex index out of range, no light, K outside
// [1, sh_count(kMaxComputeBands)], a light of other than 3K coefficients or a non-finite one, or
// options outside their ranges; Error(cancelled) when progress returns false.
std::vector<PathTraceIrradiance> path_trace_irradiance(const Mesh& mesh,
                                                       std::span<const std::uint32_t> vertices,
                                                       int K,
                                                       std::span<const std::vector<double>> lights,
                                                       const PathTraceOptions& options,
                                                       const Tracer& tracer);

// One light.
PathTraceIrradiance path_trace_irradiance(const Mesh& mesh, std::span<const std::uint32_t> vertices,
                                          int K, std::span<const double> light,
                                          const PathTraceOptions& options, const Tracer& tracer);

// Building blocks, exposed for tests.
// Cosine-weighted direction on the hemisphere about +Z for (u1, u2) ∈ [0,1)²: Shirley–Chiu's
// concentric map to the unit disc, lifted to the hemisphere (Malley's method); pdf cos θ / π.
Vec3d cosine_hemisphere_direction(double u1, double u2);
// Direction uniform in the cone of half-angle acos(cos_max) about +Z: cos θ = 1 − u1·(1 −
// cos_max), φ = 2π·u2; pdf 1 / (2π(1 − cos_max)).
Vec3d uniform_cone_direction(double u1, double u2, double cos_max);
// A right-handed orthonormal frame (t, b, n) for unit n (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited"): local (x, y, z) maps to x·t + y·b + z·n.
void orthonormal_frame(Vec3d n, Vec3d& t, Vec3d& b);

}  // namespace shprt
