// The bake session (bake/session.hpp): passes over ranges give the whole bake's bits, and an
// error-bounded session asked for more samples goes on from its sums, casting each ray once.
#include "bake_test_util.hpp"

#include "shprt/bake/session.hpp"
#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace shprt;

namespace {

// leaky_room: overlapping wall panels, parts through the floor, interpenetrating furniture.
BakeOptions bounded_options(DirectionFrame frame) {
    BakeOptions o = test::small_chunked_options();
    o.direction_frame = frame;
    o.target_error = 0.03;
    o.max_samples = 1024;
    return o;
}

BakeJob whole_job(const Mesh& mesh, TransferSink* sink) {
    BakeJob job;
    job.occluders = &mesh;
    job.receivers = vertex_receivers(mesh);
    job.sink = sink;
    return job;
}

}  // namespace

TEST(BakeSession, BakeToGoesOnFromTheLastCapAndCastsEachRayOnce) {
    const Mesh mesh = make_builtin("leaky_room");
    for (const DirectionFrame frame : {DirectionFrame::local, DirectionFrame::sphere}) {
        SCOPED_TRACE(frame == DirectionFrame::local ? "local" : "sphere");
        const BakeOptions options = bounded_options(frame);
        BakeSession session(whole_job(mesh, nullptr), options);
        std::uint64_t rays_alone = 0;
        for (const std::uint32_t cap : {128u, 512u, 1024u}) {
            SCOPED_TRACE(cap);
            HostSink sink;
            const TransferInfo info = session.bake_to(cap, sink);
            BakeOptions alone = options;
            alone.max_samples = cap;
            const TransferSet want = bake(mesh, alone);
            EXPECT_EQ(sink.rows(), want.coeffs) << "bake()'s rows with max_samples = cap";
            TransferSet got;
            sink.take_estimates(got);
            EXPECT_EQ(got.receiver_samples, want.receiver_samples);
            EXPECT_EQ(got.receiver_error, want.receiver_error);
            EXPECT_EQ(info.samples, int(cap));
            rays_alone = want.stats.rays_cast;
        }
        // Every ray once: the three rounds together cast what the last bake alone casts.
        EXPECT_EQ(session.rays_cast(), rays_alone);
        EXPECT_GT(rays_alone, 0u);
    }
}

TEST(BakeSession, PassesOverRangesAreTheWholeBakesRows) {
    const Mesh mesh = make_builtin("leaky_room");
    BakeOptions options = test::small_chunked_options();
    options.direction_frame = DirectionFrame::local;
    const TransferSet want = bake(mesh, options);
    BakeSession session(whole_job(mesh, nullptr), options);
    const Receivers all = vertex_receivers(mesh);
    const std::size_t V = all.total, cut = V / 3 + 5;  // not on a chunk's edge
    std::vector<float> rows;
    std::uint64_t rays = 0;
    for (const auto& [first, count] : {std::pair{std::size_t(0), cut}, std::pair{cut, V - cut}}) {
        HostSink sink;
        BakeJob part;
        part.receivers = all.range(first, count);
        part.sink = &sink;
        rays += session.bake(part).stats.rays_cast;
        rows.insert(rows.end(), sink.rows().begin(), sink.rows().end());
    }
    EXPECT_EQ(rows, want.coeffs);
    EXPECT_EQ(rays, want.stats.rays_cast);
    EXPECT_EQ(session.rays_cast(), rays);
}

// The CLI's error-bounded bake (bake_in_rounds): breadth first, so that after the first round
// every receiver has an estimate and each round's stage reports the estimated error of all of
// them, falling; the rows, estimates and rays are one pass's, bit for bit.
TEST(BakeSession, InRoundsGivesOnePassRowsWithTheErrorFallingRoundByRound) {
    const Mesh mesh = make_builtin("leaky_room");
    BakeOptions options = bounded_options(DirectionFrame::local);
    options.max_samples = 4096;  // rounds of 256, 1024 and 4096 samples
    options.target_error = 0.01;
    ASSERT_EQ(error_bound_rounds(options), (std::vector<std::uint32_t>{256, 1024, 4096}));
    HostSink one_pass;
    const TransferInfo want = bake(whole_job(mesh, &one_pass), options);

    struct Report {
        std::string stage;
        std::uint64_t done, total;
        double p99, over;
    };
    std::vector<Report> reports;
    const ProgressFn record = [&](const ProgressInfo& p) {
        reports.push_back({std::string(p.stage), p.done, p.total, p.error_p99, p.over_target});
        return true;
    };
    HostSink sink;
    BakeSession session(whole_job(mesh, nullptr), options);
    const TransferInfo got = session.bake_in_rounds(sink, record);
    EXPECT_EQ(sink.rows(), one_pass.rows());
    TransferSet a, b;
    sink.take_estimates(a);
    one_pass.take_estimates(b);
    EXPECT_EQ(a.receiver_samples, b.receiver_samples);
    EXPECT_EQ(a.receiver_error, b.receiver_error);
    EXPECT_EQ(got.samples, 4096);
    EXPECT_EQ(got.stats.rays_cast, want.stats.rays_cast) << "every ray once";
    EXPECT_EQ(session.rays_cast(), want.stats.rays_cast);

    // Each round's stage, in order, opened by a report of nothing done, and its last report.
    std::vector<Report> last;
    for (const Report& r : reports) {
        if (last.empty() || last.back().stage != r.stage) {
            EXPECT_EQ(r.done, 0u) << r.stage << ": a round's first report is its start";
            EXPECT_GT(r.total, 0u) << r.stage << ": never a total of 0 (callers divide)";
            last.push_back(r);
        } else {
            last.back() = r;
        }
    }
    ASSERT_EQ(last.size(), 3u) << "leaky_room has receivers over E = 0.01 at 1024 samples";
    EXPECT_EQ(last[0].stage, "bake");
    EXPECT_EQ(last[1].stage, "≤ 1024 samples");
    EXPECT_EQ(last[2].stage, "≤ 4096 samples");
    for (std::size_t r = 1; r < last.size(); ++r) {
        SCOPED_TRACE(last[r].stage);
        EXPECT_LT(last[r].p99, last[r - 1].p99) << "the 99th percentile falls";
        EXPECT_LT(last[r].over, last[r - 1].over) << "fewer receivers over E";
    }
    EXPECT_GT(last[0].over, 0.5) << "at 256 samples most receivers are over 0.01";
    // The last round's share over E is the file's.
    std::size_t over = 0;
    for (float e : a.receiver_error) over += double(e) > options.target_error ? 1 : 0;
    EXPECT_DOUBLE_EQ(last[2].over, double(over) / double(a.receiver_error.size()));
}

TEST(BakeSession, RefusesWhatItCannotDo) {
    const Mesh mesh = make_builtin("box_on_plane");
    const Mesh other = make_builtin("plane");
    HostSink sink;
    BakeSession fixed(whole_job(mesh, nullptr), test::small_chunked_options());
    EXPECT_THROW(fixed.bake_to(128, sink), Error) << "no bound";
    BakeJob elsewhere = whole_job(other, &sink);
    elsewhere.receivers = vertex_receivers(mesh);
    EXPECT_THROW(fixed.bake(elsewhere), Error) << "another scene's occluders";
    EXPECT_THROW(fixed.bake(whole_job(mesh, nullptr)), Error) << "no sink";

    BakeSession bounded(whole_job(mesh, nullptr), bounded_options(DirectionFrame::local));
    EXPECT_THROW(bounded.bake_to(100, sink), Error) << "not a power of two";
    EXPECT_THROW(bounded.bake_to(2048, sink), Error) << "over max_samples";
    EXPECT_THROW(bounded.bake_to(32, sink), Error) << "under the first prefix";
    EXPECT_THROW(fixed.bake_in_rounds(sink), Error) << "no bound";
    bounded.bake_to(512, sink);
    EXPECT_THROW(bounded.bake_in_rounds(sink), Error) << "after a bake_to";
    try {
        bounded.bake_to(256, sink);
        FAIL() << "a smaller cap than the last";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("only adds samples"), std::string::npos) << e.what();
    }
}
