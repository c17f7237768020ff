// The entries of the transport operator A (interreflect.hpp) as SHPRT_HD code: what one closest
// hit adds to its row, shared by the CPU's row builder (src/bake/interreflect.cpp) and the GPU's
// build of A (src/bake/cuda/transport_kernels.cu), and the per-index steps of that GPU build, which the
// CPU tests run on the host (tests/bake/test_transport_build.cpp). Header-only; raw pointers and
// explicit counts (core/hd.hpp).
//
// The GPU builds one block of A (rows [first, first + count)) from the sample-major hit records
// of a chunk, in four data-parallel steps with a stable sort and a scan between them:
//
//   1. transport_sample_entries, per (vertex, sample): the three entries of the sample's hit,
//      each a key j·V + column (j: the row in the block, V: the mesh's vertices) and 3 channel
//      values; samples without a front-face hit give kTransportNoEntry keys (count·V, after all).
//   2. a stable sort of the keys (payload: the entries' indices). Entries of one row then come
//      in column order, and entries of one (row, column) in ray order, because the input is
//      sample-major: for one row, sample s before sample s + 1.
//   3. transport_run_sum, per sorted position: where a run of equal keys starts, its channel sums
//      in double in ray order (as TransportRowBuilder sums into its dense accumulator), kept when
//      not zero in every channel; then an exclusive scan of the kept flags gives each kept run its
//      slot, transport_compact writes it there, and transport_row_start finds each row's first.
//
// Every multiply and add is the CPU builder's, in the same order, so a block built on the GPU has
// the bits of the CPU's from the same hits. Device code is compiled with --fmad=false
// (cmake/Cuda.cmake): no contraction into fused multiply-adds.
#pragma once

#include "shprt/bake/transfer_sample.hpp"
#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"

#include <cmath>
#include <cstdint>

namespace shprt {

// The occluder mesh as A's entries read it: positions and linear albedo per vertex, three vertex
// indices per triangle (counter-clockwise = front), and the bounce sources a hit's light comes
// from (bake/bounce_sources.hpp): triangle t is a grid of grid[t] cells per edge whose points are
// A's columns — its corners the mesh's vertices, its other points base[t] + a local index — and,
// when two-sided, a back face's points are the front's plus `back_offset`. Without a grid
// (nullptr) every triangle is one cell: A's columns are the mesh's vertices.
struct TransportMeshView {
    const Vec3f* positions = nullptr;
    const std::uint32_t* triangles = nullptr;  // 3 per triangle
    const Vec3f* albedo = nullptr;
    const std::uint32_t* grid = nullptr;  // per triangle: cells per edge n ≥ 1 (nullptr: all 1)
    const std::uint32_t* base = nullptr;  // per triangle: its first own grid point (n > 1)
    std::uint32_t back_offset = 0;        // two-sided: a back face's points are front + this
};

// The index of grid point (i, j) of a triangle cut into n cells per edge: the point
// a + (i/n)·(b − a) + (j/n)·(c − a), i, j ≥ 0, i + j ≤ n. Corners are the triangle's vertices;
// the others are numbered row by row (j, then i) after base, skipping the three corners.
SHPRT_HD_INLINE std::uint32_t grid_point_index(const std::uint32_t* tri, std::uint32_t base,
                                               std::uint32_t n, std::uint32_t i, std::uint32_t j) {
    const std::uint32_t at = j * (n + 1) - j * (j - 1) / 2 + i;  // row-by-row index, corners too
    const std::uint32_t last = (n + 1) * (n + 2) / 2 - 1;
    if (at == 0) return tri[0];
    if (at == n) return tri[1];
    if (at == last) return tri[2];
    return base + at - 1 - (at > n ? 1u : 0u);
}

// Own (non-corner) points of a triangle cut into n cells per edge.
SHPRT_HD_INLINE std::uint32_t grid_own_points(std::uint32_t n) {
    return n > 1 ? (n + 1) * (n + 2) / 2 - 3 : 0;
}

// The cell of a triangle's grid that holds barycentrics (u, v) — u toward the triangle's second
// vertex, v toward its third — and the point's weights on the cell's three corners.
struct GridCell {
    std::uint32_t i[3], j[3];
    float weight[3];
};
SHPRT_HD_INLINE GridCell grid_cell(std::uint32_t n, float u, float v) {
    const float x = u * float(n), y = v * float(n);
    const float fi = std::floor(x), fj = std::floor(y);
    const std::uint32_t j = fj < 0.0f ? 0u : (fj > float(n - 1) ? n - 1 : std::uint32_t(fj));
    std::uint32_t i = fi < 0.0f ? 0u : (fi > float(n - 1) ? n - 1 : std::uint32_t(fi));
    if (i + j > n - 1) i = n - 1 - j;  // rounding put the point past its row's last cell
    const float fx = x - float(i), fy = y - float(j);
    if (i + j + 1 < n && fx + fy > 1.0f)  // the upper cell of the pair (i, j)
        return GridCell{
            {i + 1, i, i + 1}, {j + 1, j + 1, j}, {fx + fy - 1.0f, 1.0f - fx, 1.0f - fy}};
    return GridCell{{i, i + 1, i}, {j, j, j + 1}, {1.0f - fx - fy, fx, fy}};
}

// What one ray's closest hit adds to its row of A: per corner k of the hit's cell, its column
// and per channel c the value (weight/π · β_k(h)) · ρ_c(h), with β the hit's weights on the
// cell's corners and ρ(h) = Σ_k ρ(tri[k])·β_k interpolated over the mesh triangle in that order.
struct TransportHitEntries {
    std::uint32_t column[3];
    float value[3][3];  // [corner k][channel c]
};

// The entries of a ray along `dir` whose unoccluded weight is `weight` (max(0, n·w_s)·weight_s)
// and whose closest hit is `hit`. Returns false — nothing is added — when the ray escaped
// (kNoTriangle) or, unless `two_sided`, met a back face: a one-sided surface's inside sends
// nothing (the ray runs along the face's counter-clockwise normal, dot ≥ 0). Two-sided, a back
// face sends the light of its own side: its points' back copies (back_offset).
SHPRT_HD_INLINE bool transport_hit_entries(const TransportMeshView& mesh, Vec3f dir, float weight,
                                           SampleHit hit, bool two_sided,
                                           TransportHitEntries& out) {
    if (hit.triangle == kNoTriangle) return false;
    const std::uint32_t* tri = mesh.triangles + 3 * std::uint64_t(hit.triangle);
    const Vec3f p0 = mesh.positions[tri[0]];
    const Vec3f face = cross(mesh.positions[tri[1]] - p0, mesh.positions[tri[2]] - p0);
    const bool back = dot(face, dir) >= 0.0f;
    if (!two_sided && back) return false;
    const float bary[3] = {1.0f - hit.u - hit.v, hit.u, hit.v};
    Vec3f rho{0.0f, 0.0f, 0.0f};
    for (int k = 0; k < 3; ++k) rho = rho + mesh.albedo[tri[k]] * bary[k];
    constexpr float kInvPi = float(1.0 / 3.141592653589793);  // as the CPU: float(1.0 / π)
    const float a = weight * kInvPi;
    const std::uint32_t n = mesh.grid ? mesh.grid[hit.triangle] : 1u;
    const std::uint32_t side = back ? mesh.back_offset : 0u;
    if (n == 1) {
        for (int k = 0; k < 3; ++k) {
            const float ab = a * bary[k];
            out.column[k] = tri[k] + side;
            out.value[k][0] = ab * rho.x;
            out.value[k][1] = ab * rho.y;
            out.value[k][2] = ab * rho.z;
        }
        return true;
    }
    const GridCell cell = grid_cell(n, hit.u, hit.v);
    const std::uint32_t base = mesh.base[hit.triangle];
    for (int k = 0; k < 3; ++k) {
        const float ab = a * cell.weight[k];
        out.column[k] = grid_point_index(tri, base, n, cell.i[k], cell.j[k]) + side;
        out.value[k][0] = ab * rho.x;
        out.value[k][1] = ab * rho.y;
        out.value[k][2] = ab * rho.z;
    }
    return true;
}

// One chunk of the GPU build: rows [first, first + count) of A, from the sample-major hit
// records hits[s·count + j] (closest_hit_sample's, kNoTriangle where no ray was cast). Receivers
// are the mesh's vertices (normals per vertex); directions and weights are the direction set's.
struct TransportBuildView {
    TransportMeshView mesh;
    const Vec3f* normals = nullptr;
    const float* dirs = nullptr;     // 3·S: xyz per direction
    const float* weights = nullptr;  // S
    const SampleHit* hits = nullptr;
    std::uint32_t first = 0, count = 0, samples = 0;
    std::uint32_t vertices = 0;  // V: the mesh's vertices (A's columns)
    bool two_sided = false;

    // Entries of the chunk: three per (vertex, sample). The caller keeps it below 2^31.
    SHPRT_HD_INLINE std::uint64_t entries() const {
        return 3 * std::uint64_t(count) * std::uint64_t(samples);
    }
    // The key of no entry: count·V, greater than every real key j·V + column.
    SHPRT_HD_INLINE std::uint64_t no_entry() const {
        return std::uint64_t(count) * std::uint64_t(vertices);
    }
};

// The bits a sort must look at: every key, kTransportNoEntry included, is below 2^bits.
SHPRT_HD_INLINE int transport_key_bits(const TransportBuildView& b) {
    int bits = 1;
    while (bits < 64 && (b.no_entry() >> bits) != 0) ++bits;
    return bits;
}

// Step 1 for sample-major index i < count·S (vertex first + i % count, sample i / count): writes
// entries 3i, 3i + 1, 3i + 2 — keys[e], order[e] = e and values[3e + c].
SHPRT_HD_INLINE void transport_sample_entries(const TransportBuildView& b, std::uint32_t i,
                                              std::uint64_t* keys, std::uint32_t* order,
                                              float* values) {
    const std::uint32_t s = i / b.count;
    const std::uint32_t j = i - s * b.count;
    const Vec3f dir{b.dirs[3 * s], b.dirs[3 * s + 1], b.dirs[3 * s + 2]};
    const float weight = transfer_unoccluded(b.normals[b.first + j], dir, b.weights[s]);
    TransportHitEntries hit{};
    const bool any =
        weight != 0.0f && transport_hit_entries(b.mesh, dir, weight, b.hits[i], b.two_sided, hit);
    for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t e = 3 * i + k;
        order[e] = e;
        keys[e] = any ? std::uint64_t(j) * b.vertices + hit.column[k] : b.no_entry();
        for (int c = 0; c < 3; ++c) values[3 * std::uint64_t(e) + c] = any ? hit.value[k][c] : 0.0f;
    }
}

// Step 3 at sorted position p < n (keys sorted stably, order their entries' indices): where p
// starts a run of equal real keys, its sums per channel in double, from zero, in sorted order,
// converted to float into sums[3p + c], and kept[p] = 1 unless all three are zero (a black or
// grazing hit: TransportRowBuilder drops those too); elsewhere kept[p] = 0.
SHPRT_HD_INLINE void transport_run_sum(std::uint32_t p, std::uint32_t n, const std::uint64_t* keys,
                                       const std::uint32_t* order, const float* values,
                                       std::uint64_t no_entry, float* sums, std::uint32_t* kept) {
    const std::uint64_t key = keys[p];
    kept[p] = 0;
    if (key == no_entry || (p > 0 && keys[p - 1] == key)) return;
    double r = 0.0, g = 0.0, bl = 0.0;
    for (std::uint32_t q = p; q < n && keys[q] == key; ++q) {
        const float* v = values + 3 * std::uint64_t(order[q]);
        r += v[0];
        g += v[1];
        bl += v[2];
    }
    if (r == 0.0 && g == 0.0 && bl == 0.0) return;
    kept[p] = 1;
    sums[3 * std::uint64_t(p)] = float(r);
    sums[3 * std::uint64_t(p) + 1] = float(g);
    sums[3 * std::uint64_t(p) + 2] = float(bl);
}

// Step 3's compaction at sorted position p, with slot[p] the exclusive prefix sum of kept: a kept
// run's key, column and three channel values go to index slot[p] of the block's arrays.
SHPRT_HD_INLINE void transport_compact(std::uint32_t p, const std::uint64_t* keys,
                                       const std::uint32_t* kept, const std::uint32_t* slot,
                                       const float* sums, std::uint32_t vertices,
                                       std::uint64_t* out_keys, std::int32_t* column,
                                       float* value_r, float* value_g, float* value_b) {
    if (!kept[p]) return;
    const std::uint32_t at = slot[p];
    out_keys[at] = keys[p];
    column[at] = std::int32_t(keys[p] % vertices);
    value_r[at] = sums[3 * std::uint64_t(p)];
    value_g[at] = sums[3 * std::uint64_t(p) + 1];
    value_b[at] = sums[3 * std::uint64_t(p) + 2];
}

// The block's row start of row j ≤ count: the first of the nnz kept keys (sorted) at or after
// row j's first key j·V — a binary search, so rows without entries need no other pass.
SHPRT_HD_INLINE std::int32_t transport_row_start(std::uint32_t j, const std::uint64_t* out_keys,
                                                 std::uint32_t nnz, std::uint32_t vertices) {
    const std::uint64_t first_key = std::uint64_t(j) * vertices;
    std::uint32_t lo = 0, hi = nnz;
    while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (out_keys[mid] < first_key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return std::int32_t(lo);
}

}  // namespace shprt
