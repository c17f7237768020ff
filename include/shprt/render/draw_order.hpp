// Front-to-back draw orders. A depth-tested draw shades a fragment only when it is nearer than
// what the pixel holds (llvmpipe, like GPUs, tests depth before running the fragment shader), so
// triangles drawn near to far shade each pixel about once, and far to near once per layer. The
// renderer keeps the mesh's triangles sorted along a few fixed directions and draws the order
// whose direction is nearest the view (bench/RESULTS.md "Front-to-back draw orders"). The picture
// does not depend on the order: opaque triangles, depth test LESS; only equal depths (coincident
// triangles) could resolve differently, as they already do between views.
#pragma once

#include "shprt/core/vec.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

struct Mesh;

// The directions: the 6 axes and the 8 diagonals of a cube.
inline constexpr int kDrawOrderCount = 14;

// Above this, a mesh draws in its own order only (the orders are kDrawOrderCount copies of its
// index list on the GPU): 128 MiB, about 800 000 triangles.
inline constexpr std::size_t kMaxDrawOrderBytes = std::size_t(128) << 20;

// Direction i (unit length), 0 ≤ i < kDrawOrderCount.
Vec3f draw_order_direction(int i);

// The order to draw when looking along `forward` (any non-zero length): the direction with the
// largest cosine to it (the lowest index on ties).
int draw_order_for(Vec3f forward);

// Whether the orders of `triangles` triangles fit kMaxDrawOrderBytes.
bool draw_orders_fit(std::size_t triangles);

// The kDrawOrderCount orders one after the other, 3·T vertex indices each: order i lists the
// triangles by ascending dot(centroid, direction i), near to far for an eye looking along it;
// stable, so equal keys keep the mesh's order.
std::vector<std::uint32_t> directional_draw_orders(const Mesh& mesh);

}  // namespace shprt
