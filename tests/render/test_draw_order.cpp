// render/draw_order.hpp: each order lists every triangle once, near to far along its direction,
// and the order chosen for a view is the direction nearest it.
#include "shprt/render/draw_order.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace shprt {
namespace {

TEST(DrawOrder, EachOrderListsEveryTriangleOnceNearToFar) {
    const Mesh mesh = make_builtin("box_on_plane");
    const std::size_t T = mesh.triangle_count();
    const std::vector<std::uint32_t> orders = directional_draw_orders(mesh);
    ASSERT_EQ(orders.size(), std::size_t(kDrawOrderCount) * T * 3);
    std::vector<std::array<std::uint32_t, 3>> sorted_mesh = mesh.triangles;
    std::sort(sorted_mesh.begin(), sorted_mesh.end());
    for (int i = 0; i < kDrawOrderCount; ++i) {
        SCOPED_TRACE(i);
        const Vec3f d = draw_order_direction(i);
        EXPECT_NEAR(dot(d, d), 1.0f, 1e-6f);
        std::vector<std::array<std::uint32_t, 3>> listed(T);
        float previous = -INFINITY;
        for (std::size_t t = 0; t < T; ++t) {
            const std::uint32_t* tri = orders.data() + (std::size_t(i) * T + t) * 3;
            listed[t] = {tri[0], tri[1], tri[2]};
            const Vec3f c =
                (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) *
                (1.0f / 3.0f);
            EXPECT_GE(dot(c, d), previous) << "triangle " << t << " is nearer than the one before";
            previous = dot(c, d);
        }
        // The same triangles, each with its own winding.
        std::sort(listed.begin(), listed.end());
        EXPECT_EQ(listed, sorted_mesh);
    }
}

TEST(DrawOrder, TheOrderForAViewIsTheNearestDirection) {
    EXPECT_EQ(draw_order_direction(draw_order_for({0.1f, -2.0f, 0.05f})).y, -1.0f);
    EXPECT_EQ(draw_order_direction(draw_order_for({0.0f, 0.0f, 3.0f})).z, 1.0f);
    const Vec3f diagonal = draw_order_direction(draw_order_for({1.0f, -0.9f, 1.1f}));
    EXPECT_GT(diagonal.x, 0.5f);
    EXPECT_LT(diagonal.y, -0.5f);
    EXPECT_GT(diagonal.z, 0.5f);
    for (int i = 0; i < kDrawOrderCount; ++i) EXPECT_EQ(draw_order_for(draw_order_direction(i)), i);
    EXPECT_THROW(draw_order_direction(kDrawOrderCount), Error);
}

TEST(DrawOrder, BigMeshesKeepTheirOwnOrderOnly) {
    EXPECT_TRUE(draw_orders_fit(20006));  // the room
    const std::size_t limit = kMaxDrawOrderBytes / (kDrawOrderCount * 12);
    EXPECT_TRUE(draw_orders_fit(limit));
    EXPECT_FALSE(draw_orders_fit(limit + 1));
    EXPECT_FALSE(draw_orders_fit(2000000));  // the 2M-triangle room
}

}  // namespace
}  // namespace shprt
