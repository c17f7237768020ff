// GPU bakes in passes (bake/gpu.hpp, bake/session.hpp): the error-bounded bake's segments and a
// bake session's passes on the device. Labelled `gpu`; without a CUDA device each test skips with
// the reason query_gpu() gives (so on this project's machines they are unverified on hardware).
#include "bake_test_util.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/bake/session.hpp"
#include "shprt/scene/builtin.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace shprt {
namespace {

void skip_without_gpu() {
    const GpuInfo gpu = query_gpu();
    if (!gpu.available) GTEST_SKIP() << gpu.reason;
}

TEST(GpuBake, ErrorBoundedStopsWhereTheCpuBoundStops) {
    skip_without_gpu();
    if (::testing::Test::IsSkipped()) return;
    const Mesh mesh = make_builtin("leaky_room");
    BakeOptions o;
    o.K = 16;
    o.direction_frame = DirectionFrame::local;
    o.target_error = 0.02;
    o.max_samples = 2048;
    const TransferSet cpu = bake(mesh, o);
    o.device = Device::cuda;
    const TransferSet gpu = bake(mesh, o);
    ASSERT_EQ(gpu.coeffs.size(), cpu.coeffs.size());
    ASSERT_EQ(gpu.receiver_samples.size(), cpu.receiver_samples.size());
    ASSERT_EQ(gpu.receiver_error.size(), cpu.receiver_error.size());
    EXPECT_EQ(gpu.target_error, 0.02);
    const std::size_t V = cpu.receiver_count(), F = cpu.layout.floats_per_receiver();
    std::size_t same = 0, close = 0;
    for (std::size_t v = 0; v < V; ++v) {
        if (gpu.receiver_samples[v] != cpu.receiver_samples[v]) continue;
        ++same;
        double diff = 0, scale = 0;
        for (std::size_t i = 0; i < F; ++i) {
            diff = std::max(diff, std::fabs(double(gpu.coeffs[v * F + i]) - cpu.coeffs[v * F + i]));
            scale = std::max(scale, std::fabs(double(cpu.coeffs[v * F + i])));
        }
        close += diff <= 1e-4 * std::max(scale, 1e-3) ? 1 : 0;
    }
    std::printf(
        "[ GPU vs CPU error bound ] leaky_room K=16 E=0.02: %zu of %zu stop alike, %zu of "
        "them within 1e-4; rays %llu vs %llu\n",
        same, V, close, (unsigned long long)gpu.stats.rays_cast,
        (unsigned long long)cpu.stats.rays_cast);
    EXPECT_GE(double(same), 0.99 * double(V));
    EXPECT_GE(double(close), 0.99 * double(same));
    EXPECT_NEAR(double(gpu.stats.rays_cast), double(cpu.stats.rays_cast),
                0.02 * double(cpu.stats.rays_cast));
}

TEST(GpuBake, ASessionKeepsItsBvhAcrossPassesAndBakesTheWholeBakesRows) {
    // Issue 39 item 3: a GPU session builds and uploads the BVH on its first pass and keeps both
    // for the next ones (bake_gpu.cpp, GpuOccluders), for fixed-S and error-bounded passes alike.
    skip_without_gpu();
    if (::testing::Test::IsSkipped()) return;
    const Mesh mesh = make_builtin("leaky_room");
    for (const double target : {0.0, 0.03}) {
        SCOPED_TRACE(target);
        BakeOptions o;
        o.K = 16;
        o.samples = 256;
        o.target_error = target;
        o.max_samples = target > 0 ? 1024 : 0;
        o.device = Device::cuda;
        const TransferSet want = bake(mesh, o);
        BakeJob job;
        job.occluders = &mesh;
        job.receivers = vertex_receivers(mesh);
        BakeSession session(job, o);
        const std::size_t V = job.receivers.total, cut = V / 3 + 5;
        std::vector<float> rows;
        std::vector<double> bvh_seconds;
        for (const auto& [first, count] :
             {std::pair{std::size_t(0), cut}, std::pair{cut, V - cut}}) {
            HostSink sink;
            BakeJob part;
            part.receivers = job.receivers.range(first, count);
            part.sink = &sink;
            bvh_seconds.push_back(session.bake(part).stats.seconds_bvh);
            rows.insert(rows.end(), sink.rows().begin(), sink.rows().end());
        }
        EXPECT_GT(bvh_seconds[0], 0.0) << "the first pass builds the BVH";
        EXPECT_EQ(bvh_seconds[1], 0.0) << "the second pass uses the kept one";
        ASSERT_EQ(rows.size(), want.coeffs.size());
        double worst = 0, scale = 0;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            worst = std::max(worst, std::fabs(double(rows[i]) - want.coeffs[i]));
            scale = std::max(scale, std::fabs(double(want.coeffs[i])));
        }
        EXPECT_LE(worst, 1e-5 * scale) << "two passes give the one bake's rows";
    }
}

}  // namespace
}  // namespace shprt
