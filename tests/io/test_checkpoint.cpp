// Checkpoints of a bake (io/checkpoint.hpp) and baking what is left (bake/remaining.hpp): the
// records a checkpoint holds come back exactly, a damaged tail is dropped, another bake's
// checkpoint is refused, and a bake resumed from any set of finished spans gives the whole bake's
// rows bit for bit. Also the bake's memory estimate against the peak it measures.
#include "shprt/bake/bake.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/bake/remaining.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/checkpoint.hpp"
#include "shprt/scene/builtin.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace shprt {
namespace {

namespace fs = std::filesystem;

TEST(RemainingSpans, AreTheGapsBetweenTheDoneSpansInOrder) {
    using V = std::vector<ReceiverSpan>;
    EXPECT_EQ(remaining_spans(10, 20, {}), (V{{10, 20}}));
    EXPECT_EQ(remaining_spans(10, 20, {{10, 20}}), V{});
    EXPECT_EQ(remaining_spans(10, 20, {{25, 3}, {12, 2}, {0, 11}}),
              (V{{11, 1}, {14, 11}, {28, 2}}));
    // Overlapping, empty and outside spans.
    EXPECT_EQ(remaining_spans(0, 10, {{2, 4}, {3, 2}, {5, 0}, {40, 5}, {9, 100}}),
              (V{{0, 2}, {6, 3}}));
}

class CheckpointTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_path = (fs::temp_directory_path() /
                  ("shprt_checkpoint_" + std::to_string(::getpid()) + "_" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".ckpt"))
                     .string();
        fs::remove(m_path);
    }
    void TearDown() override { fs::remove(m_path); }
    std::string m_path;
};

// Rows of `count` receivers, `floats` each, that tell receivers apart.
std::vector<float> rows(std::size_t first, std::size_t count, std::size_t floats) {
    std::vector<float> r(count * floats);
    for (std::size_t i = 0; i < r.size(); ++i) r[i] = float(first * floats + i) * 0.5f + 1.0f;
    return r;
}

TEST_F(CheckpointTest, RecordsComeBackAndADamagedTailIsDropped) {
    const std::size_t first = 100, count = 50, floats = 3;
    {
        CheckpointFile f = CheckpointFile::create(m_path, 42, first, count, floats, 0);
        for (const ReceiverSpan s : {ReceiverSpan{130, 10}, ReceiverSpan{100, 7}})
            f.append(s.first, s.count, rows(s.first, s.count, floats).data());
        EXPECT_EQ(f.done_receivers(), 17u);
        EXPECT_THROW(CheckpointFile::create(m_path, 42, first, count, floats, 0), Error);
    }
    const auto whole = fs::file_size(m_path);
    // Cut inside the second record: the first is kept, the file cut back after it.
    fs::resize_file(m_path, whole - 5);
    CheckpointFile f = CheckpointFile::resume(m_path, 42, first, count, floats, 0);
    ASSERT_EQ(f.done().size(), 1u);
    EXPECT_EQ(f.done()[0], (ReceiverSpan{130, 10}));
    EXPECT_EQ(fs::file_size(m_path), 64u + 32u + 10u * floats * 4u);

    HostSink sink;
    TransferLayout layout;
    layout.channels = 3;
    layout.K = 1;
    sink.begin(layout, first, count);
    f.replay(sink);
    const std::vector<float> expected = rows(130, 10, floats);
    EXPECT_TRUE(std::equal(expected.begin(), expected.end(), sink.rows().begin() + 30 * 3));
    EXPECT_EQ(sink.rows()[0], 0.0f);  // receiver 100's record was cut off

    // A flipped bit inside the kept record's rows ends the records there too.
    f.append(100, 7, rows(100, 7, floats).data());
    {
        std::fstream io(m_path, std::ios::in | std::ios::out | std::ios::binary);
        io.seekp(64 + 32 + 4);
        io.put('\x7f');
    }
    EXPECT_TRUE(CheckpointFile::resume(m_path, 42, first, count, floats, 0).done().empty());
}

TEST_F(CheckpointTest, AnotherBakesCheckpointIsRefused) {
    { CheckpointFile::create(m_path, 42, 0, 10, 4, 0); }
    EXPECT_NO_THROW(CheckpointFile::resume(m_path, 42, 0, 10, 4, 0));
    for (const auto& [fp, first, count, floats] :
         std::vector<std::tuple<std::uint64_t, std::size_t, std::size_t, std::size_t>>{
             {43, 0, 10, 4}, {42, 1, 10, 4}, {42, 0, 11, 4}, {42, 0, 10, 5}}) {
        try {
            CheckpointFile::resume(m_path, fp, first, count, floats, 0);
            ADD_FAILURE() << "resumed another bake's checkpoint";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
            EXPECT_NE(std::string(e.what()).find("the checkpoint is of another bake"),
                      std::string::npos)
                << e.what();
        }
    }
    std::ofstream(m_path, std::ios::trunc) << "no checkpoint";
    EXPECT_THROW(CheckpointFile::resume(m_path, 42, 0, 10, 4, 0), Error);
}

// Records that overlap, each with valid CRCs (a forged or foreign file; a bake never writes a
// receiver twice), are refused in one line, as `shprt merge` refuses overlapping parts: replayed,
// the later record's rows would replace the earlier's and change the result.
TEST_F(CheckpointTest, OverlappingRecordsAreRefused) {
    const std::size_t floats = 3;
    {
        CheckpointFile f = CheckpointFile::create(m_path, 42, 0, 20, floats, 0);
        f.append(0, 6, rows(0, 6, floats).data());
        f.append(10, 4, rows(10, 4, floats).data());
        std::vector<float> other = rows(4, 4, floats);
        for (float& v : other) v = -v;
        f.append(4, 4, other.data());  // receivers 4 and 5 a second time
    }
    try {
        CheckpointFile::resume(m_path, 42, 0, 20, floats, 0);
        ADD_FAILURE() << "resumed a checkpoint whose records overlap";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::format);
        EXPECT_NE(std::string(e.what()).find(m_path + ": checkpoint records 0 and 2 both hold "
                                                      "receivers [4, 6)"),
                  std::string::npos)
            << e.what();
    }
}

TEST(OrderSpans, FindsTheFirstSharedReceiverAsMergeDoes) {
    const SpanOrder ok = order_spans({{10, 5}, {0, 10}, {15, 0}, {15, 3}});
    EXPECT_EQ(ok.order, (std::vector<std::size_t>{1, 0, 2, 3}));
    EXPECT_FALSE(ok.overlap);
    const SpanOrder bad = order_spans({{0, 10}, {20, 5}, {9, 2}});
    ASSERT_TRUE(bad.overlap);
    EXPECT_EQ(*bad.overlap, (std::pair<std::size_t, std::size_t>{0, 2}));
    // A span inside a long one that an intermediate short one does not reach.
    EXPECT_TRUE(order_spans({{0, 100}, {10, 1}, {50, 2}}).overlap);
}

BakeOptions room_options() {
    BakeOptions o;
    o.K = 9;
    o.samples = 128;
    o.seed = 5;
    o.threads = 2;
    o.chunk_receivers = 256;
    return o;
}

const Mesh& room() {
    static const Mesh mesh = make_builtin("room");
    return mesh;
}

// Whatever spans a killed bake had finished, the resumed bake's rows are the whole bake's.
TEST_F(CheckpointTest, ResumedBakeFromScatteredSpansEqualsTheWholeBake) {
    const Mesh& mesh = room();
    const BakeOptions options = room_options();
    const TransferSet whole = bake(mesh, options);
    const Receivers all = vertex_receivers(mesh);
    const std::size_t V = all.count, floats = whole.layout.floats_per_receiver();
    const std::uint64_t fp = checkpoint_fingerprint(mesh, 0, V, bake_description(options));
    {
        CheckpointFile f = CheckpointFile::create(m_path, fp, 0, V, floats, 0);
        for (const ReceiverSpan s : {ReceiverSpan{V / 2, 300}, ReceiverSpan{17, 40},
                                     ReceiverSpan{V - 5, 5}, ReceiverSpan{1000, 1}}) {
            f.append(s.first, s.count, whole.coeffs.data() + whole.layout.offset(s.first));
        }
    }
    CheckpointFile f = CheckpointFile::resume(m_path, fp, 0, V, floats, 0);
    HostSink host;
    CheckpointSink sink(host, f);
    BakeJob job;
    job.occluders = &mesh;
    job.receivers = all;
    job.sink = &sink;
    std::uint64_t last_done = 0, last_total = 0;
    BakeOptions with_progress = options;
    with_progress.progress = [&](const ProgressInfo& p) {
        last_done = p.done;
        last_total = p.total;
        return true;
    };
    const TransferInfo info = bake_remaining(job, with_progress, f.done());
    EXPECT_EQ(info.layout.K, options.K);
    ASSERT_EQ(host.rows().size(), whole.coeffs.size());
    EXPECT_TRUE(host.rows() == whole.coeffs) << "resumed rows differ from the whole bake's";
    EXPECT_EQ(f.done_receivers(), V);
    EXPECT_GT(last_total, 0u);
    EXPECT_GE(last_done, last_total * 9 / 10);  // the progress ran over the whole range

    // Nothing left: the rows come from the checkpoint alone.
    HostSink again;
    CheckpointFile g = CheckpointFile::resume(m_path, fp, 0, V, floats, 0);
    CheckpointSink sink2(again, g);
    job.sink = &sink2;
    bake_remaining(job, options, g.done());
    EXPECT_TRUE(again.rows() == whole.coeffs);

    BakeOptions interreflected = options;
    interreflected.transfer = TransferKind::interreflected;
    EXPECT_TRUE(resume_unsupported(interreflected).has_value());
    EXPECT_FALSE(resume_unsupported(options).has_value());
}

// The estimate made before a bake is at least the peak the bake then measures (rows included),
// and not wildly more.
TEST(BakeMemoryEstimate, CoversTheMeasuredPeak) {
    for (const char* scene : {"room", "plane", "box_on_plane"}) {
        for (const std::uint32_t samples : {64u, 1024u}) {
            SCOPED_TRACE(std::string(scene) + " S=" + std::to_string(samples));
            const Mesh mesh = make_builtin(scene);
            BakeOptions o;
            o.K = 16;
            o.samples = samples;
            o.threads = 2;
            const TransferSet t = bake(mesh, o);
            const std::uint64_t measured = t.stats.peak_bytes_host;  // rows included
            const std::uint64_t estimate =
                estimate_bake_peak_bytes(mesh.triangle_count(), mesh.vertex_count(), o, true,
                                         bake_bounce_source_count(mesh, o));
            EXPECT_GE(estimate, measured);
            EXPECT_LE(estimate, 3 * measured + (1u << 20));
        }
    }
}

}  // namespace
}  // namespace shprt
