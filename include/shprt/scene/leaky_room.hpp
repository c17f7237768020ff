// builtin:leaky_room: a small room built the way real assets are, for the tests of anything that
// reads values at ray hits (issue 34: the interreflected bake was 9-22 % too bright on such
// assets). Parts overlap and interpenetrate instead of meeting edge to edge, reach below the
// floor, and leave out faces nobody sees, so many vertices lie outside the room or inside other
// parts, where the light is nothing like the light in the room.
//
// Geometry (metres, +Y up; x, z of the interior in [-2, 2], floor top y = 0), every part an
// axis-aligned box (MeshBuilder::add_box: split vertices per face, flat unit normals,
// counter-clockwise = front = outward):
//   floor     two slabs y in [-0.1, 0], x in [-2.05, 0.35] and [-0.35, 2.05], z in [-2.05, 2.05]:
//             they overlap over x in [-0.35, 0.35] (coplanar tops) and their ends reach into the
//             walls;
//   walls     four panels 0.1 thick, y in [-0.1, 2.3] (2.4 m high, from under the floor), e.g.
//             the north one x in [-2.05, 2.05], z in [-2.1, -2]: each end sticks half the
//             thickness into its neighbour (the corners overlap in 0.05 x 0.05 columns); open top;
//   ceiling   one slab over the north third, x in [-2.05, 2.05], z in [-2.05, -0.7], y in
//             [2.25, 2.35] (the walls' tops pierce it);
//   rug       x in [-1.5, -0.2], z in [0.4, 1.6], y in [-0.02, 0.01]: through the floor plane;
//   table     top x in [0.4, 1.6], z in [-0.3, 0.7], y in [0.72, 0.76]; four 0.06 m legs from
//             y = -0.05 (inside the floor slab) to 0.74 (inside the top), without bottom faces;
//             on it a 2 cm die [1, 1.02] x [0.76, 0.78] x [0.1, 0.12] without a bottom (the tiny
//             triangles);
//   boxes     one without a bottom, [-1.5, -0.7] x [-0.05, 0.6] x [-1.4, -0.6], its foot in the
//             floor; a smaller closed one, [-0.9, -0.45] x [0.35, 0.75] x [-1.15, -0.7], half
//             inside it.
// Tessellation: the floor slabs' top faces and the walls' inner faces are grids of cells of at
// most `cell` metres (the receivers in the room); every other face is one quad of two triangles.
// With the default cell: 708 triangles (the coarser cell = 1: 348).
// Albedo per vertex, linear RGB: floor (0.7, 0.55, 0.4), walls (0.75, 0.75, 0.7), ceiling
// (0.8, 0.8, 0.78), rug (0.6, 0.15, 0.1), table and legs (0.55, 0.35, 0.2), boxes
// (0.3, 0.5, 0.7), die (0.8, 0.75, 0.2).
#pragma once

#include "shprt/scene/mesh.hpp"

namespace shprt {

struct LeakyRoomOptions {
    float cell = 0.5f;  // m, > 0 and at least kLeakyRoomMinCell: the grid of the receiver faces
};

constexpr float kLeakyRoomMinCell = 0.02f;  // 2 cm: about 300 000 triangles

// Generates the room. Deterministic: the same options give the same mesh bit for bit. Throws
// Error(invalid_argument) for a cell below kLeakyRoomMinCell or not finite. Mesh::source is
// "builtin:leaky_room".
Mesh generate_leaky_room(const LeakyRoomOptions& options);

}  // namespace shprt
