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
#pragma once

#include "shprt/core/progress.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstdint>
#include <functional>
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
