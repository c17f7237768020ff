// A bake shown while it refines: the chunk queue, the worker thread, cancelling, and that the
// chunks, applied as they arrive (on the host, and into the renderer's GL buffer), rebuild the
// normal bake bit for bit.
#include "bake_stream.hpp"
#include "frame.hpp"

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

BakeOptions small_options() {
    BakeOptions o;
    o.K = 16;
    o.samples = 128;
    o.seed = 7;
    o.threads = 2;
    o.chunk_vertices = 64;  // many chunks on a small scene
    return o;
}

TEST(ChunkQueue, IsAFifoOfCopies) {
    ChunkQueue q;
    std::vector<float> a = {1, 2, 3, 4, 5, 6}, b = {7, 8};
    q.push(10, 3, a.data(), 2);
    q.push(0, 1, b.data(), 2);
    a[0] = -1;  // the queue holds its own copy
    EXPECT_EQ(q.pending(), 2u);
    const auto chunks = q.take_all();
    ASSERT_EQ(chunks.size(), 2u);
    EXPECT_EQ(chunks[0].first_vertex, 10u);
    EXPECT_EQ(chunks[0].vertex_count, 3u);
    EXPECT_EQ(chunks[0].coeffs, (std::vector<float>{1, 2, 3, 4, 5, 6}));
    EXPECT_EQ(chunks[1].coeffs, (std::vector<float>{7, 8}));
    EXPECT_EQ(q.pending(), 0u);
    EXPECT_TRUE(q.take_all().empty());
    EXPECT_EQ(q.chunks_pushed(), 2u);
    EXPECT_EQ(q.vertices_pushed(), 4u);
}

TEST(ChunkQueue, ApplyChunkChecksItsRange) {
    TransferSet t = empty_transfer(4, 2, TransferKind::shadowed);
    TransferChunk c{2, 2, {1, 2, 3, 4}};
    apply_chunk(t, c);
    EXPECT_EQ(t.coeffs, (std::vector<float>{0, 0, 0, 0, 1, 2, 3, 4}));
    TransferChunk outside{3, 2, {1, 2, 3, 4}};
    EXPECT_THROW(apply_chunk(t, outside), Error);
    TransferChunk short_data{0, 2, {1, 2, 3}};
    EXPECT_THROW(apply_chunk(t, short_data), Error);
}

TEST(BackgroundBake, ChunksRebuildTheNormalBakeExactly) {
    const Mesh mesh = load_scene("builtin:box_on_plane");
    const BakeOptions options = small_options();
    const TransferSet want = bake(mesh, options);

    BackgroundBake worker(mesh, options);
    TransferSet shown = empty_transfer(mesh.vertex_count(), options.K, options.transfer);
    std::vector<bool> covered(mesh.vertex_count(), false);
    std::size_t chunks = 0;
    // The consumer side, as the window loop does it: drain while the bake runs.
    auto drain = [&] {
        for (const TransferChunk& c : worker.chunks().take_all()) {
            for (std::size_t v = c.first_vertex; v < c.first_vertex + c.vertex_count; ++v) {
                ASSERT_FALSE(covered[v]) << "vertex " << v << " arrived twice";
                covered[v] = true;
            }
            apply_chunk(shown, c);
            ++chunks;
        }
    };
    while (!worker.done()) {
        drain();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    drain();
    ASSERT_EQ(worker.state(), BakeState::finished) << worker.error();
    EXPECT_EQ(worker.fraction_done(), 1.0);
    EXPECT_GT(chunks, 1u) << "progressive: more than one update";
    EXPECT_EQ(chunks, worker.chunks().chunks_pushed());
    for (std::size_t v = 0; v < covered.size(); ++v) ASSERT_TRUE(covered[v]) << "vertex " << v;
    EXPECT_EQ(shown.coeffs, want.coeffs) << "chunks rebuild the bake bit for bit";
    EXPECT_EQ(worker.result().coeffs, want.coeffs);
}

TEST(BackgroundBake, CancelStopsPromptly) {
    const Mesh mesh = load_scene("builtin:room");
    BakeOptions options;
    options.K = 16;
    options.samples = 1u << 16;  // minutes of work if it were not cancelled
    const auto start = std::chrono::steady_clock::now();
    {
        BackgroundBake worker(mesh, options);
        worker.cancel();
        worker.wait();
        EXPECT_EQ(worker.state(), BakeState::cancelled) << worker.error();
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 30.0);
    // The destructor alone cancels too (a window closed mid-bake).
    { BackgroundBake worker(mesh, options); }
}

TEST(BackgroundBake, ABadBakeReportsItsError) {
    const Mesh mesh = load_scene("builtin:box_on_plane");
    BakeOptions options = small_options();
    options.samples = 0;
    BackgroundBake worker(mesh, options);
    worker.wait();
    EXPECT_EQ(worker.state(), BakeState::failed);
    EXPECT_NE(worker.error().find("sample"), std::string::npos) << worker.error();
}

TEST(BackgroundBake, ChunksIntoTheRenderersBufferEqualTheNormalBake) {
    std::unique_ptr<HeadlessGlContext> context;
    try {
        context = std::make_unique<HeadlessGlContext>();
    } catch (const Error& e) {
        GTEST_SKIP() << "no headless OpenGL 4.3 core context: " << e.what();
    }
    const Mesh mesh = load_scene("builtin:box_on_plane");
    const BakeOptions options = small_options();
    const TransferSet want = bake(mesh, options);
    {
        Renderer renderer;
        renderer.set_scene(mesh, empty_transfer(mesh.vertex_count(), options.K, options.transfer));
        BackgroundBake worker(mesh, options);
        std::size_t updates = 0;
        auto drain = [&] {
            for (const TransferChunk& c : worker.chunks().take_all()) {
                renderer.update_transfer(c.first_vertex, c.vertex_count, c.coeffs.data());
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
