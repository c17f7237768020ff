// The paper's test scene: a furnished room, generated deterministically.
//
// Geometry (metres, +Y up, right-handed): the interior floor is x in [-3, 3], z in [-2.5, 2.5] at
// y = 0; four walls 0.2 m thick and 2.7 m high surround it. The back wall (z = -2.5) has a window
// (x in [-1.8, -0.2], y in [0.9, 2.2]); the right wall (x = +3) has a door (z in [0.7, 1.6], y up
// to 2.1). The top is open, so distant light reaches inside, unless `ceiling` is set: then a 0.2 m
// slab closes it at y = 2.7 with two skylight openings. Furniture: a dining table with four chairs,
// a sofa with cushions, a rug and a coffee table, a bookshelf with books, a floor lamp, a potted
// plant and a picture. Albedos are plausible linear-RGB colours.
//
// Every face is a grid of cells of at most h metres (floor and inner walls h, furniture 1.5 h,
// outer wall faces and wall tops 2 h); h is chosen so the triangle count is as close as possible
// to `triangles` (within 10 % from 5 000 up). Below about 2 000 triangles the furniture alone sets
// the count: a 1 000 request gives roughly 1 400. Boxes have split vertices at their edges, so
// normals are flat per face; cylinders and the plant are smooth.
//
// UVs: a packed atlas (scene/uv_atlas.hpp, default options: gutters of 4 texels at 1024²), so
// `--domain texel` bakes the room. Planar faces are one chart each; the smooth cylinders and the
// plant's spheres are cut into charts, their vertices copied along the cuts (appended after the
// builder's vertices).
#pragma once

#include "shprt/scene/mesh.hpp"

#include <cstddef>

namespace shprt {

constexpr float kRoomWallHeight = 2.7f;     // m; with no ceiling nothing is higher
constexpr float kRoomCeilingTop = 2.9f;     // m; top of the ceiling slab when there is one
constexpr float kRoomHalfWidth = 3.0f;      // m; interior x in [-3, 3]
constexpr float kRoomHalfDepth = 2.5f;      // m; interior z in [-2.5, 2.5]
constexpr float kRoomWallThickness = 0.2f;  // m
constexpr std::size_t kRoomMinTriangles = 1000;
constexpr std::size_t kRoomMaxTriangles = 20'000'000;

struct RoomOptions {
    std::size_t triangles =
        20000;             // requested triangle count, in [kRoomMinTriangles, kRoomMaxTriangles]
    bool ceiling = false;  // close the top with a ceiling that has skylights
};

// Generates the room. Deterministic: the same options give the same mesh bit for bit. Throws
// Error(invalid_argument) when options.triangles is outside [kRoomMinTriangles,
// kRoomMaxTriangles]. Mesh::source is "builtin:room".
Mesh generate_room(const RoomOptions& options);

// The grid cell size h (metres) that generate_room uses for these options (see above).
double room_cell_size(const RoomOptions& options);

}  // namespace shprt
