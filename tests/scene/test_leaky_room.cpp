// builtin:leaky_room (scene/leaky_room.hpp): that it is built the way real assets are — panels
// whose ends stick into their neighbours, overlapping floor slabs, parts below the floor, legs
// through the table top, boxes inside boxes, missing bottoms — and the rest of what a generated
// mesh promises (validity, counts, tessellation, determinism).
//
// "Inside a part" is decided per part, with rays: the mesh is split into its parts (triangles
// connected through shared vertex positions: each box is one), and a point is inside a closed
// part when every ray from it first meets the back of one of that part's faces. Testing against
// the whole mesh would not do: in this scene other parts' faces run inside a part.
#include "common/brute_force_tracer.hpp"
#include "scene/geometry_checks.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/leaky_room.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <tuple>
#include <vector>

namespace shprt {
namespace {

using test::BruteForceTracer;

constexpr Vec3f kFloor{0.7f, 0.55f, 0.4f};
constexpr Vec3f kWalls{0.75f, 0.75f, 0.7f};
constexpr Vec3f kRug{0.6f, 0.15f, 0.1f};
constexpr Vec3f kTable{0.55f, 0.35f, 0.2f};
constexpr Vec3f kBoxes{0.3f, 0.5f, 0.7f};
constexpr Vec3f kDie{0.8f, 0.75f, 0.2f};
constexpr float kInf = std::numeric_limits<float>::infinity();

Vec3f face_normal(const Mesh& m, std::size_t t) {
    const auto& tri = m.triangles[t];
    const Vec3f p0 = m.positions[tri[0]];
    return normalize(cross(m.positions[tri[1]] - p0, m.positions[tri[2]] - p0));
}

// One part of the scene: its triangles as a mesh of their own, and a tracer over them.
struct Part {
    Mesh mesh;
    Bounds bounds;
    std::unique_ptr<BruteForceTracer> tracer;
};

// The parts: classes of triangles connected through vertices at the same position.
std::vector<Part> split_parts(const Mesh& m) {
    std::vector<std::size_t> parent(m.vertex_count());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    const auto find = [&](std::size_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    std::map<std::tuple<float, float, float>, std::size_t> first_at;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const Vec3f p = m.positions[v];
        const auto [it, added] = first_at.try_emplace({p.x, p.y, p.z}, v);
        if (!added) parent[find(v)] = find(it->second);
    }
    for (const auto& t : m.triangles) {
        parent[find(t[1])] = find(t[0]);
        parent[find(t[2])] = find(t[0]);
    }
    std::map<std::size_t, std::size_t> index;  // root -> part
    std::vector<Part> parts;
    for (const auto& t : m.triangles) {
        const auto [it, added] = index.try_emplace(find(t[0]), parts.size());
        if (added) parts.emplace_back();
        Mesh& pm = parts[it->second].mesh;
        std::array<std::uint32_t, 3> out{};
        for (int k = 0; k < 3; ++k) {
            out[k] = std::uint32_t(pm.positions.size());
            pm.positions.push_back(m.positions[t[k]]);
            pm.normals.push_back(m.normals[t[k]]);
            pm.albedo.push_back(m.albedo[t[k]]);
        }
        pm.triangles.push_back(out);
    }
    for (Part& p : parts) {
        p.bounds = mesh_bounds(p.mesh);
        p.tracer = std::make_unique<BruteForceTracer>(p.mesh);
    }
    return parts;
}

// Whether p is inside `part`: rays along the six axes and eight diagonals all first meet the back
// of one of its faces. For a part without a bottom face, only the rays that do not go down.
bool inside(const Part& part, Vec3f p, bool open_bottom = false) {
    std::vector<Vec3f> dirs = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const float sx : {-1.0f, 1.0f})
        for (const float sy : {-1.0f, 1.0f})
            for (const float sz : {-1.0f, 1.0f})
                dirs.push_back(normalize(Vec3f{sx, sy * 0.7f, sz * 1.3f}));
    for (const Vec3f d : dirs) {
        if (open_bottom && d.y < 0) continue;
        const Hit h = part.tracer->intersect(p, d, 0.0f, kInf);
        if (!h.hit || dot(face_normal(part.mesh, h.triangle), d) <= 0.0f) return false;
    }
    return true;
}

// The parts that contain p.
std::size_t parts_containing(const std::vector<Part>& parts, Vec3f p) {
    return std::size_t(std::count_if(parts.begin(), parts.end(),
                                     [&](const Part& part) { return inside(part, p); }));
}

// The part whose vertices all have this albedo and whose bounds contain p.
const Part& part_at(const std::vector<Part>& parts, Vec3f albedo, Vec3f p) {
    for (const Part& part : parts) {
        const Bounds& b = part.bounds;
        if (part.mesh.albedo[0] == albedo && p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y &&
            p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z)
            return part;
    }
    ADD_FAILURE() << "no part there";
    return parts.front();
}

TEST(SceneLeakyRoom, ValidWithDocumentedCountsAndDeterministic) {
    const Mesh m = generate_leaky_room(LeakyRoomOptions{});
    test::expect_valid_generated(m);
    EXPECT_EQ(m.source, "builtin:leaky_room");
    EXPECT_EQ(m.triangle_count(), 708u);  // the header's count
    const Mesh again = make_builtin("leaky_room");
    ASSERT_EQ(again.vertex_count(), m.vertex_count());
    EXPECT_EQ(std::memcmp(again.positions.data(), m.positions.data(), m.vertex_count() * 12), 0);
    EXPECT_EQ(std::memcmp(again.normals.data(), m.normals.data(), m.vertex_count() * 12), 0);
    EXPECT_EQ(std::memcmp(again.albedo.data(), m.albedo.data(), m.vertex_count() * 12), 0);
    EXPECT_EQ(again.triangles, m.triangles);
    // 2 floor slabs, 4 walls, the ceiling, the rug, the table top and 4 legs, the die, 2 boxes.
    EXPECT_EQ(split_parts(m).size(), 16u);
    const Mesh coarse = generate_leaky_room({1.0f});
    test::expect_valid_generated(coarse);
    EXPECT_EQ(coarse.triangle_count(), 348u);
    EXPECT_EQ(split_parts(coarse).size(), 16u);
    const Bounds b = mesh_bounds(m);
    EXPECT_EQ(b.lo, (Vec3f{-2.1f, -0.1f, -2.1f}));
    EXPECT_EQ(b.hi, (Vec3f{2.1f, 2.35f, 2.1f}));
}

TEST(SceneLeakyRoom, RejectsBadCells) {
    for (const float cell : {0.0f, -1.0f, 0.01f, std::numeric_limits<float>::quiet_NaN(), kInf})
        EXPECT_THROW(generate_leaky_room({cell}), Error) << cell;
}

// Receiver faces are grids of at most `cell`; every other face one quad; and somewhere tiny
// triangles.
TEST(SceneLeakyRoom, TessellatedReceiversHugeAndTinyTriangles) {
    for (const float cell : {0.5f, 1.0f}) {
        SCOPED_TRACE(cell);
        const Mesh m = generate_leaky_room({cell});
        std::size_t floor_top = 0, wall_inner = 0, others = 0;
        float longest_receiver_edge = 0, shortest_edge = kInf;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const auto& tri = m.triangles[t];
            const Vec3f n = face_normal(m, t), a = m.albedo[tri[0]];
            const Vec3f c =
                (m.positions[tri[0]] + m.positions[tri[1]] + m.positions[tri[2]]) / 3.0f;
            float longest = 0;
            for (int k = 0; k < 3; ++k) {
                const float e = length(m.positions[tri[(k + 1) % 3]] - m.positions[tri[k]]);
                longest = std::max(longest, e);
                shortest_edge = std::min(shortest_edge, e);
            }
            // A wall's inner face: at |x| = 2 or |z| = 2, facing the room's centre.
            const bool wall_face = (std::abs(std::abs(c.x) - 2.0f) < 1e-5f && n.x * c.x < -0.5f) ||
                                   (std::abs(std::abs(c.z) - 2.0f) < 1e-5f && n.z * c.z < -0.5f);
            if (a == kFloor && n.y > 0.5f) {
                ++floor_top;
            } else if (a == kWalls && wall_face) {
                ++wall_inner;
            } else {
                ++others;
                continue;
            }
            longest_receiver_edge = std::max(longest_receiver_edge, longest);
        }
        // Cells of at most cell × cell: diagonals of at most √2 cell.
        EXPECT_LE(longest_receiver_edge, cell * std::sqrt(2.0f) + 1e-5f);
        // Two slabs of ceil(2.4/cell) × ceil(4.1/cell) cells, four walls of ceil(4.1/cell) ×
        // ceil(2.4/cell); the other 84 faces of the 16 parts one quad each.
        const std::size_t n_short = std::size_t(std::ceil(2.4f / cell - 1e-4f));
        const std::size_t n_long = std::size_t(std::ceil(4.1f / cell - 1e-4f));
        EXPECT_EQ(floor_top, 2 * 2 * n_short * n_long);
        EXPECT_EQ(wall_inner, 4 * 2 * n_short * n_long);
        EXPECT_EQ(others, 2 * 84u);
        EXPECT_LE(shortest_edge, 0.02f + 1e-6f);  // the die
    }
}

// Each wall panel's ends lie inside its neighbours: the inner-face vertices at a panel's ends
// (x or z = ±2.05, in the plane |z| or |x| = 2 of its inner face) are inside the neighbouring
// panel, and so are the floor receivers at the slabs' ends. (Vertices on the neighbour's own
// boundary, at its top and bottom and the room's corners, are on it, not inside.)
TEST(SceneLeakyRoom, WallPanelsAndFloorEndsStickIntoTheWalls) {
    const Mesh m = make_builtin("leaky_room");
    const std::vector<Part> parts = split_parts(m);
    std::size_t wall_ends = 0, floor_ends = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const Vec3f p = m.positions[v], n = m.normals[v];
        const bool end_x = std::abs(p.x) == 2.05f, end_z = std::abs(p.z) == 2.05f;
        if (end_x == end_z || p.y == -0.1f || p.y == 2.3f) continue;  // corners, top, bottom
        const bool wall_inner =
            m.albedo[v] == kWalls &&
            ((std::abs(p.z) == 2.0f && n.z * p.z < 0) || (std::abs(p.x) == 2.0f && n.x * p.x < 0));
        const bool floor_top = m.albedo[v] == kFloor && n.y > 0.5f;
        if (!wall_inner && !floor_top) continue;
        const Part& wall =
            part_at(parts, kWalls, end_x ? Vec3f{p.x, 1.0f, 0.0f} : Vec3f{0.0f, 1.0f, p.z});
        EXPECT_TRUE(inside(wall, p)) << (wall_inner ? "wall" : "floor") << " vertex (" << p.x
                                     << ", " << p.y << ", " << p.z << ") is not in the wall";
        ++(wall_inner ? wall_ends : floor_ends);
    }
    // Two ends per panel with 4 inner rows of vertices; per slab 8 + 5 + 5 vertices at its ends.
    EXPECT_EQ(wall_ends, 4 * 2 * 4u);
    EXPECT_EQ(floor_ends, 2 * 18u);
    // The corner columns belong to two panels.
    for (const float sx : {-1.0f, 1.0f})
        for (const float sz : {-1.0f, 1.0f})
            EXPECT_EQ(parts_containing(parts, {sx * 2.03f, 1.2f, sz * 2.03f}), 2u);
}

// What reaches below the floor, and the two floor slabs that overlap.
TEST(SceneLeakyRoom, PartsReachBelowTheFloorAndOverlap) {
    const Mesh m = make_builtin("leaky_room");
    const std::vector<Part> parts = split_parts(m);
    std::size_t below = 0;
    for (const Part& part : parts) {
        const Vec3f a = part.mesh.albedo[0];
        if (part.bounds.lo.y < 0) ++below;
        if (a == kWalls || a == kFloor) {
            EXPECT_EQ(part.bounds.lo.y, -0.1f);
        }
        if ((a == kBoxes || a == kTable) && part.bounds.lo.y < 0) {
            EXPECT_EQ(part.bounds.lo.y, -0.05f);  // the legs and the big box
        }
        if (a == kRug) {
            EXPECT_LT(part.bounds.lo.y, 0.0f);
            EXPECT_GT(part.bounds.hi.y, 0.0f);
        }
    }
    EXPECT_EQ(below, 2 + 4 + 1 + 4 + 1u);  // floor, walls, rug, legs, box
    // Vertical rays through the slabs' overlap cross two coplanar tops and two bottoms.
    const BruteForceTracer tracer(m);
    for (const float x : {-0.3f, 0.0f, 0.3f}) {
        int tops = 0, bottoms = 0;
        for (const auto& t : m.triangles) {
            const Vec3d a = cast<double>(m.positions[t[0]]);
            const auto h = test::intersect_triangle({x, 1.0, -1.77}, {0, -1, 0}, a,
                                                    cast<double>(m.positions[t[1]]) - a,
                                                    cast<double>(m.positions[t[2]]) - a);
            if (!h || !(m.albedo[t[0]] == kFloor)) continue;
            tops += std::abs(1.0 - h->t) < 1e-6;
            bottoms += std::abs(1.0 - h->t + 0.1) < 1e-6;
        }
        EXPECT_EQ(tops, 2) << x;
        EXPECT_EQ(bottoms, 2) << x;
        EXPECT_EQ(parts_containing(parts, {x, -0.05f, -1.77f}), 2u) << x;
    }
    // The foot of a wall is inside the floor slab's end, and the rug inside the floor.
    EXPECT_EQ(parts_containing(parts, {-2.03f, -0.05f, 0.5f}), 2u);
    EXPECT_EQ(parts_containing(parts, {-1.0f, -0.01f, 1.0f}), 2u);
    // Open below: from under the floor, the sky is in sight straight down.
    EXPECT_FALSE(tracer.intersect({0.5f, -0.2f, 0.5f}, {0, -1, 0}, 0.0f, kInf).hit);
}

// Furniture: legs through the table top and into the floor, without bottoms; a bottomless box in
// the floor with a smaller box half inside it; the tiny die on the table.
TEST(SceneLeakyRoom, FurnitureInterpenetrates) {
    const Mesh m = make_builtin("leaky_room");
    const std::vector<Part> parts = split_parts(m);
    // Each leg's top (y = 0.74) is inside the table top, its foot (y = -0.05) in a floor slab.
    for (const float x : {0.48f, 1.52f})
        for (const float z : {-0.22f, 0.62f}) {
            EXPECT_TRUE(inside(part_at(parts, kTable, {1.0f, 0.74f, 0.2f}), {x, 0.735f, z}));
            EXPECT_TRUE(inside(part_at(parts, kFloor, {1.0f, -0.05f, 0.2f}), {x, -0.045f, z}));
            EXPECT_TRUE(inside(part_at(parts, kTable, {x, 0.3f, z}), {x, 0.3f, z}, true));
        }
    // The small box's corner inside the big one, the big one's top edge inside the small one.
    const Part& big = part_at(parts, kBoxes, {-1.0f, 0.0f, -1.0f});
    const Part& small = part_at(parts, kBoxes, {-0.6f, 0.7f, -0.9f});
    ASSERT_NE(&big, &small);
    EXPECT_TRUE(inside(big, {-0.89f, 0.36f, -1.14f}, true));
    EXPECT_TRUE(inside(small, {-0.8f, 0.6f, -0.9f}));
    EXPECT_TRUE(inside(big, {-0.8f, 0.59f, -0.9f}, true));
    // The big box's foot is in the floor: its sides go below y = 0.
    EXPECT_TRUE(inside(part_at(parts, kFloor, {-1.0f, -0.05f, -1.0f}), {-1.5f, -0.04f, -1.0f}));
    // No bottom faces on the legs, the big box and the die; the small box and the table top
    // have theirs.
    const auto faces_down = [](const Part& part) {
        for (std::size_t t = 0; t < part.mesh.triangle_count(); ++t)
            if (face_normal(part.mesh, t).y < -0.5f) return true;
        return false;
    };
    for (const float x : {0.48f, 1.52f})
        for (const float z : {-0.22f, 0.62f})
            EXPECT_FALSE(faces_down(part_at(parts, kTable, {x, 0.3f, z})));
    EXPECT_FALSE(faces_down(big));
    EXPECT_FALSE(faces_down(part_at(parts, kDie, {1.01f, 0.77f, 0.11f})));
    EXPECT_TRUE(faces_down(small));
    EXPECT_TRUE(faces_down(part_at(parts, kTable, {1.0f, 0.74f, 0.2f})));
}

// Open top but for one ceiling slab over about a third of the room.
TEST(SceneLeakyRoom, OneThirdOfACeiling) {
    const Mesh m = make_builtin("leaky_room");
    const BruteForceTracer tracer(m);
    int covered = 0, total = 0;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j) {
            const Vec3f p{-1.9f + 0.2f * float(i), 1.5f, -1.9f + 0.2f * float(j)};
            covered += tracer.intersect(p, {0, 1, 0}, 0.0f, kInf).hit;
            ++total;
        }
    EXPECT_NEAR(double(covered) / total, 1.0 / 3.0, 0.05);
}

}  // namespace
}  // namespace shprt
