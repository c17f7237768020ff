// Building the flat BVH (flat_bvh.hpp) on the host: a surface-area-heuristic binary tree built by
// Embree's generic builder (rtcBuildBVH with our own node callbacks), then flattened depth first
// into FlatBvhNode / tri_verts / tri_ids arrays that can be copied byte for byte to a GPU.
#pragma once

#include "shprt/scene/mesh.hpp"
#include "shprt/trace/flat_bvh.hpp"

#include <cstdint>
#include <vector>

namespace shprt {

struct FlatBvhBuildOptions {
    // Embree's build quality: true = RTC_BUILD_QUALITY_HIGH, false = MEDIUM (both binned SAH).
    bool high_quality = true;
    // Spatial splits (HIGH only): reference capacity / triangle count, in [1, 4]; 1 disables
    // them. On the room they add 0.3 % references, no measurable speed, and 10× the build time
    // (bench/RESULTS.md, "Tracing"), hence off by default; scenes of long thin triangles gain more.
    float spatial_split_budget = 1.0f;
    int max_leaf_size = 4;  // 1..kFlatBvhMaxLeafSize
    // SAH costs of one node traversal and one triangle test (relative).
    float traversal_cost = 1.0f;
    float intersection_cost = 1.0f;
};

struct FlatBvhStats {
    std::uint32_t triangles = 0;   // mesh triangles in the tree (degenerate ones are left out)
    std::uint32_t references = 0;  // primitive references (≥ triangles with spatial splits)
    std::uint32_t leaves = 0;
    std::uint32_t max_depth = 0;  // deepest leaf; the root's children are at depth 1
    double sah_cost = 0.0;        // SAH cost of the tree with the options' costs
};

// An owning flat BVH in host memory (see FlatBvhView for the meaning of each array).
struct FlatBvh {
    std::vector<FlatBvhNode> nodes;
    std::vector<float> tri_verts;
    std::vector<std::uint32_t> tri_ids;
    FlatBvhStats stats;

    FlatBvhView view() const {
        return FlatBvhView{nodes.data(), tri_verts.data(), tri_ids.data(),
                           static_cast<std::uint32_t>(nodes.size()),
                           static_cast<std::uint32_t>(tri_ids.size())};
    }
    std::size_t bytes() const {
        return nodes.size() * sizeof(FlatBvhNode) + tri_verts.size() * sizeof(float) +
               tri_ids.size() * sizeof(std::uint32_t);
    }
};

// Builds the tree over mesh.triangles. Triangles of zero area (which no ray can hit) are left
// out. Runs on the calling thread plus Embree's TBB tasks. Throws shprt::Error(invalid_argument)
// naming mesh.source when the mesh has no triangles, an index out of range, a non-finite
// position, or only degenerate triangles; Error(unsupported) when it is too large for the layout
// (more than kFlatBvhMaxPrimRefs references); Error(invalid_argument) for bad options.
FlatBvh build_flat_bvh(const Mesh& mesh, const FlatBvhBuildOptions& options);
FlatBvh build_flat_bvh(const Mesh& mesh);  // default options: HIGH, no splits, leaves ≤ 4

// Checks the structural invariants of a flat BVH: every reference inside the arrays; nodes stored
// depth first, each reached exactly once; every child box containing the child node's boxes;
// every leaf box overlapping the bounds of its triangles (a spatially split triangle lies partly
// outside); the vertices in tri_verts equal to the mesh's and the stored normals equal to
// triangle_normal of them; depth ≤ kFlatBvhStackSize; every non-degenerate triangle of `mesh`
// referenced at least once. Throws shprt::Error(format) naming the first violation. For tests.
void validate_flat_bvh(const FlatBvh& bvh, const Mesh& mesh);

}  // namespace shprt
