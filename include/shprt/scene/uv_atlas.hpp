// A UV atlas for a mesh that has none, so that per-texel transfer (bake/texels.hpp) can bake it:
// charts grown over shared edges, each laid out flat, packed without overlaps into the unit square
// with a gutter between charts, all at one scale (texels per metre are the same everywhere).
//
// Charts: in triangle order, an unassigned triangle seeds a chart and it grows breadth-first over
// edges to every triangle whose face normal is within `max_angle_deg` of the seed's.
//
// Layouts (ChartLayout):
// * projected — the generated room's (scene/room.hpp): edges are two shared vertex indices; a
//   chart is projected orthographically along the seed's normal (lengths kept in the plane,
//   foreshortened by at most cos(max_angle_deg) across it). Planar pieces become one chart each,
//   undistorted. One-to-one when the chart is planar or lies on a convex surface — true of every
//   generated scene, not of meshes in general.
// * conformal — any mesh (`shprt bake --unwrap`, `shprt scene unwrap`): edges are shared by
//   position (bit-equal floats: a file's split vertices are welded for adjacency, never merged),
//   and only manifold, consistently oriented edges join charts; a triangle with no area (|n| ≤
//   1e-9 · its longest edge²) is a chart of its own and gets no texels. Each chart is laid out by
//   least-squares conformal maps (Lévy, Petitjean, Ray & Maillot, SIGGRAPH 2002: two far vertices
//   pinned, the normal equations solved by sparse Cholesky), scaled so its UV area equals its
//   surface area, and split in two (grown from two far triangles) while a triangle is flipped or
//   its stretch exceeds `max_stretch`; after packing, the rasteriser's overlap check
//   (find_uv_overlap at the atlas's resolution) splits any chart that overlaps itself, grown from
//   the two overlapping triangles, until none does.
//
// Stretch of a triangle: max(σ₁, 1/σ₂), σ₁ ≥ σ₂ the singular values of the linear map from the
// triangle (metres) to its UVs (metres at the atlas's one scale): 1 when the map is an isometry.
//
// Packing, at one scale, at least `gutter_texels` texels apart at the atlas's resolution (half
// that from the border), so dilation and bilinear filtering never mix two charts there. Projected
// charts: bounding boxes on shelves, tallest first (the room's atlas, as its tests and docs quote
// it). Conformal charts, turned to their smallest box lying flat: boxes on shelves or a skyline
// (whichever needs less room) and then, when it does better, by their texels — each chart's
// conservative coverage dropped from above onto the columns' filled heights where its top stays
// lowest, its coverage grown by the gutter, so charts settle into each other's dents. The scale
// is `texels_per_metre` when set (the image side is then the smallest that holds the atlas), else
// the largest at which the charts fit a `resolution`² image (to 1 %).
#pragma once

#include "shprt/core/options.hpp"

#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace shprt {

enum class ChartLayout { projected, conformal };

struct UvAtlasOptions {
    int resolution = 1024;      // the square image's side; unused when texels_per_metre > 0
    double gutter_texels = 4;   // empty texels between charts at the atlas's resolution
    double max_angle_deg = 45;  // largest angle between a chart's face normals and its seed's
    ChartLayout layout = ChartLayout::projected;
    double texels_per_metre = 0;  // > 0: the atlas's scale; its resolution follows
    double max_stretch = 2;       // conformal: the largest stretch a chart keeps before a split
};

// The normal cone of conformal charts where the caller does not choose (`--unwrap`, `scene
// unwrap`): LSCM flattens curved charts with little stretch, so they may be wider than 45°.
inline constexpr double kUnwrapMaxAngle = 60;

// A conformal atlas as `shprt scene unwrap` takes it (core/options.hpp): a texel density or a
// resolution (not both), the gutter, the charts' normal cone and stretch.
struct UnwrapChoice {
    std::optional<double> texel_density;  // texels per metre, > 0 (chooses the resolution)
    std::optional<int> resolution;        // 1 to kMaxTexelSide (default UvAtlasOptions's)
    double gutter = UvAtlasOptions{}.gutter_texels;
    double max_angle = kUnwrapMaxAngle;
    double max_stretch = UvAtlasOptions{}.max_stretch;
};
// One row per option, in the command line's help order.
const std::vector<OptionRow<UnwrapChoice>>& unwrap_option_table();
// The conformal atlas's options of the choice; one-line Error(invalid_argument) naming the option
// for both a density and a resolution, a density ≤ 0 or a resolution out of range.
UvAtlasOptions unwrap_options_from(const UnwrapChoice& choice);

// Image sides above this get a warning (log_warn): 64 M texels; kMaxTexelSide is refused.
inline constexpr int kLargeAtlasSide = 8192;

struct UvAtlasInfo {
    std::vector<std::uint32_t> chart;  // per triangle: its chart, 0 … charts − 1
    std::size_t charts = 0;
    std::size_t added_vertices = 0;  // copies made where charts meet
    int resolution = 0;              // the square image's side the atlas is laid out for
    double texels_per_metre = 0;     // at `resolution`
    // Conformal: charts split because a triangle flipped, because of stretch, or because the
    // chart overlapped itself.
    std::size_t split_flipped = 0, split_stretched = 0, split_overlapping = 0;
    std::size_t degenerate_triangles = 0;  // no area: charts of their own, no texels
    // Stretch (see above) over the triangles with area: the largest, and the mean weighted by
    // surface area.
    double max_stretch = 1, mean_stretch = 1;
    double chart_share = 0;         // the charts' UV area over the square's (packing efficiency)
    bool overlaps_checked = false;  // conformal: find_uv_overlap found none at `resolution`
};

// Sets mesh.uvs (replacing any) to a packed atlas. A vertex used by several charts keeps its
// index in the first of them (by triangle order); each other chart gets a copy appended after
// all existing vertices (position, normal, albedo, and source_vertex / parents / brdf_index when
// present), and its triangles are renumbered to it: existing vertices keep their indices, the
// triangle list keeps its order and count. Deterministic; CPU, one thread. Throws
// Error(invalid_argument), naming mesh.source, for a mesh without triangles, indices out of range,
// a non-finite position, options outside resolution 1..kMaxTexelSide, gutter ≥ 0,
// 0 < angle < 90, texels_per_metre ≥ 0 (finite), max_stretch > 1, or a texels_per_metre that
// needs an image side above kMaxTexelSide (the message says the largest density that fits).
UvAtlasInfo make_uv_atlas(Mesh& mesh, const UvAtlasOptions& options = {});

// One line: "N charts (S split: F flipped, T stretched, O overlapping), WxW texels at D texels/m,
// stretch max X mean Y, P% of the image in charts, +A vertices[, overlap 0][, Z triangles without
// area]".
std::string describe(const UvAtlasInfo& info);

}  // namespace shprt
