// The bake of transfer probes (transfer/probes.hpp, docs/probes.md): a grid of points in the
// scene's volume, baked beside the bake's receivers (BakeJob::probes), each with a K×K matrix per
// channel from the distant light's SH to the SH projection of the radiance arriving at the point.
//
// Estimator. The bake's own direction set {w_s, weight_s} on the whole sphere (its sampler, seed
// and S; a local bake takes the sphere set of its sampler), the closest hit h_s of the ray from
// the probe p along w_s (tnear 0: a probe has no surface to leave), and V_s = 1 when it escapes:
//
//     M_c[i][j] = Σ_s weight_s · y_i(w_s) · [ V_s · y_j(w_s) + (1 − V_s) · B_c,j(h_s) ]
//
// The first part (shadowed, unshadowed with V ≡ 1, glossy: the light is the same) is symmetric and
// is the glossy bake's product, one SGEMM per chunk of probes on the pair-product table
// (stages.hpp: pair_product_table, project_rows). The second is interreflected transfer's only
// (channels = 3): B_c(h) = ρ_c(h)/π · E_c(h), the light a diffuse hit point sends, with E(h) the
// irradiance transfer of the hit's bounce sources (bounce_sources.hpp) interpolated over the
// corners of the hit's cell exactly as the transport operator's entries do
// (transport_hit_entries), so no vertex interpolation carries light across geometry; E is
// T_0 + … + T_{N−1} at the sources (a probe's light has bounced at most N times, as a
// receiver's). A back face sends nothing unless two-sided (its back copies' light).
//
// Invalid probes. A probe inside or under geometry sees the backs of the surfaces around it: when
// more than kProbeBackShare of its rays that hit something hit a back face (one-sided surfaces,
// counter-clockwise = front), the probe is invalid and its matrices are zero.
//
// Determinism: probes are projected in fixed chunks of kProbeChunk from probe 0, one
// single-threaded SGEMM each; the bounced part per probe in a fixed order: the same bits for any
// thread count.
#pragma once

#include "shprt/bake/transport_build.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/transfer/probes.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace shprt {

struct BakeOptions;
struct DirectionSet;
struct Mesh;
class Tracer;

// The spacing `--probes auto` takes: probes at most half a metre apart (builtin:room's bounds,
// 6.4 × 3 × 5.4 m: 13 × 6 × 11 probes), grown until the grid holds at most kMaxAutoProbes.
inline constexpr float kDefaultProbeSpacing = 0.5f;
inline constexpr std::size_t kMaxAutoProbes = std::size_t(1) << 15;
// Most bands (K = bands²) of a probe's matrices (kMaxProbeSide and kMaxProbes bound the grid:
// transfer/probes.hpp).
inline constexpr int kMaxProbeBands = 8;
inline constexpr int kDefaultProbeBands = 3;
// A probe is invalid when more than this share of its rays that hit a surface hit a back face.
inline constexpr float kProbeBackShare = 0.5f;
// Probes per projection chunk (one SGEMM each).
inline constexpr std::size_t kProbeChunk = 64;

// Where the probes go, as `shprt bake --probes --probe-box --probe-bands` and Python's probes=,
// probe_box=, probe_bands= spell it.
struct ProbeSpec {
    std::array<int, 3> counts{0, 0, 0};       // 0, 0, 0: automatic (from the box and the spacing)
    float spacing = 0;                        // metres; 0: automatic (kDefaultProbeSpacing, or the
                                              // box's size over the counts when counts are given)
    std::optional<std::array<Vec3f, 2>> box;  // lo, hi; none: the scene's bounds
    int bands = kDefaultProbeBands;
};

// The spec of `probes` ("auto", "auto:SPACING", "NX,NY,NZ" or "NX,NY,NZ:SPACING"), `box`
// ("X0,Y0,Z0,X1,Y1,Z1" or empty) and `bands` (1 to kMaxProbeBands, none: 3), or nothing when
// `probes` is empty. One-line Error(invalid_argument) naming the option for a bad value, or for
// --probe-box or --probe-bands without --probes.
std::optional<ProbeSpec> parse_probes(const std::string& probes, const std::string& box,
                                      std::optional<long long> bands);

// The grid `spec` lays over `mesh` (its bounds, or the spec's box): counts, spacing and origin,
// K = bands², channels (3 for interreflected transfer, else 1); no matrices yet. Counts with a
// spacing: that grid, centred on the box. Otherwise the probes sit at the centres of n equal cells
// that fill the box, never on its faces (automatic: n = ⌈extent / spacing⌉ per axis, at least 1,
// so the cells are at most the spacing — kDefaultProbeSpacing unless given).
// Throws Error(invalid_argument) for more than kMaxProbes probes.
ProbeGrid probe_grid_layout(const ProbeSpec& spec, const Mesh& mesh, bool interreflected);

// What a bake's probes need of an interreflected bake: the occluders as the transport operator
// reads them (with the bounce sources' grid) and, per source, E = T_0 + … + T_{N−1} in 3
// channels of `K` floats (`columns` of them non-zero past T_0's, the later bounces' coefficients).
struct ProbeBounce {
    TransportMeshView view;
    const float* light = nullptr;  // sources · 3 · K
    int K = 0;
    bool two_sided = false;
};

// Bakes `grid`'s matrices and validity (its layout given: counts, spacing, origin, K ≤
// sh_count(kMaxProbeBands), channels) against the occluders with the direction set `directions`
// (weights summing to 4π over the sphere) and `tracer` (built over `occluders`; null for
// unshadowed transfer: V ≡ 1, every probe valid). With `bounce`, channels must be 3 and the
// bounced part is added. Progress: ProgressInfo{"probes", probes done, probes, "probes"} through
// options.progress; Error(cancelled) when it returns false. Returns the rays cast.
std::uint64_t bake_probe_grid(ProbeGrid& grid, const Mesh& occluders, const BakeOptions& options,
                              const DirectionSet& directions, const Tracer* tracer,
                              const ProbeBounce* bounce = nullptr);

}  // namespace shprt
