// The precompute of diffuse PRT (Sloan, Kautz & Snyder 2002), run the way the paper describes and
// as fast as this machine allows:
//
//   * one direction set {w_s, weight_s}, s = 0..S-1, shared by every vertex;
//   * the basis table Y[S×K], Y[s][i] = y_i(w_s), computed once;
//   * per vertex v with position p and unit normal n, the transfer samples
//         W[v][s] = V(p, w_s) · max(0, n·w_s) · weight_s        (shadowed)
//         W[v][s] =              max(0, n·w_s) · weight_s        (unshadowed)
//     where rays below the horizon (n·w_s ≤ 0) are not cast, the others are cast in one stream
//     call per vertex from origin offset_ray_origin(p, n) with tnear 0 and tfar ∞;
//   * the projection as a matrix product over chunks of vertices, C[chunk×K] = W[chunk×S]·Y[S×K].
//
// The result is one channel of K coefficients per receiver: row[v][i] = Σ_s W[v][s]·y_i(w_s), the
// SH coefficients (flat index i, paper convention, see sh/basis.hpp) of the transfer function T_v.
// Under distant light with SH coefficients l_i, Σ_i coeffs[v*K+i]·l_i is the irradiance at v (the
// Lambertian 1/π and the albedo are applied when shading, see DESIGN.md "Radiometry").
//
// Memory: O(V·K) for the result, plus the BVH, plus O(chunk·S) per thread; rays are generated on
// the fly and a V×S buffer never exists. BakeStats::peak_bytes_host states the bake's peak:
// coefficients, basis table, direction arrays, the per-thread W and ray buffers, and the
// tracer's acceleration structure (Tracer::memory_bytes: Embree's peak allocation through its
// memory monitor). The mesh, which the caller owns, is not counted.
//
// The three seams. A bake takes its *occluders* (the mesh the rays hit), its *receivers* (where
// transfer is computed, and which range of them: receivers.hpp) and a *sink* (where the rows go:
// host memory, a file region, a device buffer; sink.hpp). Per chunk of receivers it runs the
// stages weight → trace → project → sink (src/bake/stages.hpp), the places where closest hits
// for bounces and Yᵀ·diag(w)·Y for glossy matrices plug in.
//
// Determinism: the chunks are a grid over the whole receiver set, cut from receiver 0 every
// chunk_receivers (a count set by the set's size and S only, never by the range baked or the
// thread count), and each chunk's product is one SGEMM on one thread. A row's bits depend on its
// W row, Y, and where it sits in an SGEMM of which height: OpenBLAS's Haswell and Zen kernels
// give a row other last bits at another row of the call or in a call of another height. So a
// range projects each chunk it touches whole (the rows outside it with zero weights) and keeps
// its own rows: the same inputs and seed give bit-identical rows with any number of threads, and
// a sub-range (a shard, a resumed gap) gives exactly the rows of the whole bake (both tested).
// A different chunk_receivers is a different grid, which may change the last bits.
#pragma once

#include "shprt/bake/receivers.hpp"
#include "shprt/core/progress.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/transfer/sink.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace shprt {

class Tracer;
struct EmbreeTracerOptions;
struct BakeJob;

// Largest basis size a bake accepts (32 full bands).
inline constexpr int kMaxBakeCoeffs = sh_count(kMaxComputeBands);
// Largest basis size of a glossy (matrix) bake: 8 bands, K = 64 (a 64×64 matrix per receiver).
inline constexpr int kMaxGlossyCoeffs = sh_count(8);
// Most directions a bake accepts: W[chunk×S] must stay a sensible per-thread buffer.
inline constexpr std::uint32_t kMaxBakeSamples = std::uint32_t(1) << 24;
// BakeOptions::indirect_samples 0 means S / kIndirectSampleShare (chosen by measurement:
// docs/interreflection.md, "Final gather"): S/8 cosine-distributed rays per receiver, as many
// rays as S/4 directions of the sphere have above a horizon.
inline constexpr std::uint32_t kIndirectSampleShare = 8;
// BakeOptions::bounce_coeffs 0 means this many (4 bands), or K when smaller: light that has
// bounced twice or more is carried in its first coefficients only (chosen by measurement:
// docs/interreflection.md, "Coefficients of the bounces").
inline constexpr int kDefaultBounceCoeffs = 16;
// Most worker threads a bake accepts.
inline constexpr int kMaxBakeThreads = 4096;
// Most bounces an interreflected bake accepts (BakeOptions::bounces and max_bounces).
inline constexpr int kMaxBounces = 10000;
// The error-bounded bake (BakeOptions::target_error, docs/sampling.md "Error-bounded bakes"):
// every receiver starts with the first kTargetFirstSamples directions of the nested set (its
// halves give the first estimate) and doubles while its estimated error is over the target, up
// to max_samples (0: kDefaultMaxSamples). A power of two, so that every prefix is a balanced
// Sobol net; 64 because a smaller first prefix can miss a small occluder in both halves and
// stop there (the estimate sees no difference), and a larger one spends more on the open
// receivers that need no more (measured: bench/RESULTS.md, "Error-bounded bakes").
inline constexpr std::uint32_t kTargetFirstSamples = 64;
inline constexpr std::uint32_t kDefaultMaxSamples = 16384;

// The basis size K of a bake when the caller gives neither bands nor K: 16 (4 bands), and 25 (5
// bands: 25×25 matrices) for glossy transfer. The command line and Python both ask here.
int default_coeffs(TransferKind kind);

// Where a bake runs: the CPU, a CUDA GPU, or the GPU when one is usable and else the CPU.
enum class Device { cpu, cuda, automatic };
const char* to_string(Device device);
Device parse_device(const std::string& name);  // "cpu", "cuda", "auto"; throws Error

struct BakeOptions {
    TransferKind transfer = TransferKind::shadowed;
    int K = 16;  // basis size, 1..kMaxBakeCoeffs; need not be a square (default_coeffs)
    std::uint32_t samples = 1024;  // S, 1..kMaxBakeSamples directions (ignored when a
                                   // DirectionSet is given)
    // Sobol (Owen-scrambled): the paper table measured 7× lower error than the paper's uniform
    // set at the same cost (docs/paper_table.md); SamplerKind::uniform is the paper's.
    SamplerKind sampler = SamplerKind::sobol;
    // Where the shared set lives (docs/sampling.md): local (the default: one set in each
    // receiver's tangent frame, cosine-weighted — uniform on the hemisphere for glossy —, every
    // direction traced, the frame's coefficients rotated to world space band by band; the GPU
    // bake rotates on the host, so it cannot write into a device sink) or sphere (the paper's:
    // one set in world space, weights 4π/S, about half of it above a receiver's horizon). A
    // caller's DirectionSet is read in its own frame (DirectionSet::frame), which replaces this;
    // a local one's weights multiply the visibility alone (the cosine, if any, folded in).
    // Interreflected transfer: T_0 uses it; the bounce sources keep the sphere set (their final
    // gather is cosine-distributed already).
    DirectionFrame direction_frame = DirectionFrame::local;
    // A local set only: the open part exactly (docs/sampling.md, "The open part exactly"): each
    // row corrected by its visible fraction times the set's own error on an open receiver, so
    // that an open receiver is exact at any S. Off gives the plain estimator (for comparison:
    // bench_local_directions); not an option of the command line.
    bool open_control = true;
    // The error-bounded bake (docs/sampling.md, "Error-bounded bakes"): 0 = off (every receiver
    // gets `samples`); E in (0, 1]: each receiver gets the smallest nested prefix
    // kTargetFirstSamples·2^k ≤ max_samples whose estimated error (‖ĉ_S − ĉ_{S/2}‖ over the
    // norm of a fully open receiver's transfer) is at most E, and `samples` is not used: the set
    // is max_samples long (what the file records as its samples). Vectors only (unshadowed,
    // shadowed; vertices or texels), a nested sampler (sobol, uniform), the CPU, the bake's own
    // set (no caller's DirectionSet). max_samples: 0 (kDefaultMaxSamples) or a power of two,
    // kTargetFirstSamples to kMaxBakeSamples; only with target_error.
    double target_error = 0;
    std::uint32_t max_samples = 0;
    std::uint64_t seed = 1;
    int threads = 0;  // worker threads, 0..kMaxBakeThreads; 0 = all hardware threads
    // cpu; cuda (the GPU bake; Error(unsupported) with the reason where it cannot run); or
    // automatic (the GPU where one is usable, else the CPU): resolve_device().
    Device device = Device::cpu;
    int device_index = 0;  // the CUDA device (0-based, after CUDA_VISIBLE_DEVICES); ≥ 0
    // Receivers per chunk of the grid (one W[chunk×S] buffer and one SGEMM each); 0 = automatic,
    // from the whole receiver set's size and S only (see "Determinism" above).
    std::size_t chunk_receivers = 0;
    // The GPU bake (Device::cuda): the device bytes it may plan with, at most what is free (0 =
    // 90% of what is free when it starts; the CUDA context and cuBLAS need the rest). Its chunks
    // fit it, and for interreflected transfer so do A's blocks kept on the device for the
    // bounces: the others are copied in per bounce (plan_transport_residency, gpu.hpp).
    std::uint64_t device_memory_budget = 0;
    // Interreflected transfer only (TransferKind::interreflected, bake/interreflect.hpp): the
    // bounces N ≥ 0 (0 = the shadowed transfer in three channels), or with `converge` as many as
    // it takes for the largest relative change of any receiver's transfer to fall under
    // `tolerance` (> 0), at most max_bounces; `two_sided`: a ray that hits a back face sees the
    // radiance of the front (else it brings nothing). The albedo is the occluder mesh's.
    int bounces = 1;
    bool converge = false;
    double tolerance = 1e-4;
    int max_bounces = 1000;
    bool two_sided = false;
    // Interreflected transfer: the rays each receiver casts for the bounces (its final gather),
    // the first ones of the bake's sampler and seed (for Sobol a nested prefix of the bake's set)
    // mapped to the receiver's cosine-weighted hemisphere; the other bounce sources trace the
    // first 1/kInnerSourceShare of them as sphere directions. T_0 keeps all S, the smooth
    // bounces take fewer (docs/interreflection.md). 0 = S / kIndirectSampleShare; at most S.
    std::uint32_t indirect_samples = 0;
    // Interreflected transfer: the bounce sources' cells, at most this many metres a side
    // (bake/bounce_sources.hpp); 0 = the scene's bounding-box diagonal / kDefaultSourceCells;
    // infinity = the mesh's vertices only (the discretisation before the sources had cells).
    float source_spacing = 0;
    // Interreflected transfer: the coefficients that light carries after its second bounce and
    // on (0 = kDefaultBounceCoeffs, capped at K; else 1..K). The first bounce reaches the
    // receivers in all K; the later bounces, smooth in the light's direction and computed from
    // sources that trace few rays, in the first bounce_coeffs (the others get the first bounce
    // alone). Each bounce's product costs in proportion to its coefficients.
    int bounce_coeffs = 0;
    // Interreflected transfer on the CPU: the bytes the whole bake may use (0 = no limit). The
    // transport operator A, whose size is known only once traced, gets what the estimate of the
    // rest (estimate_bake_peak_bytes) leaves; its blocks past that are spilled, as they are
    // built, to a temporary file in `spill_directory` ("" = $TMPDIR, else /tmp) and read back
    // memory-mapped: same bits, BakeStats::operator_bytes_spilled says how much.
    std::uint64_t memory_budget = 0;
    std::string spill_directory;
    // Called with ProgressInfo{"bake", rays done, rays total (estimate), "rays"} ("samples" for
    // unshadowed transfer) from the thread that called bake(), at most ~20 times a second, and
    // once at the end. Returning false stops the bake promptly; bake() then throws
    // Error(cancelled).
    ProgressFn progress;
};

// Why a GPU bake (Device::cuda) refuses the error bound of `options`, as one line, or null: the
// device bakes it for shadowed and unshadowed transfer with a local direction set (it reads each
// receiver's visible rays from its first coefficient); interreflected transfer and the sphere set
// bake it on the CPU. bake() and request_refusal ask here. Device::automatic keeps every
// error-bounded bake on the CPU (the device's has not run on a GPU yet: bench/RESULTS.md).
const char* gpu_target_error_refusal(const BakeOptions& options);

// The error bound as a front end takes it (`shprt bake --target-error E --max-samples N`,
// Python's target_error=, max_samples=), checked with the same limits for both and named as the
// front end spells them with their separator ("--target-error ", "target_error="): E = 0 (off) or
// in (0, 1]; N = 0 (kDefaultMaxSamples) or a power of two kTargetFirstSamples to kMaxBakeSamples,
// and only with E > 0. One-line Error(invalid_argument) otherwise.
void set_error_bound(BakeOptions& options, double target_error, long long max_samples,
                     std::string_view target_name, std::string_view max_name);

// ‖c_open‖, the error-bounded bake's unit: the norm of a fully open receiver's diffuse transfer
// (the clamped cosine about its normal) over the full bands that hold `coeffs` coefficients; it
// depends on the bands only. A receiver's error is ‖ĉ − c‖ / ‖c_open‖ (docs/sampling.md).
double open_transfer_norm(int coeffs);

// The size of the direction set a bake with `options` makes: samples, or with target_error the
// error-bounded bake's max_samples (kDefaultMaxSamples when 0).
std::uint32_t bake_set_size(const BakeOptions& options);

// The one check of bake options, made at the boundary (every bake entry point calls it once):
// Error(invalid_argument) naming the option for K outside 1..kMaxBakeCoeffs (1..kMaxGlossyCoeffs
// for glossy transfer), samples outside
// 1..kMaxBakeSamples, threads outside 0..kMaxBakeThreads, a negative device index, a target
// error outside [0, 1] or max_samples that is not 0 or a power of two kTargetFirstSamples to
// kMaxBakeSamples (or without a target error), a target error with a sampler whose prefixes are
// not nested; Error(unsupported) for a target error with glossy or interreflected transfer.
void validate(const BakeOptions& options);

// The one place a bake's backend is chosen: Device::cpu → cpu; Device::cuda → cuda when
// query_gpu(device_index) finds a usable device, else Error(unsupported) with its one-line reason;
// Device::automatic → cuda when there is one, else cpu. Returns Device::cpu or Device::cuda.
Device resolve_device(Device requested, int device_index = 0);

// The Embree scene a CPU bake of `job` with a set of `samples` directions builds
// (EmbreeTracerOptions::for_rays over the rays of the whole receiver set, not of the job's
// range): every path that builds its own tracer (bake, a resumed bake's gaps, MPI ranks) asks
// this, so that they trace the same scene.
EmbreeTracerOptions bake_tracer_options(const BakeJob& job, const BakeOptions& options,
                                        std::size_t samples);

// What a bake with `options` produces, before it runs: its kind and layout (vertex receivers, one
// channel — three for interreflected —, a vector of K each — a symmetric K×K matrix for glossy
// transfer —, float32), sampler, samples and seed; no stats. A progressive
// display starts from TransferSet::zeros(bake_description(options), V).
TransferInfo bake_description(const BakeOptions& options);

// The direction set a bake with `options` makes when it is given none (BakeJob::directions):
// make_direction_set(sampler, seed, samples) for DirectionFrame::sphere; for local the set of
// make_local_direction_set, cosine-weighted (uniform on the hemisphere for glossy transfer: a
// cosine density would weigh its samples by 1/cos θ, of infinite variance at the horizon).
DirectionSet bake_direction_set(const BakeOptions& options);

// A bake's inputs: the three seams, plus optional caller-made pieces.
struct BakeJob {
    const Mesh* occluders = nullptr;  // the scene the rays hit (its triangles); required
    Receivers receivers;              // where transfer is computed; required (count ≥ 1)
    TransferSink* sink = nullptr;     // where the rows go; required
    // The direction set; nullptr = make_direction_set(options.sampler, options.seed,
    // options.samples). A given set must be non-empty with unit directions; options.samples then
    // becomes its size, options.direction_frame its frame (and options.sampler a label).
    const DirectionSet* directions = nullptr;
    // A tracer built over `occluders` (CPU only); nullptr = the bake builds Embree's.
    const Tracer* tracer = nullptr;
    // Interreflected transfer only: a second sink for the direct part T_0 (the same receivers,
    // one channel of K each: TransferSet::direct), given its rows once the bounces are done;
    // nullptr = not kept.
    TransferSink* direct = nullptr;
    // Transfer probes baked beside the receivers (bake/probe_bake.hpp): the grid's layout in
    // (counts, spacing, origin, K, channels: 3 for interreflected transfer), its matrices and
    // validity filled once the receivers are done, on the CPU (a GPU bake traces them with
    // Embree); nullptr = none.
    ProbeGrid* probes = nullptr;
};

// Glossy transfer (TransferKind::glossy, docs/glossy.md) is the same pipeline with two changes:
// the weight is W[v][s] = V(p, w_s)·[n·w_s > 0]·weight_s (visibility over the hemisphere, no
// cosine: the cosine and the BRDF enter at shading), and the table is the pair-product table
// P[s][(i,j)] = y_i(w_s)·y_j(w_s) for i ≤ j (packed upper triangle, row by row), so that a chunk's
// matrices are again one SGEMM, C[chunk×K(K+1)/2] = W[chunk×S]·P[S×K(K+1)/2] — row v of C is the
// packed upper triangle of M_v = Yᵀ·diag(W[v])·Y, with the same determinism as the diffuse
// product. On the GPU the same two changes: transfer_sample with `hemisphere`, and cuBLAS SGEMM on
// the same table (unverified on hardware so far). K ≤ kMaxGlossyCoeffs; no bounces
// (interreflected glossy transfer is not written).
//
// Bakes diffuse transfer (one channel of K coefficients per receiver, see the top of this file)
// for job.receivers' range into job.sink, on resolve_device(options.device, ...). Returns the
// description of what went to the sink (kind, layout, sampler, S, seed) and BakeStats: the time
// split (bvh, trace, project, total), the rays cast, the peak working memory (not counting the
// sink's own memory) and the device ("cpu: N threads" or the GPU's name).
// CPU backend: TBB workers over chunks, one single-threaded cblas_sgemm per chunk; OpenBLAS's
// thread count is a process-wide setting, set to 1 for the bake and restored afterwards (so do
// not run OpenBLAS work of your own concurrently with a bake and expect its thread count).
// Throws Error(invalid_argument) for bad options (validate), an occluder mesh without triangles,
// receivers without normals or with an empty range, more than 2^32 − 1 receivers, a missing sink;
// Error(unsupported) for Device::cuda where no GPU bake can run, for a DeviceSink on the CPU and
// for a tracer on the GPU; Error(cancelled) when the progress callback returns false (the sink's
// finish() is then not called); what the sink throws.
TransferInfo bake(const BakeJob& job, const BakeOptions& options);

// Convenience: every vertex of `mesh` as receivers and occluders, into host memory.
TransferSet bake(const Mesh& mesh, const BakeOptions& options);
// The rows of `receivers`' range (e.g. a shard: vertex_receivers(mesh).range(first, count)),
// with `mesh` as occluders, into host memory: the result's coeffs hold receivers.count rows.
TransferSet bake(const Mesh& mesh, const Receivers& receivers, const BakeOptions& options);
// The same with an explicit direction set (e.g. an exact quadrature set in tests).
TransferSet bake(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions);
// The same with a caller-owned tracer built over `mesh` (the BVH time is then 0). CPU only.
TransferSet bake_with_tracer(const Mesh& mesh, const BakeOptions& options,
                             const DirectionSet& directions, const Tracer& tracer);

// The slow, obvious reference for tests: per vertex and per direction, in double precision, one
// ray per occluded() call, the basis evaluated per sample (no table, no GEMM), single-threaded.
// Same definition of W as bake(); progress, threads and chunking are ignored.
TransferSet bake_reference(const Mesh& mesh, const BakeOptions& options,
                           const DirectionSet& directions, const Tracer& tracer);

// A bake's peak host memory, estimated before it runs (no BVH is built): the BVH at
// kBvhBytesPerTriangle per triangle (Embree's measured peak on the builtin scenes, rounded up, and
// the blocker cones' 36 bytes of corners: tracer.hpp),
// the basis and direction tables, every worker's W[chunk×S], ray and row buffers, and — when
// `rows_in_memory` (a HostSink: the rows of every receiver) — the rows. Every kind is counted by
// one rule from its layout (bake_description(options).layout): floats_per_receiver() floats per
// row and floats_per_channel() columns in the product's table and buffers (K for vectors,
// K(K+1)/2 for glossy's packed matrices, whose table is built from the K-column one);
// interreflected transfer adds its work arrays over the receivers and its `bounce_sources`
// (bounce_source_count; 0: as many as receivers), each 3K floats (its transport operator, which
// depends on what the rays hit, is not estimated: it is counted against BakeOptions::memory_budget
// as it is built, and what does not fit is spilled to a mapped file). Used to refuse a bake that
// cannot fit (`shprt bake --max-memory`, MemAvailable) before any work.
inline constexpr std::uint64_t kBvhBytesPerTriangle = 200;
std::uint64_t estimate_bake_peak_bytes(std::size_t triangles, std::size_t receivers,
                                       const BakeOptions& options, bool rows_in_memory,
                                       std::size_t bounce_sources = 0);

// The automatic chunk size for `receivers` receivers and S directions: about 1 MiB of W per
// thread, at least 64 chunks when the count allows, rounded up to a multiple of 16 (the SGEMM
// kernel's row blocking) when at least 16, at most 1024. Depends on its arguments only. Exposed
// for tests and benchmarks.
std::size_t auto_chunk_receivers(std::size_t receivers, std::size_t samples);

}  // namespace shprt
