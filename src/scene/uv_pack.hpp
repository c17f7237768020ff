// The packing of a UV atlas's charts (scene/uv_atlas.cpp): each chart's box placed in a square by
// shelves or a skyline, and conformal charts packed by the texels they touch. Private to the
// scene area.
#pragma once

#include "shprt/scene/uv_atlas.hpp"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace shprt::detail {

using Uv = std::array<double, 2>;

// Twice the signed area of UV triangle (a, b, c).
inline double uv_area2(const Uv& a, const Uv& b, const Uv& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
}

// A chart's UV bounding box (metres at the chart's own layout) and where packing put it.
struct ChartBox {
    double lo_u = 1e300, lo_v = 1e300, hi_u = -1e300, hi_v = -1e300;
    double x = 0, y = 0;  // packed position of (lo_u, lo_v), metres
    double width() const { return hi_u - lo_u; }
    double height() const { return hi_v - lo_v; }
};

// The image side and scale (texels per metre) for `boxes` (metres), packed in place: shelves for
// projected charts, the skyline or shelves (whichever needs less room) for conformal ones. Throws
// Error(invalid_argument) naming `name` when options.texels_per_metre needs more than
// kMaxTexelSide.
std::pair<int, double> pack_atlas(std::vector<ChartBox>& boxes, const UvAtlasOptions& options,
                                  const std::string& name);

// Packs conformal charts by the texels their triangles (per chart, UVs in metres) touch when that
// beats the boxes already packed in `boxes` at `by_boxes` (resolution, texels per metre): a larger
// scale at the same resolution, or the same scale in a smaller image. Moves the boxes (x, y:
// metres) and returns the better pair.
std::pair<int, double> pack_texels(const std::vector<std::vector<std::array<Uv, 3>>>& triangles,
                                   std::vector<ChartBox>& boxes, const UvAtlasOptions& options,
                                   std::pair<int, double> by_boxes);

}  // namespace shprt::detail
