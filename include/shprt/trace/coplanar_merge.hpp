// The triangles a visibility ray needs, not the ones shading needs. Per-vertex transfer wants a
// mesh tessellated finely enough to carry it (the paper's meshes, the room's grids, refine's
// subdivisions), and every one of those coplanar triangles costs a ray traversal steps. A flat
// face covers the same points as one triangle pair or as a thousand.
//
// merge_coplanar returns triangles that cover exactly the same set of points as the mesh's
// (to float rounding), with coplanar neighbours merged:
//  1. Vertices are welded by their exact position (split vertices at UV, material and normal seams
//     join).
//  2. Each triangle is paired with the neighbour across its longest edge when that edge is the
//     neighbour's longest too (a grid cell's diagonal), only two triangles share it, the windings
//     agree and the two make a convex quad in one plane.
//  3. Two quads that share a whole side merge when the sides next to it run straight on at both
//     of its ends: the union is then a convex quad again (its corners are the two quads' other
//     corners), so any of its diagonals splits it exactly. Repeated until nothing merges: a grid
//     becomes one quad, a wall with a window four.
// "Straight" and "in one plane" are to float rounding: the vertex left out lies within a few
// units in the last place of the coordinates (kRoundingUlps) of the line or plane. Nothing else
// is merged: triangles that were not paired, T-junctions, overlapping or interpenetrating parts,
// faces with opposite windings and curved surfaces stay as they are. A check of the total area
// (the merged triangles' must equal the mesh's) guards the whole: where it fails, the mesh's own
// triangles come back.
//
// The merged triangles know nothing of the mesh's triangle indices, so they serve visibility
// (Tracer::occluded, the GPU bake's visibility BVH) only; closest hits need the mesh's own
// triangles (embree_tracer.cpp keeps both). bench/RESULTS.md, "Tracing merged coplanar triangles",
// measures what it buys.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

struct MergedTriangles {
    std::vector<Vec3f> positions;                         // only the vertices still used
    std::vector<std::array<std::uint32_t, 3>> triangles;  // windings as in the mesh
    std::size_t input_triangles = 0;
    bool area_check_failed = false;  // true: `triangles` are the mesh's own (see above)
};

// Throws shprt::Error(invalid_argument) naming mesh.source, as the tracers do, for a mesh with no
// triangles, an index out of range, a non-finite position or only zero-area triangles.
MergedTriangles merge_coplanar(const Mesh& mesh);

// The merged triangles as a Mesh of positions and triangles only (its source the mesh's), for a
// BVH builder: the GPU bake's visibility BVH (build_flat_bvh).
Mesh merged_mesh(const Mesh& mesh);

}  // namespace shprt
