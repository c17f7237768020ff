// A sun kept out of the SH sum (`shprt shade --sun`, docs/lights.md "A sun kept out of the SH
// sum"): its direct light traced at every receiver, sharp; its bounced light and the sky through
// the baked transfer. The CPU twin of the renderer's shadow-mapped sun (issue 36), for diffuse
// receivers, per vertex and per texel.
//
// For a receiver with position p, unit normal n, albedo ρ, transfer T (the file's whole transfer)
// and, for an interreflected file, its direct part T_0 (TransferSet::direct), under a sky c_sky
// (the SH sum of the --light specs) and a sun S of radiance L, solid angle Ω and SH projection
// c_S (light/sun.hpp, prepare_sun):
//
//   E_sun,direct   = L · Ω/N · Σ_j V(p, d_j) · max(0, n·d_j)     traced, d_j = sun_disc_directions
//   E_sun,bounced  = Σ_i (T − T_0)_c^i · c_S,c^i                 interreflected files only
//   E_sky          = Σ_i T_c^i · c_sky,c^i                        (shade/shade.hpp)
//   E = E_sun,direct + E_sun,bounced + E_sky,     L_out = ρ/π · E
//
// Why: T_0·c_S is the sun's direct light through K coefficients, a blur of the disc tens of
// degrees wide (docs/lights.md); the trace replaces exactly that term and nothing else, so the sum
// is the all-SH result T·(c_sky + c_S) with T_0·c_S replaced by its traced limit (tested: the two
// agree as the bands grow). A file without a direct part (shadowed, unshadowed, texels, or an
// interreflected file read with --direct) gives the sun's direct light only.
//
// Visibility: Embree over the file's own mesh, rays from offset_ray_origin(p, n) (trace/tracer.hpp)
// toward every disc direction above the receiver's horizon. N = 1 traces the centre direction
// only: the hard shadow of a point sun with the disc's irradiance L·Ω. Soft shadows come from the
// disc's N directions, one set shared by every receiver (seeded, stratified), so the penumbra has
// N + 1 levels and the result is the same bits for any thread count.
#pragma once

#include "shprt/light/light_setup.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstdint>
#include <vector>

namespace shprt {

class Tracer;

inline constexpr int kDefaultSunSamples = 64;  // 8 × 8 directions on the disc
inline constexpr std::uint64_t kDefaultSunSeed = 0x53554eu;

struct SunShadeOptions {
    int disc_samples = kDefaultSunSamples;  // N: a square in [1, kMaxSunSamples]
    std::uint64_t seed = kDefaultSunSeed;   // of the disc's jitter
};

// E_sun,direct above for points with unit normals (positions.size() == normals.size()), occluded
// by what `tracer` holds; in parallel, the same bits for any thread count. Throws
// Error(invalid_argument) for a bad sun or sample count (sun_disc_directions) or mismatched sizes.
std::vector<Vec3f> sun_direct_irradiance(const Tracer& tracer, const std::vector<Vec3f>& positions,
                                         const std::vector<Vec3f>& normals, const Sun& sun,
                                         const SunShadeOptions& options);

struct SunShadeResult : ShadeResult {  // irradiance E and radiance ρ/π·E, the whole sum above
    std::vector<Vec3f> sun_direct;     // E_sun,direct alone, per receiver
    bool bounced = false;              // E_sun,bounced is in (the transfer has a direct part)
};

// The sum above for every receiver of `transfer` (vertices, or texels in atlas order as
// shade_texels), occluders = `mesh`'s triangles (Embree). `sky` and `sun.sh` are shaded with the
// first K' coefficients (options.K_used, effective_basis_size). Vector transfer: diffuse only,
// Error(unsupported) for options.k < 1 (the paper's glossy term is a product of two sums over
// the light, not linear in it: the sun cannot be taken out of it; a `sun:` light projects the
// sun into SH for it). Throws what shade_receivers throws.
SunShadeResult shade_with_sun(const Mesh& mesh, const TransferSet& transfer, const ShLight& sky,
                              const PreparedSun& sun, const ShadeOptions& options,
                              const SunShadeOptions& sun_options);

// Glossy transfer matrices (shade/glossy.hpp) under a sky and a sun kept out of the SH sum: the
// sky through M (shade_glossy), and the sun's direct light traced over its disc with the BRDF's
// exact lobe, not its zonal fit — so the highlight is as sharp as the BRDF, and shadowed:
//   L_c += ρ_d,c/π · E_sun,c + ρ_s,c · L_sun,c · Ω/N · Σ_j f(r · d_j) · V(p, d_j)   (n·d_j > 0)
// with f the vertex's normalised lobe profile (brdf_profile) about its reflection direction r
// and ρ_d, ρ_s as shade_glossy's. Glossy files have no direct part: no bounced sun. Vertices
// only (Error(unsupported) for texel matrices). Throws what shade_glossy throws.
SunShadeResult shade_glossy_with_sun(const Mesh& mesh, const TransferSet& transfer,
                                     const ShLight& sky, const PreparedSun& sun,
                                     const GlossyShadeOptions& options,
                                     const SunShadeOptions& sun_options);

}  // namespace shprt
