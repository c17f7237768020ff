// Triangulating the polygons a mesh file may contain (OBJ n-gons, PLY quads), done here rather
// than by Assimp's post-process, whose assertions abort on some corrupt files.
#pragma once

#include "shprt/core/vec.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace shprt {

// Appends triangles covering the planar (or nearly planar) simple polygon whose corners are
// positions[polygon[0]], positions[polygon[1]], ... in order; each triangle lists vertex indices
// from `polygon` in the polygon's own winding, so front faces stay front faces. Ear clipping in
// the plane of the polygon's Newell normal; for a convex polygon the result is the fan from
// polygon[0]: (p0, p1, p2), (p0, p2, p3), ... A self-intersecting, degenerate or very large
// (over 1000 corners) polygon falls back to that fan. Fewer than 3 corners give nothing.
// Precondition: every index is < positions.size().
void triangulate_polygon(std::span<const Vec3f> positions, std::span<const std::uint32_t> polygon,
                         std::vector<std::array<std::uint32_t, 3>>& out);

}  // namespace shprt
