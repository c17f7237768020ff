// The viewer's progressive bake: chunks of a background bake (shprt/bake/background.hpp), drained
// into the renderer's transfer buffer as the window loop does, equal the normal bake bit for bit.
#include "frame.hpp"

#include "bake/bake_test_util.hpp"
#include "shprt/bake/background.hpp"
#include "shprt/core/error.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/load.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>
#include <vector>

namespace shprt::viewer {
namespace {

TEST(BackgroundBake, ChunksIntoTheRenderersBufferEqualTheNormalBake) {
    std::unique_ptr<HeadlessGlContext> context;
    try {
        context = std::make_unique<HeadlessGlContext>();
    } catch (const Error& e) {
        GTEST_SKIP() << "no headless OpenGL 4.3 core context: " << e.what();
    }
    const Mesh mesh = load_scene("builtin:box_on_plane");
    const BakeOptions options = test::small_chunked_options();
    const TransferSet want = bake(mesh, options);
    {
        Renderer renderer;
        renderer.set_scene(mesh,
                           TransferSet::zeros(bake_description(options), mesh.vertex_count()));
        BackgroundBake worker(mesh, options);
        std::size_t updates = 0;
        auto drain = [&] {
            for (const TransferChunk& c : worker.chunks().take_all()) {
                renderer.update_transfer(c.first, c.count, c.rows.data());
                ++updates;
            }
        };
        while (!worker.done()) {
            drain();
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        drain();
        ASSERT_EQ(worker.state(), BakeState::finished) << worker.error();
        EXPECT_GT(updates, 1u);
        const std::vector<float> gpu =
            read_gl_buffer(renderer.transfer_buffer(), want.coeffs.size());
        EXPECT_EQ(gpu, want.coeffs);
    }
}

}  // namespace
}  // namespace shprt::viewer
