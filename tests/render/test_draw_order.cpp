// render/draw_order.hpp: each order lists every triangle once, near to far along its direction,
// and the order chosen for a view is the direction nearest it; the renderer drawing in it shades
// one fragment per pixel where the mesh's own order shades one per layer, and shows the same
// picture (that test SKIPs without EGL / OpenGL 4.3).
#include "shprt/render/draw_order.hpp"

#include "render_test_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh.hpp"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
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

// Six full-screen quads one behind the other, listed far to near. Drawn in that order every
// layer passes the depth test (six fragments shaded per pixel); in the front-to-back order the
// renderer picks for a camera looking down −z, only the nearest (one per pixel). Same picture.
TEST(DrawOrder, FrontToBackOrderShadesEachPixelOnceAndChangesNoPixel) {
    REQUIRE_GL(context);
    Mesh mesh;
    mesh.source = "six layers";
    const int layers = 6;
    for (int k = 0; k < layers; ++k) {
        const float z = -float(layers - 1 - k);  // the first quad listed is the farthest
        const auto first = static_cast<std::uint32_t>(mesh.positions.size());
        for (const auto& [x, y] :
             {std::pair{-9.0f, -9.0f}, {9.0f, -9.0f}, {9.0f, 9.0f}, {-9.0f, 9.0f}}) {
            mesh.positions.push_back({x, y, z});
            mesh.normals.push_back({0, 0, 1});
            mesh.albedo.push_back({0.2f + 0.1f * float(k), 0.5f, 0.8f - 0.1f * float(k)});
        }
        mesh.triangles.push_back({first, first + 1, first + 2});
        mesh.triangles.push_back({first, first + 2, first + 3});
    }
    const TransferSet transfer = test::analytic_transfer(mesh, 9);
    const ShLight light = make_light({"builtin"}, 9);
    Renderer renderer;
    renderer.set_scene(mesh, transfer);
    renderer.set_light(light);
    DrawSettings settings;
    settings.camera.eye = {0.3f, -0.2f, 3.0f};
    settings.camera.target = {0.0f, 0.0f, 0.0f};
    const int w = 64, h = 48;
    RenderTarget target(w, h, 1);
    GLuint query = 0;
    glGenQueries(1, &query);
    auto draw = [&](bool front_to_back, Image& image) {
        settings.front_to_back = front_to_back;
        target.bind();
        glBeginQuery(GL_SAMPLES_PASSED, query);
        renderer.draw(settings, w, h);
        glEndQuery(GL_SAMPLES_PASSED);
        GLuint64 samples = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &samples);
        image = target.read_pixels();
        return samples;
    };
    Image ordered, listed;
    const GLuint64 shaded_ordered = draw(true, ordered);
    const GLuint64 shaded_listed = draw(false, listed);
    glDeleteQueries(1, &query);
    EXPECT_EQ(shaded_ordered, GLuint64(w * h));
    EXPECT_EQ(shaded_listed, GLuint64(layers * w * h));
    EXPECT_EQ(ordered.rgb, listed.rgb);
    // The nearest layer is what both show.
    const float* centre = ordered.pixel(w / 2, h / 2);
    EXPECT_GT(centre[0], centre[2]) << "the nearest layer is the reddest";
}

}  // namespace
}  // namespace shprt
