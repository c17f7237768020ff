// Adaptive refinement of per-vertex transfer: bake, split the edges across which the transfer
// changes too much, bake only the new vertices, repeat (docs/refinement.md). Per-vertex PRT is
// interpolated linearly across each triangle, so it misses any shadow that falls between
// vertices; refinement puts vertices where the transfer says they are needed (D3DX PRT's answer;
// here on the receivers seam of bake.hpp).
//
// The measure. An edge (a, b) is split when
//     d(a, b) = max_j |E_j(a) − E_j(b)| / E_max  >  tolerance
// where E_j(v) = Σ_i c_v[i]·l_j[i] is the irradiance of vertex v under test light j, the clamped
// cosine lobe L_j(w) = max(0, d_j·w) around one of 14 directions d_j (the 6 axes and the 8 cube
// diagonals), and E_max = 2π/3 is the irradiance such a light gives an unoccluded surface facing
// it. Why: it is what shading shows (irradiance under light coming from some side, not a
// coefficient norm, whose higher bands barely show after the cosine), it is linear in the
// coefficients (cheap: 14 dot products of K per vertex), the 14 lobes together see every
// direction so a shadow from any side registers, and dividing by the brightest value rather than
// by the local one makes the tolerance "a step of that fraction of full brightness", so dark
// corners with sampling noise are not refined forever.
//
// The splits keep the mesh conforming (no T-junctions): a split edge gets one new vertex, at its
// midpoint, shared by both triangles on it; each triangle is then cut by how many of its edges
// were split: one → two triangles, two → three (the quad cut along its shorter diagonal), three →
// four (red refinement). New vertices interpolate their parents' position, normal (renormalised),
// albedo and UVs; they lie on the original surface, so the occluders (and the BVH) stay the input
// mesh's. Existing vertices keep their indices; new ones are appended in order of their edge
// (lower index, then higher), and Mesh::parents records each one's edge.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

struct RefineOptions {
    double tolerance = 0.05;       // largest d(a, b) left unsplit, > 0
    std::size_t max_vertices = 0;  // stop when the mesh would exceed this many (0 = 16 × input)
    int max_depth = 6;             // a vertex made by splitting an edge whose ends have depth
                                   // ≤ D−1 has depth ≤ D; deeper splits are not made (1..30)
};

struct RefineResult {
    Mesh mesh;             // the refined mesh (input vertices first, then the new ones)
    TransferSet transfer;  // one row per vertex of `mesh`
    std::size_t input_vertices = 0;
    int passes = 0;                 // bake-and-split rounds after the first bake
    std::size_t edges_over = 0;     // edges still above the tolerance at the end
    bool budget_reached = false;    // max_vertices stopped it (some edges over tolerance left)
    bool depth_reached = false;     // max_depth kept some edge over tolerance from splitting
    double largest_difference = 0;  // max d(a, b) over the final mesh's edges
    // For each triangle of `mesh`, the input triangle it lies in (for locating points).
    std::vector<std::uint32_t> triangle_origin;
};

// The 14 test lights' SH coefficients (first K of each, see the top of this file).
std::vector<std::vector<float>> refine_test_lights(int K);

// d(a, b) for two rows of one-channel vector transfer with K coefficients.
double transfer_difference(const float* a, const float* b, int K,
                           const std::vector<std::vector<float>>& lights);

// Splits the given edges of `mesh` (pairs of vertex indices that are edges of its triangles;
// order and duplicates do not matter) as described at the top of this file, appending one vertex
// per edge and extending Mesh::parents. Returns the number of vertices added. With
// `triangle_origin` (one entry per triangle, e.g. the input triangle it lies in), each new
// triangle inherits its parent's entry. Throws Error(invalid_argument) for a pair that is not an
// edge, or origins of the wrong size.
std::size_t split_edges(Mesh& mesh, std::vector<std::array<std::uint32_t, 2>> edges,
                        std::vector<std::uint32_t>* triangle_origin = nullptr);

// The refinement loop on `mesh` with bake options `options` (shadowed or unshadowed, one channel,
// CPU or GPU as options.device says). Edges are visited in the order of their end indices; when
// the budget cannot take every edge over the tolerance, the largest differences go first (ties by
// index). Deterministic: the same inputs give the same mesh and rows whatever the thread count.
// Throws Error(invalid_argument) for bad refine options or for interreflected transfer
// (Error(unsupported)), and what bake() throws.
RefineResult bake_refined(const Mesh& mesh, const BakeOptions& options,
                          const RefineOptions& refine);

}  // namespace shprt
