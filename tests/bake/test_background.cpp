// A bake shown while it refines: the chunk queue (a sink), the worker thread, cancelling, and
// that the chunks, applied as they arrive, rebuild the normal bake bit for bit.
#include "bake_test_util.hpp"
#include "shprt/bake/background.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/load.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>
#include <vector>

namespace shprt {
namespace {

TransferInfo grey_vectors(int K) {
    TransferInfo info;
    info.layout.K = K;
    return info;
}

TEST(ChunkQueue, IsAFifoOfCopies) {
    ChunkQueue q;
    q.begin(grey_vectors(2).layout, 0, 16);
    std::vector<float> a = {1, 2, 3, 4, 5, 6}, b = {7, 8};
    q.write(10, 3, a.data());
    q.write(0, 1, b.data());
    a[0] = -1;  // the queue holds its own copy
    EXPECT_EQ(q.pending(), 2u);
    const auto chunks = q.take_all();
    ASSERT_EQ(chunks.size(), 2u);
    EXPECT_EQ(chunks[0].first, 10u);
    EXPECT_EQ(chunks[0].count, 3u);
    EXPECT_EQ(chunks[0].rows, (std::vector<float>{1, 2, 3, 4, 5, 6}));
    EXPECT_EQ(chunks[1].rows, (std::vector<float>{7, 8}));
    EXPECT_EQ(q.pending(), 0u);
    EXPECT_TRUE(q.take_all().empty());
    EXPECT_EQ(q.chunks_written(), 2u);
    EXPECT_EQ(q.receivers_written(), 4u);
    q.write(4, 2, nullptr);  // rows that went to a device buffer: counted, not queued
    EXPECT_EQ(q.pending(), 0u);
    EXPECT_EQ(q.receivers_written(), 6u);
}

TEST(ChunkQueue, ApplyToChecksItsRange) {
    TransferSet t = TransferSet::zeros(grey_vectors(2), 4);
    TransferChunk c{2, 2, {1, 2, 3, 4}};
    c.apply_to(t);
    EXPECT_EQ(t.coeffs, (std::vector<float>{0, 0, 0, 0, 1, 2, 3, 4}));
    TransferChunk outside{3, 2, {1, 2, 3, 4}};
    EXPECT_THROW(outside.apply_to(t), Error);
    TransferChunk short_data{0, 2, {1, 2, 3}};
    EXPECT_THROW(short_data.apply_to(t), Error);
    // RGB rows: three channels of K per receiver.
    TransferInfo rgb = grey_vectors(2);
    rgb.layout.channels = 3;
    TransferSet t3 = TransferSet::zeros(rgb, 2);
    TransferChunk c3{1, 1, {1, 2, 3, 4, 5, 6}};
    c3.apply_to(t3);
    EXPECT_EQ(t3.coeffs, (std::vector<float>{0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5, 6}));
    EXPECT_THROW(c.apply_to(t3), Error) << "grey rows into an RGB set";
}

TEST(BackgroundBake, ChunksRebuildTheNormalBakeExactly) {
    const Mesh mesh = load_scene("builtin:box_on_plane");
    const BakeOptions options = test::small_chunked_options();
    const TransferSet want = bake(mesh, options);

    BackgroundBake worker(mesh, options);
    TransferSet shown = TransferSet::zeros(bake_description(options), mesh.vertex_count());
    std::vector<bool> covered(mesh.vertex_count(), false);
    std::size_t chunks = 0;
    // The consumer side, as the window loop does it: drain while the bake runs.
    auto drain = [&] {
        for (const TransferChunk& c : worker.chunks().take_all()) {
            for (std::size_t v = c.first; v < c.first + c.count; ++v) {
                ASSERT_FALSE(covered[v]) << "vertex " << v << " arrived twice";
                covered[v] = true;
            }
            c.apply_to(shown);
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
    EXPECT_EQ(chunks, worker.chunks().chunks_written());
    for (std::size_t v = 0; v < covered.size(); ++v) ASSERT_TRUE(covered[v]) << "vertex " << v;
    EXPECT_EQ(shown.coeffs, want.coeffs) << "chunks rebuild the bake bit for bit";
    EXPECT_EQ(worker.result().layout, want.layout);
    EXPECT_EQ(worker.result().stats.rays_cast, want.stats.rays_cast);
}

// An error-bounded bake refines toward its target in rounds (error_bound_rounds): the rows shown at
// the end are the bounded bake's own, bit for bit; each round's estimate is recorded, and the
// worst estimate and the share of receivers over the target fall from the first round to the last.
TEST(BackgroundBake, RefinesTowardTheTargetInRoundsAndEndsWithTheBoundedBake) {
    const Mesh mesh = load_scene("builtin:box_on_plane");
    BakeOptions options = test::small_chunked_options();
    options.direction_frame = DirectionFrame::local;
    options.target_error = 0.02;
    options.max_samples = 4096;
    EXPECT_EQ(error_bound_rounds(options), (std::vector<std::uint32_t>{256, 1024, 4096}));
    BakeOptions fixed = options;
    fixed.target_error = 0, fixed.max_samples = 0;
    EXPECT_EQ(error_bound_rounds(fixed), (std::vector<std::uint32_t>{fixed.samples}));
    const TransferSet want = bake(mesh, options);

    BackgroundBake worker(mesh, options);
    TransferSet shown = TransferSet::zeros(bake_description(options), mesh.vertex_count());
    while (!worker.done()) {
        for (const TransferChunk& c : worker.chunks().take_all()) c.apply_to(shown);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    for (const TransferChunk& c : worker.chunks().take_all()) c.apply_to(shown);
    ASSERT_EQ(worker.state(), BakeState::finished) << worker.error();
    EXPECT_EQ(shown.coeffs, want.coeffs) << "the last round is the bounded bake, bit for bit";
    EXPECT_EQ(worker.rays_cast(), want.stats.rays_cast)
        << "the rounds go on from each other (one bake session): every ray is cast once";
    const std::vector<RefineRound> seen = worker.refine_history();
    ASSERT_EQ(seen.size(), 3u);
    const RefineRound& first = seen.front();
    const RefineRound last = worker.refine_round();
    EXPECT_EQ(last.round, 3);
    EXPECT_EQ(last.rounds, 3);
    EXPECT_EQ(last.max_samples, 4096u);
    EXPECT_EQ(first.round, 1);
    EXPECT_EQ(first.max_samples, 256u);
    EXPECT_EQ(seen[1].max_samples, 1024u);
    EXPECT_GT(first.worst, last.worst) << "the estimate falls";
    EXPECT_GT(first.over_target, last.over_target);
    EXPECT_GT(last.mean_samples, first.mean_samples);
    EXPECT_LE(last.p99, options.target_error);
    EXPECT_EQ(worker.fraction_done(), 1.0);
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
    BakeOptions options = test::small_chunked_options();
    options.samples = 0;
    BackgroundBake worker(mesh, options);
    worker.wait();
    EXPECT_EQ(worker.state(), BakeState::failed);
    EXPECT_NE(worker.error().find("sample"), std::string::npos) << worker.error();
}

}  // namespace
}  // namespace shprt
