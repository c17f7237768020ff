// MeshBuilder: the primitives the generated scenes are made of (tessellated rectangles with
// holes, boxes, cylinders and cones, icospheres), with hard edges split so every face keeps its
// own flat normal. Tessellation is controlled by a cell size in metres: faces are cut into grids
// whose cells are at most that size, so shadows have vertices to land on.
//
// A builder can run in counting mode, where primitives only add to triangle_count(): the room
// generator uses it to search for the cell size that gives a requested triangle count.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <span>
#include <string>

namespace shprt {

enum class Axis { x = 0, y = 1, z = 2 };

// A rectangle [a0, a1] x [b0, b1] in a plane's two in-plane coordinates (see add_rect).
struct Rect2 {
    double a0, a1, b0, b1;
};

// Face selection bits for add_box.
constexpr unsigned kBoxNegX = 1u << 0;
constexpr unsigned kBoxPosX = 1u << 1;
constexpr unsigned kBoxNegY = 1u << 2;
constexpr unsigned kBoxPosY = 1u << 3;
constexpr unsigned kBoxNegZ = 1u << 4;
constexpr unsigned kBoxPosZ = 1u << 5;
constexpr unsigned kBoxAll = 63u;
constexpr unsigned kBoxNoBottom = kBoxAll & ~kBoxNegY;  // for things standing on a surface

class MeshBuilder {
public:
    // With count_only, primitives add to triangle_count() and store nothing.
    explicit MeshBuilder(bool count_only = false) : m_count_only(count_only) {}

    // Local-to-world placement for every primitive added afterwards: rotate by `yaw` radians
    // about +Y (right-handed: +Z turns toward +X, +X toward -Z), then translate by `origin`.
    // Quarter turns are exact.
    void set_placement(Vec3d origin, double yaw = 0.0);
    void reset_placement() { set_placement({0, 0, 0}, 0.0); }

    // An axis-aligned rectangle in the local plane {axis = coord}. Its in-plane coordinates
    // (a, b) are the other two axes in cyclic order: x -> (y, z), y -> (z, x), z -> (x, y). It
    // faces +axis when sign > 0, else -axis (counter-clockwise seen from the front either way).
    // It is cut into a grid of cells at most `cell` metres on a side (at least one cell per
    // interval) whose lines pass through every hole edge; cells inside a hole are left out.
    // Holes lie inside `r` and do not overlap.
    void add_rect(Axis axis, double coord, int sign, Rect2 r, double cell, Vec3f albedo,
                  std::span<const Rect2> holes = {});

    // An axis-aligned box [lo, hi] in local coordinates; `faces` selects which of its six faces
    // are emitted (kBox* bits). Each face is a separate grid (add_rect), so edges are hard.
    void add_box(Vec3d lo, Vec3d hi, double cell, Vec3f albedo, unsigned faces = kBoxAll);

    // A frustum of a cone around the local vertical line through `base` (a cylinder when the
    // radii are equal), from base.y to base.y + height. Smooth side normals; flat caps with their
    // own vertices. Segments around: max(8, ceil(circumference / cell)); rings along the side and
    // across each cap: ceil(length / cell).
    void add_cylinder(Vec3d base, double radius_bottom, double radius_top, double height,
                      double cell, Vec3f albedo, bool bottom_cap = true, bool top_cap = true);

    // An icosphere (subdivided icosahedron, 20 * 4^level triangles, vertices on the sphere,
    // outward normals). add_sphere picks the smallest level in [1, 7] whose edges are at most
    // `cell` metres (7 when none is).
    void add_icosphere(Vec3d centre, double radius, int level, Vec3f albedo);
    void add_sphere(Vec3d centre, double radius, double cell, Vec3f albedo);

    std::size_t triangle_count() const { return m_triangle_count; }
    // Exact only when not counting.
    std::size_t vertex_count() const { return m_mesh.positions.size(); }

    // Moves the built mesh out (the builder is left empty). Precondition: not count_only.
    Mesh take_mesh(std::string source);

private:
    std::uint32_t add_vertex(Vec3d local_position, Vec3d local_normal, Vec3f albedo);
    void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c);

    bool m_count_only;
    std::size_t m_triangle_count = 0;
    Vec3d m_origin{0, 0, 0};
    double m_cos = 1.0, m_sin = 0.0;
    Mesh m_mesh;
};

}  // namespace shprt
