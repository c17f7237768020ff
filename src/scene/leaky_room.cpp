// builtin:leaky_room (shprt/scene/leaky_room.hpp): boxes that overlap, interpenetrate and reach
// below the floor, as modellers build rooms, with the receiver faces tessellated and the rest
// left as single quads.
#include "shprt/scene/leaky_room.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/builder.hpp"

#include <cmath>
#include <limits>

namespace shprt {
namespace {

constexpr double kHalf = 2.0;               // interior x, z in [-kHalf, kHalf]
constexpr double kWall = 0.1;               // wall and floor thickness
constexpr double kEnd = kHalf + kWall / 2;  // where panel ends and floor slabs stop: mid-wall
constexpr double kWallTop = 2.3;            // walls span [-kWall, kWallTop]: 2.4 m
constexpr double kSlabOverlap = 0.35;       // the floor slabs meet over x in [-0.35, 0.35]
// One cell per face: a quad of two triangles, as an asset's unseen faces are.
constexpr double kWhole = std::numeric_limits<double>::infinity();

constexpr Vec3f kFloor{0.7f, 0.55f, 0.4f};
constexpr Vec3f kWalls{0.75f, 0.75f, 0.7f};
constexpr Vec3f kCeiling{0.8f, 0.8f, 0.78f};
constexpr Vec3f kRug{0.6f, 0.15f, 0.1f};
constexpr Vec3f kTable{0.55f, 0.35f, 0.2f};
constexpr Vec3f kBoxes{0.3f, 0.5f, 0.7f};
constexpr Vec3f kDie{0.8f, 0.75f, 0.2f};

// A box whose faces in `fine` are grids of `cell` and whose other faces in `faces` are one quad.
void add_part(MeshBuilder& b, Vec3d lo, Vec3d hi, Vec3f albedo, unsigned faces, unsigned fine,
              double cell) {
    if (faces & fine) b.add_box(lo, hi, cell, albedo, faces & fine);
    if (faces & ~fine) b.add_box(lo, hi, kWhole, albedo, faces & ~fine);
}

}  // namespace

Mesh generate_leaky_room(const LeakyRoomOptions& options) {
    const double cell = options.cell;
    SHPRT_CHECK(std::isfinite(cell) && cell >= kLeakyRoomMinCell, invalid_argument,
                "leaky_room: cell {} m must be at least {} m", options.cell, kLeakyRoomMinCell);
    MeshBuilder b;
    // Floor: two overlapping slabs whose top faces are the receivers.
    add_part(b, {-kEnd, -kWall, -kEnd}, {kSlabOverlap, 0, kEnd}, kFloor, kBoxAll, kBoxPosY, cell);
    add_part(b, {-kSlabOverlap, -kWall, -kEnd}, {kEnd, 0, kEnd}, kFloor, kBoxAll, kBoxPosY, cell);
    // Walls, from under the floor, each end half inside its neighbour; the inner faces are the
    // receivers.
    add_part(b, {-kEnd, -kWall, -kHalf - kWall}, {kEnd, kWallTop, -kHalf}, kWalls, kBoxAll,
             kBoxPosZ, cell);  // north
    add_part(b, {-kEnd, -kWall, kHalf}, {kEnd, kWallTop, kHalf + kWall}, kWalls, kBoxAll, kBoxNegZ,
             cell);  // south
    add_part(b, {-kHalf - kWall, -kWall, -kEnd}, {-kHalf, kWallTop, kEnd}, kWalls, kBoxAll,
             kBoxPosX, cell);  // west
    add_part(b, {kHalf, -kWall, -kEnd}, {kHalf + kWall, kWallTop, kEnd}, kWalls, kBoxAll, kBoxNegX,
             cell);  // east
    // A third of a ceiling, pierced by the wall tops: light bounces under it.
    b.add_box({-kEnd, 2.25, -kEnd}, {kEnd, 2.35, -0.7}, kWhole, kCeiling);
    b.add_box({-1.5, -0.02, 0.4}, {-0.2, 0.01, 1.6}, kWhole, kRug);
    // Table: the legs pierce the top and the floor, and have no bottom faces.
    b.add_box({0.4, 0.72, -0.3}, {1.6, 0.76, 0.7}, kWhole, kTable);
    for (const double x : {0.48, 1.52})
        for (const double z : {-0.22, 0.62})
            b.add_box({x - 0.03, -0.05, z - 0.03}, {x + 0.03, 0.74, z + 0.03}, kWhole, kTable,
                      kBoxNoBottom);
    b.add_box({1.0, 0.76, 0.1}, {1.02, 0.78, 0.12}, kWhole, kDie, kBoxNoBottom);
    // A bottomless box with its foot in the floor, and a smaller one half inside it.
    b.add_box({-1.5, -0.05, -1.4}, {-0.7, 0.6, -0.6}, kWhole, kBoxes, kBoxNoBottom);
    b.add_box({-0.9, 0.35, -1.15}, {-0.45, 0.75, -0.7}, kWhole, kBoxes);
    return b.take_mesh("builtin:leaky_room");
}

}  // namespace shprt
