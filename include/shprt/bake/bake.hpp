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
// The result is a TransferSet with one channel: coeffs[v*K + i] = Σ_s W[v][s]·y_i(w_s), the SH
// coefficients (flat index i, paper convention, see sh/basis.hpp) of the transfer function T_v.
// Under distant light with SH coefficients l_i, Σ_i coeffs[v*K+i]·l_i is the irradiance at v (the
// Lambertian 1/π and the albedo are applied when shading, see DESIGN.md "Radiometry").
//
// Memory: O(V·K) for the result, plus the BVH, plus O(chunk·S) per thread; rays are generated on
// the fly and a V×S buffer never exists. BakeStats::peak_bytes_host states the bake's peak:
// coefficients, basis table, direction arrays, the per-thread W and ray buffers, and the
// tracer's acceleration structure (Tracer::memory_bytes: Embree's peak allocation through its
// memory monitor). The mesh, which the caller owns, is not counted.
//
// Determinism: the chunk partition depends only on (V, S, chunk_vertices), never on the thread
// count, and each chunk's product is computed independently by one thread, so the same inputs and
// seed give bit-identical coefficients with any number of threads.
#pragma once

#include "shprt/bake/transfer.hpp"
#include "shprt/core/progress.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/sampler.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>

namespace shprt {

class Tracer;

// Largest basis size a bake accepts (32 full bands).
inline constexpr int kMaxBakeCoeffs = 1024;

struct BakeOptions {
    TransferKind transfer = TransferKind::shadowed;
    int K = 16;                    // basis size, 1..kMaxBakeCoeffs; need not be a square
    std::uint32_t samples = 1024;  // S ≥ 1 directions (ignored when a DirectionSet is passed)
    SamplerKind sampler = SamplerKind::uniform;  // (ignored when a DirectionSet is passed)
    std::uint64_t seed = 1;
    int threads = 0;  // worker threads; 0 = all hardware threads
    // cpu; cuda (the GPU bake; Error(unsupported) with the reason where it cannot run); or
    // automatic (the GPU where one is usable, else the CPU). See choose_backend in bake.cpp.
    Device device = Device::cpu;
    // Vertices per chunk (one W[chunk×S] buffer and one SGEMM each); 0 = automatic, from V and S
    // only. The partition never depends on the thread count.
    std::size_t chunk_vertices = 0;
    // Called with ProgressInfo{"bake", rays done, rays total (estimate), "rays"} from the thread
    // that called bake(), at most ~20 times a second, and once at the end. Returning false stops
    // the bake promptly; bake() then throws Error(cancelled).
    ProgressFn progress;
    // Optional: called once per finished chunk with its K-coefficient rows (count × K floats,
    // vertex-major) for progressive display. Called from worker threads, one call at a time (the
    // bake serialises the calls); the pointer is valid only during the call. Keep it cheap.
    std::function<void(std::size_t first_vertex, std::size_t count, const float* coeffs)> on_chunk;
};

// Bakes per-vertex transfer of `mesh` with the direction set
// make_direction_set(options.sampler, options.seed, options.samples), on options.device.
// Builds the tracer (Embree) itself; BakeStats records the time split (bvh, trace, project,
// total), the rays cast, the peak working memory and "cpu: N threads".
// CPU backend: TBB workers over chunks, one single-threaded cblas_sgemm per chunk; OpenBLAS's
// thread count is a process-wide setting, set to 1 for the bake and restored afterwards (so do
// not run OpenBLAS work of your own concurrently with a bake and expect its thread count).
// Throws Error(invalid_argument) for K outside 1..1024, samples = 0, an empty mesh or a normal
// count that differs from the vertex count; Error(unsupported) for Device::cuda where no GPU
// bake can run (no CUDA in the build, or no usable device); Error(cancelled) when the progress
// callback returns false.
TransferSet bake(const Mesh& mesh, const BakeOptions& options);

// As above with an explicit direction set (e.g. an exact quadrature set in tests); options.samples
// and options.sampler are ignored, and the result records sampler/samples from the options only
// as labels (samples = directions.size()). The set must be non-empty with unit directions.
TransferSet bake(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions);

// As above with a caller-owned tracer built over `mesh` (the BVH time is then 0). CPU only.
TransferSet bake_with_tracer(const Mesh& mesh, const BakeOptions& options,
                             const DirectionSet& directions, const Tracer& tracer);

// The slow, obvious reference for tests: per vertex and per direction, in double precision, one
// ray per occluded() call, the basis evaluated per sample (no table, no GEMM), single-threaded.
// Same definition of W as bake(); progress, on_chunk, threads and chunking are ignored.
TransferSet bake_reference(const Mesh& mesh, const BakeOptions& options,
                           const DirectionSet& directions, const Tracer& tracer);

// The automatic chunk size for V vertices and S directions: about 1 MiB of W per thread, at least
// 64 chunks when V allows, rounded up to a multiple of 16 (the SGEMM kernel's row blocking) when
// at least 16, at most 1024. Depends on V and S only. Exposed for tests and benchmarks.
std::size_t auto_chunk_vertices(std::size_t vertex_count, std::size_t samples);

}  // namespace shprt
