// Interreflected transfer: the light that reaches a receiver after bouncing off the scene's
// diffuse surfaces, as a sparse linear operator on per-vertex transfer (docs/interreflection.md).
//
// Definition. T_0 is the shadowed transfer (bake.hpp). Light leaving a surface point h of albedo
// ρ(h) under irradiance E(h) has radiance ρ(h)/π · E(h), so with the shared direction set
// {w_s, weight_s} and the closest hit h_s of the ray from vertex v along w_s:
//
//     T_b(v) = Σ_s weight_s · max(0, n_v·w_s) · ρ(h_s)/π · T_{b−1}(h_s)
//
// where T_{b−1}(h) is interpolated from the hit triangle's vertices with the hit's barycentrics
// and ρ(h) likewise from their albedos. A ray that escapes brings nothing (its light is T_0's); a
// ray that hits the back of a triangle (one-sided surfaces: counter-clockwise = front) brings
// nothing unless `two_sided`. Every bounce is linear in T_{b−1}, per colour channel c:
//
//     T_b = A_c · T_{b−1},   A_c[v][j] = Σ_{s: h_s on a triangle with vertex j}
//                                          weight_s · cos_s / π · ρ_c(h_s) · bary_j(h_s)
//
// a sparse V×V matrix: one row per vertex, one column per vertex its rays hit (entries from the
// same vertex merged). The three channels share one pattern. The stored transfer is
// T_0 + T_1 + … + T_N (RGB: three channels of K per receiver).
//
// Determinism: each row of A is built by one thread from its own rays in direction order and its
// duplicates merged in that order; each row of a product is one thread's sum over its entries in
// column order. Same inputs and seed → same bits for any thread count (tested).
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/bake/bounce_sources.hpp"
#include "shprt/bake/transfer_sample.hpp"
#include "shprt/bake/transport_build.hpp"
#include "shprt/core/progress.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/sampler.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace shprt {

class Tracer;

// The transport operator A in compressed sparse rows (int32 indices, float values), one pattern
// and three channels' values (R, G, B), stored as consecutive blocks of rows: each block is the
// CSR of its own rows, built by one worker and kept as it was built. Nothing is ever concatenated,
// so building A needs no second copy of it (the peak is A itself), and a block's int32 offsets
// bound only its own non-zeros: the whole operator may hold more than 2^31 − 1.
//
// A block is either in memory (its vectors) or spilled: when a memory budget is given
// (TransportOptions::memory_budget) and the finished blocks would pass it, further finished
// blocks are written to a temporary file and their vectors freed; once every block is built the
// file is mapped read-only and the spilled blocks' arrays point into the mapping (`mapped`), which
// the operator owns (`spill`). The file is unlinked as soon as it is mapped, and removed on an
// error or a signal before that (core/file.hpp's AtomicFile). Readers use the accessors, which
// serve both kinds; the bits of every product are the same.
struct TransportOperator {
    struct Block {
        std::size_t first = 0;                     // the block's first row (vertex)
        std::vector<std::int32_t> row_start;       // rows() + 1 offsets into column/values
        std::vector<std::int32_t> column;          // columns, increasing within a row
        std::array<std::vector<float>, 3> values;  // per channel, one per column entry
        // A spilled block's arrays in the operator's mapping (the vectors are then empty).
        struct Mapped {
            const std::int32_t* row_start = nullptr;
            const std::int32_t* column = nullptr;
            std::array<const float*, 3> values{};
            std::size_t rows = 0, nnz = 0;
        } mapped;

        bool spilled() const { return mapped.row_start != nullptr; }
        std::size_t rows() const {
            if (spilled()) return mapped.rows;
            return row_start.empty() ? 0 : row_start.size() - 1;
        }
        std::size_t nnz() const { return spilled() ? mapped.nnz : column.size(); }
        const std::int32_t* starts() const {
            return spilled() ? mapped.row_start : row_start.data();
        }
        const std::int32_t* columns() const { return spilled() ? mapped.column : column.data(); }
        const float* channel(int c) const {
            return spilled() ? mapped.values[std::size_t(c)] : values[std::size_t(c)].data();
        }
        // Bytes of its arrays: row starts, columns, three channels of values.
        std::uint64_t bytes() const { return (rows() + 1) * 4 + std::uint64_t(nnz()) * 16; }
    };
    std::size_t vertices = 0;
    std::vector<Block> blocks;        // rows [0, vertices) in order, each row in exactly one block
    std::uint64_t rays_cast = 0;      // closest-hit rays traced to build it
    std::uint64_t spilled_bytes = 0;  // bytes of the blocks that live in the mapping
    std::shared_ptr<const void> spill;  // owns the mapping of the spilled blocks (or null)

    std::uint64_t nnz() const {
        std::uint64_t n = 0;
        for (const Block& b : blocks) n += b.nnz();
        return n;
    }
    // Bytes of the arrays: row starts, columns, three channels of values (spilled or not).
    std::uint64_t bytes() const {
        std::uint64_t n = 0;
        for (const Block& b : blocks) n += b.bytes();
        return n;
    }
};

struct TransportOptions {
    bool two_sided = false;
    int threads = 0;  // 0 = all hardware threads
    // Rows per block of A (and per task): 0 = the CPU bake's chunk (auto_chunk_receivers).
    // Fixed by the caller, never by the threads, so A's blocks do not depend on them.
    std::size_t rows_per_block = 0;
    ProgressFn progress;  // ProgressInfo{"bake", rays done, rays (estimate), "rays"}
    // Bytes the finished blocks may keep in memory (0 = no limit): a finished block that would
    // take them past it is spilled to a temporary file in `spill_directory` ("" = $TMPDIR, else
    // /tmp) and mapped back read-only (see TransportOperator). Which blocks spill depends on the
    // order the workers finish them, never the bits.
    std::uint64_t memory_budget = 0;
    std::string spill_directory;
};

// Builds A for every vertex of `mesh` (positions, unit normals, albedo per vertex) with the
// direction set `directions` and a tracer built over `mesh` (its closest_hits: one stream per
// vertex from offset_ray_origin(p, n), directions above the horizon only): the bounce sources
// are the vertices alone (bounce_sources.hpp, spacing infinity), and two-sided their back copies
// too (2V rows: vertex v's back at V + v). Throws
// Error(invalid_argument) for a mesh without albedo per vertex; Error(out_of_memory) when one
// block's non-zeros would pass 2^31 − 1; Error(cancelled) when the progress callback returns
// false.
TransportOperator build_transport_operator(const Mesh& mesh, const DirectionSet& directions,
                                           const Tracer& tracer, const TransportOptions& options);

// Builds A over bounce sources made for `mesh` (make_bounce_sources with the same two_sided):
// one row per point — its closest hits from offset_ray_origin(p, n) over the directions above
// its horizon — and one column per point (a hit's light from the corners of its cell). The
// same errors as build_transport_operator, and Error(invalid_argument) for sources of another
// mesh or side option.
TransportOperator build_source_operator(const Mesh& mesh, const BounceSources& sources,
                                        const DirectionSet& directions, const Tracer& tracer,
                                        const TransportOptions& options);

// The bounce sources an interreflected bake with `options` makes of `mesh` (its spacing, 0 =
// default_source_spacing; its sides), for estimate_bake_peak_bytes; 0 for other kinds.
float bake_source_spacing(const Mesh& mesh, const BakeOptions& options);
std::size_t bake_bounce_source_count(const Mesh& mesh, const BakeOptions& options);

// The directions the operator of an interreflected bake with `options` traces: the first
// BakeOptions::indirect_samples (0 = S / kIndirectSampleShare) of the bake's sampler and seed —
// for Sobol a nested prefix of `directions` —, or `directions` itself when that many or more.
// A local bake (DirectionFrame::local): always the sphere set of its sampler and seed, at most S.
// An error-bounded bake (target_error > 0) gives `gather_base`, the prefix its receivers' direct
// part needed (the mean prefix rounded up to a power of two: gather_base_of), for S: the final
// gather then takes gather_base / kIndirectSampleShare directions of the same nested set.
DirectionSet indirect_direction_set(const BakeOptions& options, const DirectionSet& directions,
                                    std::size_t gather_base = 0);
// The gather base of an error-bounded bake from its receivers' prefixes: their mean rounded up to
// a power of two (at least 1).
std::size_t gather_base_of(const std::vector<std::uint32_t>& receiver_samples);

// The coefficients light carries from its second bounce on in an interreflected bake with
// `options`: BakeOptions::bounce_coeffs, 0 = kDefaultBounceCoeffs, at most K.
int bounce_coeffs(const BakeOptions& options);

// The mesh's arrays as A's entries read them (transport_build.hpp: the CPU's rows and the GPU's
// build of A share its arithmetic); valid while `mesh` is.
TransportMeshView transport_mesh_view(const Mesh& mesh);

// Which code runs a bounce's product: automatic (AVX2 where the CPU has it, else Eigen), Eigen's
// sparse × dense product (Eigen::SparseMatrix row-major, mapped on A's arrays, per channel), or
// the AVX2 kernel (all three channels in one pass over the shared pattern; Error(unsupported)
// without AVX2). Both give the same bits (tested): the same multiplies and adds in the same order.
enum class TransportKernel { automatic, eigen, avx2 };

// One bounce: out = A·in per channel, where `in` and `out` are V rows of 3 channels × K floats
// (the transfer layout, receiver-major: row v, channel c at (v·3 + c)·K). TBB over fixed blocks of
// 2048 rows; `threads` 0 = all. The bits do not depend on the threads or the kernel. With
// `columns` < K only the first `columns` floats of each channel are computed (the others of
// `out` are left as they were); each is the same as in the whole product.
void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads);
void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads,
                     TransportKernel kernel, int columns = 0);

}  // namespace shprt
