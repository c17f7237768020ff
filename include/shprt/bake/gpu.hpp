// The GPU bake (CUDA): device discovery, the chunk planner, the bake itself and a raw traversal
// measurement. This header is CUDA-free: it compiles, links and answers in every build; in a build
// without CUDA (SHPRT_HAS_CUDA == 0, config.hpp) query_gpu() says so and the rest throws
// Error(unsupported).
//
// What the GPU bake computes is exactly bake.hpp's diffuse transfer, with the same direction set
// (the host's set and weights are uploaded, never recomputed in float on the device) and the same
// basis table Y[S×K] (computed on the host by basis_table). Per chunk of vertices:
//   1. a kernel with one thread per (vertex, sample) computes W[v][s] with transfer_sample()
//      (transfer_sample.hpp: visibility from the flat BVH of bvh_build.hpp, traversed by the
//      SHPRT_HD code of flat_bvh.hpp), warps spanning 32 consecutive vertices for one direction so
//      that their rays are nearly parallel and their horizons agree;
//   2. cuBLAS SGEMM C[chunk×K] = W[chunk×S]·Y[S×K] (FP32, no TF32);
//   3. C is copied back (or written in place into a caller's device buffer).
// Chunks alternate between two CUDA streams with their own buffers, so the trace of one chunk
// overlaps the projection and copy of the previous one.
//
// Agreement with the CPU bake. Where the flat BVH and Embree agree on a ray's visibility, the
// GPU's W is bit-identical to the CPU's (transfer_sample.hpp); the coefficients then differ only
// by the summation order of the two SGEMMs: |ΔC_i| ≤ (S + 8)·2^-24·Σ_s weight_s·|Y_si| (in
// practice ~1e-6 relative). Visibility may differ on rays that graze an edge (the two tracers'
// triangle tests round differently, and Embree's interval is closed): each such ray moves
// coefficient i by weight_s·|Y_si| ≤ (4π/S)·max|y_i|, i.e. ~1e-3 of the unoccluded L00 per ray
// at S = 4096. The flat BVH agrees with Embree on ≥ 99.9 % of the rays (tests/trace), so the
// expected maximum relative difference of a vertex's coefficients (max_i |ΔC_i| / max_i |C_i|) is
// ~1e-6 for most vertices and a few 1e-3 for the worst vertex of a scene such as the room.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

// ---------------------------------------------------------------------------------------------
// Devices

struct GpuInfo {
    bool available = false;        // a CUDA device can run the bake
    std::string name;              // e.g. "NVIDIA H100 80GB HBM3" (empty when unavailable)
    std::string reason;            // why not, one line, when !available
    std::size_t memory_bytes = 0;  // total device memory
    int compute_capability = 0;    // major·10 + minor, e.g. 90 for Hopper
    int multiprocessors = 0;
    int device_count = 0;  // CUDA devices the machine shows (0 when none or no CUDA build)
};

// CUDA device `device` (0-based among those CUDA_VISIBLE_DEVICES shows). Never throws: without a
// CUDA build, reason is "this build has no CUDA (<why>)", where <why> is what the configure step
// found and what to do: SHPRT_CUDA=OFF with or without an nvcc (named), an nvcc (named) that failed
// CMake's CUDA check, or no nvcc at all (cmake/Cuda.cmake);
// when the CUDA runtime reports an error (e.g. "CUDA driver version is insufficient for CUDA
// runtime version" on a machine without a GPU) or no device, reason is
// "no CUDA device (cudaGetDeviceCount: <CUDA's message>)"; for an index past the last device,
// "no CUDA device N (the machine has M)". The answer is computed once per process and device and
// cached. Thread-safe.
GpuInfo query_gpu(int device = 0);

// ---------------------------------------------------------------------------------------------
// Chunk planning (pure host code; tested without a GPU)

// What the GPU bake keeps on the device for the whole bake, in bytes: the flat BVH
// (bvh_bytes = FlatBvh::bytes(), 0 for unshadowed transfer), positions and normals (24 bytes per
// vertex), directions and weights (16 bytes per sample), the basis table (4·S·K bytes).
std::uint64_t gpu_bake_fixed_bytes(std::size_t vertices, std::size_t samples, int K,
                                   std::uint64_t bvh_bytes);

// What interreflected transfer adds to a slot per sample: the 12-byte hit record and the build of
// A's block from it (transport_build.hpp): three entries of 80 bytes (two 8-byte keys for the
// sort, the kept key, two 4-byte indices, the kept flag and its slot, 3 values, 3 sums, the
// column and 3 channel values) plus 8 bytes each budgeted for cub's temporary storage.
inline constexpr std::uint64_t kClosestHitBytesPerSample = 12 + 3 * (80 + 8);

// Bytes each chunk buffer ("slot") holds per vertex: W (4·S) plus C (4·K, unless the bake writes
// into a caller's device buffer) plus, for interreflected transfer (`closest_hits`),
// kClosestHitBytesPerSample per sample and a 4-byte row start; a slot also holds one 8-byte ray
// counter.
std::uint64_t gpu_bake_bytes_per_vertex(std::size_t samples, int K, bool device_output,
                                        bool closest_hits = false);

struct ChunkPlanRequest {
    std::size_t vertices = 0;              // V ≥ 1
    std::size_t samples = 0;               // S ≥ 1
    int K = 0;                             // 1..kMaxBakeCoeffs
    std::uint64_t free_device_bytes = 0;   // cudaMemGetInfo's free memory before the bake
    std::uint64_t fixed_device_bytes = 0;  // gpu_bake_fixed_bytes(...)
    bool device_output = false;            // C written into the caller's buffer: no C per slot
    bool closest_hits = false;  // interreflected: kClosestHitBytesPerSample per sample per slot
    std::size_t requested_chunk = 0;  // BakeOptions::chunk_receivers; 0 = automatic
    int slots = 2;                    // buffers in flight (2 = double buffering), ≥ 1
    // Automatic chunks stop growing at this many bytes per slot: larger ones fill the GPU no
    // better and leave nothing to overlap or to report progress on.
    std::uint64_t max_slot_bytes = std::uint64_t(64) << 20;
    // Only this fraction of the free memory is planned for (the CUDA context, cuBLAS and
    // fragmentation need the rest).
    double usable_fraction = 0.9;
};

struct ChunkPlan {
    std::size_t chunk_vertices = 0;  // vertices per chunk (the last chunk may be smaller)
    std::size_t chunk_count = 0;     // ⌈V / chunk_vertices⌉
    int slots = 0;                   // slots allocated: min(request.slots, chunk_count)
    std::uint64_t slot_bytes = 0;    // device bytes of one slot
    std::uint64_t peak_bytes = 0;    // fixed_device_bytes + slots·slot_bytes
};

// Chooses the chunk size of a GPU bake so that everything fits in the usable free memory:
//   budget = ⌊usable_fraction·free⌋ − fixed; per vertex b = gpu_bake_bytes_per_vertex(...);
//   fit    = ⌊(budget − slots·8) / (slots·b)⌋   (the most vertices that fit per slot);
//   chunk  = min(V, fit, ⌊(2^31 − 1)/S⌋ (the kernel's 32-bit thread index; ⌊(2^31 − 1)/3S⌋
//            with closest_hits: A's entries), and either
//            requested_chunk or, when automatic, max(1, ⌊max_slot_bytes / b⌋));
// an automatic chunk below V is rounded down to a multiple of 128 when at least 128 (whole GEMM
// tiles). When memory is ample the plan depends on (V, S, K, the request) only, never on the free
// memory, so repeated bakes cut the same chunks and give the same bits.
// Throws Error(out_of_memory) when not even one vertex per slot fits (naming the bytes needed and
// free), Error(invalid_argument) for V, S or slots = 0, K out of range or a fraction outside
// (0, 1].
ChunkPlan plan_chunks(const ChunkPlanRequest& request);

// Where an interreflected GPU bake's bounces keep the transport operator A (its blocks, in row
// order, of block_bytes[i] = TransportOperator::Block::bytes() each). With
//   usable = ⌊usable_fraction·free_device_bytes⌋ − dense_bytes   (the transfer in and out),
// every block stays on the device when Σ block_bytes ≤ usable. Otherwise the blocks are streamed:
// staging = the largest block's bytes is set aside, the first blocks whose sum fits the rest stay
// resident, and the others are copied in per bounce through the staging buffers (the same
// products, the same bits). Error(out_of_memory) when not even the dense arrays and the staging
// buffers fit.
struct TransportResidency {
    std::size_t resident_blocks = 0;   // blocks [0, resident_blocks) stay on the device
    std::uint64_t staging_bytes = 0;   // 0 when every block is resident
    std::uint64_t streamed_bytes = 0;  // the bytes copied in per bounce
    std::uint64_t peak_bytes = 0;      // dense + resident blocks + staging
};
TransportResidency plan_transport_residency(const std::vector<std::uint64_t>& block_bytes,
                                            std::uint64_t dense_bytes,
                                            std::uint64_t free_device_bytes,
                                            double usable_fraction = 0.9);

// ---------------------------------------------------------------------------------------------
// The bake
//
// The GPU bake is bake() (bake.hpp) with options.device = Device::cuda (or automatic where a GPU
// is usable), on CUDA device options.device_index. It computes what the CPU bake computes, to the
// tolerance stated at the top of this file. options.threads limits the host's BVH build (0 = all
// cores); options.chunk_receivers is honoured when it fits in device memory (else smaller chunks
// are used). Progress: as the CPU bake, from the calling thread between chunks. The sink's
// write() is called from the calling thread, in receiver order, once per chunk, with the chunk's
// rows in (pinned) host memory — or with nullptr when the sink has device_rows() (a DeviceSink,
// e.g. a mapped OpenGL buffer, see gpu_gl_interop.hpp): the rows are then written there, and are
// complete when bake() returns.
//
// Stats: seconds_bvh (flat BVH build on the host), seconds_trace and seconds_project (GPU time of
// the transfer kernels and of the SGEMMs, from CUDA events), seconds_total (wall time, including
// uploads), rays_cast, peak_bytes_host (the basis table, the host BVH and the pinned staging
// buffers), peak_bytes_device (every device allocation of the bake plus the cuBLAS workspaces),
// device_name = the GPU's name. One GPU bake runs at a time per process (a second caller waits).
// Errors beyond bake()'s: Error(out_of_memory) when even one-receiver chunks do not fit;
// Error(cuda) with the CUDA/cuBLAS message, file and line when a CUDA call fails.

// The transfer samples the GPU kernel computes for vertices [first, first + count): row j holds
// W[first + j][s] for s < S (count × S floats, vertex-major), exactly as the bake's kernel
// produces them, copied back. For tests: compare with transfer_sample() run on the host (with
// a local `frame`, local_transfer_sample(): the directions are then in each vertex's frame).
// Throws as the GPU bake, and Error(invalid_argument) for a range outside the mesh.
std::vector<float> gpu_transfer_samples(const Mesh& mesh, TransferKind kind,
                                        const DirectionSet& directions, std::size_t first,
                                        std::size_t count,
                                        DirectionFrame frame = DirectionFrame::sphere,
                                        int device = 0);

// The transport operator A of interreflected transfer (interreflect.hpp) as the GPU bake builds
// it: closest hits over the flat BVH and A's blocks built on the device (transport_build.hpp),
// one block per chunk of `chunk` vertices (0 = the bake's plan). For tests: the same bits as
// build_transport_operator with a tracer over the same flat BVH. One-sided, over the vertices
// alone: the bake's operator over the bounce sources (cells, back copies, validity) is traced on
// the host for now (docs/interreflection.md, "Not done"), and this device build is the piece
// that will take it over. Throws as the GPU bake, Error(invalid_argument) for a mesh without
// albedo per vertex and Error(unsupported) for `two_sided`.
TransportOperator gpu_transport_operator(const Mesh& mesh, const DirectionSet& directions,
                                         bool two_sided, std::size_t chunk = 0, int device = 0);

// Raw any-hit traversal rate: a kernel that only traces, one thread per (vertex, direction) with
// n·w > 0, from offset_ray_origin(p, n), over the flat BVH of `mesh`; no W, no projection.
// Runs the kernel `repeats` (≥ 1) times after one warm-up launch and reports the fastest.
struct GpuTraversalResult {
    std::uint64_t rays = 0;      // rays per launch (the bake's rays_cast for this set)
    std::uint64_t occluded = 0;  // of those, how many hit something (for validation)
    double seconds = 0;          // GPU time of the fastest launch (CUDA events)
    std::string device_name;
};
GpuTraversalResult measure_gpu_traversal(const Mesh& mesh, const DirectionSet& directions,
                                         int repeats, int device = 0);

}  // namespace shprt
