// The fast bake (Embree stream tracing + SGEMM over chunks) against the slow references: a
// brute-force ray test over all triangles, the per-sample double-precision projection; and its
// contracts: determinism across thread counts, K that is not a square, progress, cancellation,
// chunk callbacks, statistics, bad options.
#include "bake/bake_test_util.hpp"
#include "bake/twins.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <thread>
#include <vector>

namespace shprt {
namespace {

// Compares coefficient-by-coefficient within the float rounding bound of each coefficient and
// returns the number of vertices where some coefficient differs by more.
std::size_t vertices_beyond_rounding(const TransferSet& fast, const TransferSet& reference,
                                     const DirectionSet& set) {
    EXPECT_EQ(fast.layout.K, reference.layout.K);
    EXPECT_EQ(fast.coeffs.size(), reference.coeffs.size());
    const std::vector<double> bound = test::float_dot_bounds(fast.layout.K, set);
    std::size_t bad = 0;
    for (std::size_t v = 0; v < fast.receiver_count(); ++v) {
        bool ok = true;
        for (int i = 0; i < fast.layout.K; ++i)
            ok =
                ok && std::fabs(double(fast.receiver(v)[i]) - reference.receiver(v)[i]) <= bound[i];
        bad += !ok;
    }
    return bad;
}

const Mesh& room() {
    static const Mesh mesh = make_builtin("room");
    return mesh;
}

TEST(BakeReference, BoxOnPlaneVisibilityEqualsABruteForceRayTest) {
    const Mesh mesh = make_builtin("box_on_plane");
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 11, 128);
    BakeOptions options;
    options.K = 9;
    const TransferSet fast = bake(mesh, options, set);
    const test::BruteForceTracer brute(mesh);
    const TransferSet reference = bake_reference(mesh, options, set, brute);
    EXPECT_EQ(vertices_beyond_rounding(fast, reference, set), 0u)
        << "of " << mesh.vertex_count() << " vertices";
    // Not a vacuous comparison: the box shadows the plane, so some rays are blocked.
    options.transfer = TransferKind::unshadowed;
    const TransferSet open = bake(mesh, options, set);
    EXPECT_GT(vertices_beyond_rounding(open, reference, set), mesh.vertex_count() / 10);
    EXPECT_EQ(fast.stats.rays_cast, reference.stats.rays_cast);
}

TEST(BakeReference, GemmPathEqualsThePerSampleProjectionOnTheRoom) {
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 5, 128);
    BakeOptions options;
    options.K = 25;
    const TransferSet fast = bake(room(), options, set);
    const auto tracer = make_embree_tracer(room());
    const TransferSet reference = bake_reference(room(), options, set, *tracer);
    EXPECT_EQ(vertices_beyond_rounding(fast, reference, set), 0u)
        << "of " << room().vertex_count() << " vertices";
}

TEST(BakeReference, UnshadowedCastsNoRaysAndMatchesTheReference) {
    const Mesh mesh = make_builtin("box_on_plane");
    const DirectionSet set = make_direction_set(SamplerKind::sobol, 2, 512);
    BakeOptions options;
    options.K = 16;
    options.transfer = TransferKind::unshadowed;
    const TransferSet fast = bake(mesh, options, set);
    const test::BruteForceTracer brute(mesh);
    const TransferSet reference = bake_reference(mesh, options, set, brute);
    EXPECT_EQ(fast.stats.rays_cast, 0u);
    EXPECT_EQ(fast.kind, TransferKind::unshadowed);
    EXPECT_EQ(vertices_beyond_rounding(fast, reference, set), 0u);
}

TEST(BakeReference, KThatIsNotASquare) {
    const Mesh mesh = make_builtin("box_on_plane");
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 1, 200);
    const auto tracer = make_embree_tracer(mesh);
    BakeOptions options;
    options.K = 16;
    const TransferSet k16 = bake(mesh, options, set);
    for (int K : {32, 48}) {
        SCOPED_TRACE(K);
        options.K = K;
        const TransferSet fast = bake(mesh, options, set);
        ASSERT_EQ(fast.layout.K, K);
        ASSERT_EQ(fast.coeffs.size(), mesh.vertex_count() * std::size_t(K));
        const TransferSet reference = bake_reference(mesh, options, set, *tracer);
        EXPECT_EQ(vertices_beyond_rounding(fast, reference, set), 0u);
        // The first 16 coefficients are those of the K = 16 bake (the basis is nested).
        const std::vector<double> bound = test::float_dot_bounds(16, set);
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
            for (int i = 0; i < 16; ++i)
                ASSERT_NEAR(fast.receiver(v)[i], k16.receiver(v)[i], 2 * bound[i]);
    }
}

TEST(BakeDeterminism, SameSeedGivesIdenticalBitsWithOneAndTwoThreads) {
    BakeOptions options;
    options.K = 64;
    options.samples = 256;
    options.seed = 42;
    options.threads = 1;
    const TransferSet one = bake(room(), options);
    options.threads = 2;
    const TransferSet two = bake(room(), options);
    const TransferSet again = bake(room(), options);
    options.threads = 3;  // more threads than cores: a different schedule again
    const TransferSet three = bake(room(), options);
    ASSERT_EQ(one.coeffs.size(), two.coeffs.size());
    const std::size_t bytes = one.coeffs.size() * sizeof(float);
    EXPECT_EQ(std::memcmp(one.coeffs.data(), two.coeffs.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(two.coeffs.data(), again.coeffs.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(one.coeffs.data(), three.coeffs.data(), bytes), 0);
    EXPECT_EQ(one.stats.rays_cast, two.stats.rays_cast);
    EXPECT_EQ(one.stats.device_name, "cpu: 1 thread");
    EXPECT_EQ(two.stats.device_name, "cpu: 2 threads");
    // A different seed is a different direction set.
    options.seed = 43;
    const TransferSet other = bake(room(), options);
    EXPECT_NE(std::memcmp(one.coeffs.data(), other.coeffs.data(), bytes), 0);
}

TEST(BakeProgress, ReportsRaysFromTheCallingThreadAndEndsAtTheTotal) {
    BakeOptions options;
    options.K = 16;
    options.samples = 1024;
    options.threads = 2;
    const std::thread::id caller = std::this_thread::get_id();
    std::vector<ProgressInfo> calls;
    bool all_from_caller = true;
    options.progress = [&](const ProgressInfo& info) {
        all_from_caller = all_from_caller && std::this_thread::get_id() == caller;
        calls.push_back(info);
        EXPECT_EQ(info.stage, "bake");
        EXPECT_EQ(info.unit, "rays");
        return true;
    };
    const TransferSet t = bake(room(), options);
    ASSERT_FALSE(calls.empty());
    EXPECT_TRUE(all_from_caller);
    for (std::size_t i = 1; i < calls.size(); ++i) EXPECT_GE(calls[i].done, calls[i - 1].done);
    for (const ProgressInfo& c : calls) EXPECT_LE(c.done, c.total);
    EXPECT_EQ(calls.back().done, t.stats.rays_cast);
    EXPECT_EQ(calls.back().total, t.stats.rays_cast);
}

TEST(BakeProgress, ReturningFalseCancels) {
    BakeOptions options;
    options.K = 16;
    options.samples = 4096;
    int calls = 0;
    std::uint64_t done_at_cancel = 0, total_at_cancel = 0;
    options.progress = [&](const ProgressInfo& info) {
        ++calls;
        done_at_cancel = info.done;
        total_at_cancel = info.total;
        return false;
    };
    try {
        bake(room(), options);
        FAIL() << "a cancelled bake must throw";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
    }
    EXPECT_EQ(calls, 1) << "no more reports after the cancel";
    EXPECT_LT(done_at_cancel, total_at_cancel) << "cancelled before the end, not after";
}

TEST(BakeChunks, TheSinkGetsEveryVertexOnceWithTheFinalCoefficients) {
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions options;
    options.K = 9;
    options.samples = 128;
    options.chunk_receivers = 7;  // odd, so the last chunk is partial
    const TransferSet t = bake(mesh, options);
    for (bool in_place : {false, true}) {
        test::RecordingSink sink;
        sink.offer_host_rows = in_place;  // projected into the sink's rows, or handed over
        bake_into(mesh, options, sink);
        EXPECT_EQ(sink.begins, 1);
        EXPECT_EQ(sink.finishes, 1);
        std::vector<int> seen(mesh.vertex_count(), 0);
        for (const auto& w : sink.writes) {
            EXPECT_LE(w.count, 7u);
            EXPECT_TRUE(w.had_rows);
            for (std::size_t j = 0; j < w.count; ++j) ++seen[w.first + j];
        }
        for (std::size_t v = 0; v < seen.size(); ++v) ASSERT_EQ(seen[v], 1) << "vertex " << v;
        EXPECT_EQ(sink.host.rows(), t.coeffs) << (in_place ? "in place" : "handed over");
    }
}

TEST(BakeChunks, AutomaticChunkSizeDependsOnVerticesAndSamplesOnly) {
    EXPECT_EQ(auto_chunk_receivers(100000, 1024) % 16, 0u);
    EXPECT_LE(auto_chunk_receivers(100000, 1024) * 1024 * sizeof(float), 2u << 20);
    EXPECT_GE(auto_chunk_receivers(100000, 1 << 24), 1u);
    EXPECT_EQ(auto_chunk_receivers(100000, 1 << 24), 1u) << "huge S: memory first";
    EXPECT_GE(auto_chunk_receivers(3, 16), 1u);
    EXPECT_LE(auto_chunk_receivers(10000000, 1), 1024u);
}

TEST(BakeStatsTest, TimeSplitRaysAndMemory) {
    BakeOptions options;
    options.K = 48;
    options.samples = 512;
    options.threads = 2;
    const TransferSet t = bake(room(), options);
    const BakeStats& s = t.stats;
    EXPECT_GT(s.seconds_bvh, 0);
    EXPECT_GT(s.seconds_trace, 0);
    EXPECT_GT(s.seconds_project, 0);
    EXPECT_GE(s.seconds_total, s.seconds_bvh + s.seconds_trace + s.seconds_project);
    EXPECT_GT(s.rays_cast, 0u);
    const std::vector<bool> copied = test::twin_vertices(room(), 512);
    const auto traced = std::uint64_t(std::count(copied.begin(), copied.end(), false));
    EXPECT_LT(traced, room().vertex_count()) << "the room has twins in its chunks";
    EXPECT_EQ(s.rays_cast, traced * 512)
        << "the default local set: every direction above the horizon, each traced once, and "
           "twins copied";
    const std::uint64_t output_bytes = room().vertex_count() * 48 * sizeof(float);
    // The output and the BVH (Embree's allocations, as the tracer reports them) are counted: the
    // scene this bake traces, its merged coplanar triangles (visibility only).
    const Mesh& mesh = room();
    const BakeJob job{&mesh, vertex_receivers(mesh), nullptr, nullptr, nullptr, nullptr};
    const EmbreeTracerOptions traced_scene = bake_tracer_options(job, options, 512);
    EXPECT_TRUE(traced_scene.merge_coplanar);
    EXPECT_FALSE(traced_scene.closest_hits);
    const std::uint64_t bvh_bytes = make_embree_tracer(mesh, traced_scene)->memory_bytes();
    EXPECT_GT(bvh_bytes, merge_coplanar(mesh).triangles.size() * 24u)
        << "Embree holds at least its vertex and index buffers";
    EXPECT_GE(s.peak_bytes_host, output_bytes + bvh_bytes);
    // O(V·K + BVH + chunk·S per thread): never a V×S buffer.
    EXPECT_LT(s.peak_bytes_host, output_bytes + bvh_bytes + 8u * (1u << 20));
    EXPECT_EQ(t.samples, 512);
    EXPECT_EQ(t.sampler, SamplerKind::sobol) << "the default sampler";
    EXPECT_EQ(t.direction_frame, DirectionFrame::local) << "the default frame";
    EXPECT_EQ(t.seed, 1u);
}

template <class F>
void expect_error(ErrorCode code, F&& f) {
    try {
        f();
        ADD_FAILURE() << "expected shprt::Error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), code) << e.what();
        EXPECT_GT(std::strlen(e.what()), 10u);
    }
}

TEST(BakeErrors, BadOptionsThrowWithAClearMessage) {
    const Mesh mesh = make_builtin("plane");
    const auto with = [&](auto change) {
        BakeOptions o;
        o.samples = 16;
        change(o);
        return [&mesh, o] { bake(mesh, o); };
    };
    expect_error(ErrorCode::invalid_argument, with([](BakeOptions& o) { o.K = 0; }));
    expect_error(ErrorCode::invalid_argument, with([](BakeOptions& o) { o.K = 1025; }));
    expect_error(ErrorCode::invalid_argument, with([](BakeOptions& o) { o.samples = 0; }));
    expect_error(ErrorCode::invalid_argument, with([](BakeOptions& o) { o.threads = -1; }));
    if (!query_gpu().available)
        expect_error(ErrorCode::unsupported, with([](BakeOptions& o) { o.device = Device::cuda; }));
    // K = 1024 (32 bands) is allowed.
    BakeOptions big;
    big.K = 1024;
    big.samples = 16;
    EXPECT_EQ(bake(mesh, big).layout.K, 1024);

    BakeOptions o;
    o.samples = 16;
    expect_error(ErrorCode::invalid_argument, [&] { bake(Mesh{}, o); });
    Mesh no_normals = mesh;
    no_normals.normals.pop_back();
    expect_error(ErrorCode::invalid_argument, [&] { bake(no_normals, o); });
    expect_error(ErrorCode::invalid_argument, [&] { bake(mesh, o, DirectionSet{}); });
    const test::BruteForceTracer brute(mesh);
    o.K = 0;
    expect_error(ErrorCode::invalid_argument, [&] {
        bake_reference(mesh, o, make_direction_set(SamplerKind::uniform, 1, 8), brute);
    });
}

TEST(BakeErrors, AutomaticDeviceRunsOnTheCpuWithoutAGpu) {
    if (query_gpu().available) GTEST_SKIP() << "a GPU is present: automatic picks it";
    BakeOptions o;
    o.samples = 64;
    o.device = Device::automatic;
    const TransferSet t = bake(make_builtin("plane"), o);
    EXPECT_EQ(t.stats.device_name.rfind("cpu", 0), 0u) << t.stats.device_name;
}

}  // namespace
}  // namespace shprt
