// The generated room: triangle counts across scales, determinism, open top, openings, and the
// properties every generated mesh has.
#include "scene/geometry_checks.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/room.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <tuple>

namespace shprt {
namespace {

using test::brute_force_hit;

constexpr std::size_t kDefaultSlack = 2000;  // the 20 000 +- 2 000
constexpr double kScaleTol = 0.10;           // +- 10 % of the request from 5 000 up

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(SceneRoom, DefaultIsValidAndAbout20000Triangles) {
    const Mesh m = generate_room(RoomOptions{});
    EXPECT_GE(m.triangle_count(), 20000 - kDefaultSlack);
    EXPECT_LE(m.triangle_count(), 20000 + kDefaultSlack);
    EXPECT_EQ(m.source, "builtin:room");
    test::expect_valid_generated(m);
    // The built-in name gives the same mesh.
    const Mesh b = make_builtin("room");
    EXPECT_TRUE(same_bits(b.positions, m.positions));
}

TEST(SceneRoom, ScalesWithinTenPercent) {
    for (std::size_t n : {5000u, 100000u, 1000000u}) {
        SCOPED_TRACE(n);
        for (bool ceiling : {false, true}) {
            const Mesh m = generate_room({n, ceiling});
            const double ratio = static_cast<double>(m.triangle_count()) / static_cast<double>(n);
            EXPECT_NEAR(ratio, 1.0, kScaleTol) << m.triangle_count();
        }
    }
    // The smallest request is allowed to be coarser, but not wildly so.
    const Mesh small = generate_room({kRoomMinTriangles, false});
    EXPECT_LE(small.triangle_count(), 2 * kRoomMinTriangles);
    test::expect_valid_generated(small);
}

TEST(SceneRoom, FinerRoomsHaveSmallerCells) {
    EXPECT_GT(room_cell_size({5000, false}), room_cell_size({20000, false}));
    EXPECT_GT(room_cell_size({20000, false}), room_cell_size({100000, false}));
    // Shadows need vertices to land on: at the default size the floor grid is under 0.2 m.
    EXPECT_LT(room_cell_size({}), 0.2);
}

TEST(SceneRoom, RejectsOutOfRangeRequests) {
    for (std::size_t n : {std::size_t{0}, kRoomMinTriangles - 1, kRoomMaxTriangles + 1}) {
        try {
            generate_room({n, false});
            ADD_FAILURE() << n;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
            EXPECT_NE(std::string(e.what()).find(std::to_string(n)), std::string::npos);
        }
    }
}

TEST(SceneRoom, DeterministicBitForBit) {
    for (bool ceiling : {false, true}) {
        const Mesh a = generate_room({30000, ceiling}), b = generate_room({30000, ceiling});
        EXPECT_TRUE(same_bits(a.positions, b.positions));
        EXPECT_TRUE(same_bits(a.normals, b.normals));
        EXPECT_TRUE(same_bits(a.albedo, b.albedo));
        EXPECT_TRUE(same_bits(a.triangles, b.triangles));
    }
}

TEST(SceneRoom, OpenTopUnlessCeiling) {
    const Mesh open = generate_room({});
    const Bounds b = mesh_bounds(open);
    EXPECT_EQ(b.hi.y, kRoomWallHeight);  // nothing above the walls
    EXPECT_EQ(b.lo.y, 0.0f);
    EXPECT_EQ(b.lo.x, -kRoomHalfWidth - kRoomWallThickness);
    EXPECT_EQ(b.hi.z, kRoomHalfDepth + kRoomWallThickness);
    // Straight up from the open floor between the window wall and the table: the sky.
    const Vec3d floor_point{0.0, 1e-4, -1.5}, up{0, 1, 0};
    EXPECT_FALSE(brute_force_hit(open, floor_point, up).has_value());

    const Mesh closed = generate_room({20000, true});
    EXPECT_EQ(mesh_bounds(closed).hi.y, kRoomCeilingTop);
    const auto hit = brute_force_hit(closed, floor_point, up);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(*hit, kRoomWallHeight - 1e-4, 1e-5);
    // Under a skylight (x in [0.2, 1.4], z in [-0.6, 0.6], clear of the table and chairs) the
    // sky is still visible.
    EXPECT_FALSE(brute_force_hit(closed, {0.6, 1e-4, -0.55}, up).has_value());
}

TEST(SceneRoom, WindowAndDoorAreOpenings) {
    const Mesh m = generate_room({});
    // Through the window in the back wall (x in [-1.8, -0.2], y in [0.9, 2.2]) ...
    EXPECT_FALSE(brute_force_hit(m, {-1.0, 1.5, -1.0}, {0, 0, -1}).has_value());
    // ... but below its sill the wall: its inner face is 1.5 m away.
    const auto sill = brute_force_hit(m, {-1.0, 0.5, -1.0}, {0, 0, -1});
    ASSERT_TRUE(sill.has_value());
    EXPECT_NEAR(*sill, 1.5, 1e-5);
    // Through the door in the right wall (z in [0.7, 1.6], up to 2.1 m) ...
    EXPECT_FALSE(brute_force_hit(m, {2.0, 1.0, 1.15}, {1, 0, 0}).has_value());
    // ... and beside it the wall.
    const auto wall = brute_force_hit(m, {2.0, 1.0, 0.2}, {1, 0, 0});
    ASSERT_TRUE(wall.has_value());
    EXPECT_NEAR(*wall, 1.0, 1e-5);
    // Walls are thick: from outside, the back wall's outer face is 0.2 m before its inner face.
    const auto outer = brute_force_hit(m, {-2.5, 1.0, -4.0}, {0, 0, 1});
    ASSERT_TRUE(outer.has_value());
    EXPECT_NEAR(*outer, 4.0 - kRoomHalfDepth - kRoomWallThickness, 1e-5);
}

TEST(SceneRoom, HasFurnitureAndVariedColours) {
    const Mesh m = generate_room({});
    std::set<std::tuple<float, float, float>> colours;
    std::size_t above_floor_inside = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const Vec3f a = m.albedo[v], p = m.positions[v];
        colours.insert({a.x, a.y, a.z});
        if (p.y > 0.05f && p.y < 2.0f && std::abs(p.x) < kRoomHalfWidth - 0.05f &&
            std::abs(p.z) < kRoomHalfDepth - 0.05f)
            ++above_floor_inside;
    }
    EXPECT_GE(colours.size(), 15u);  // floor, walls, woods, fabrics, books, plant, ...
    EXPECT_GT(above_floor_inside, 2000u);
    // Not all grey: some albedo has clearly unequal channels.
    bool coloured = false;
    for (const auto& [r, g, b] : colours) coloured = coloured || std::abs(r - b) > 0.2f;
    EXPECT_TRUE(coloured);
}

}  // namespace
}  // namespace shprt
