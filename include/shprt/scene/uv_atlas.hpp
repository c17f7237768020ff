// A UV atlas for a mesh that has none (the generated room, scene/room.hpp), so that per-texel
// transfer (bake/texels.hpp) can bake it: charts grown over shared edges, each projected flat,
// packed without overlaps into the unit square with a gutter between charts.
//
// Charts: in triangle order, an unassigned triangle seeds a chart and it grows breadth-first over
// edges (two shared vertex indices) to every triangle whose face normal is within
// `max_angle_deg` of the seed's. A chart is projected orthographically along the seed's normal
// (lengths kept in the plane, foreshortened by at most cos(max_angle_deg) across it). Planar
// pieces (a grid of add_rect, a box face, a cylinder cap) become one chart each, undistorted;
// smooth convex pieces (cylinder sides, spheres) are cut into a few charts. The projection of a
// chart is one-to-one when the chart is planar or lies on a convex surface — true of every
// generated scene; for other meshes the texel rasteriser's overlap check is the judge.
//
// Packing: charts' bounding boxes on shelves, tallest first, all at one scale (texels per metre
// are the same on every chart), at least `gutter_texels` texels apart at `resolution` (half that
// from the border), so dilation and bilinear filtering never mix two charts at that resolution.
#pragma once

#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

struct UvAtlasOptions {
    int resolution = 1024;      // the texel resolution the gutter is sized for
    double gutter_texels = 4;   // empty texels between charts at `resolution`
    double max_angle_deg = 45;  // largest angle between a chart's face normals and its seed's
};

struct UvAtlasInfo {
    std::vector<std::uint32_t> chart;  // per triangle: its chart, 0 … charts − 1
    std::size_t charts = 0;
    std::size_t added_vertices = 0;  // copies made where charts meet
    double texels_per_metre = 0;     // at options.resolution
};

// Sets mesh.uvs (replacing any) to a packed atlas. A vertex used by several charts keeps its
// index in the first of them (by triangle order); each other chart gets a copy appended after
// all existing vertices (position, normal, albedo, and source_vertex / parents when present),
// and its triangles are renumbered to it: existing vertices keep their indices, the triangle
// list keeps its order and count. Deterministic. Throws Error(invalid_argument) for a mesh
// without triangles, indices out of range, or options outside resolution ≥ 1, gutter ≥ 0,
// 0 < angle < 90.
UvAtlasInfo make_uv_atlas(Mesh& mesh, const UvAtlasOptions& options = {});

}  // namespace shprt
