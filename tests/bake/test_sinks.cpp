// The bake's seams: receivers (a sub-range of the domain) and sinks (host rows, a file region, a
// device buffer where a GPU exists). Each kind of sink, and every sub-range, gives exactly the
// corresponding rows of a whole bake, bit for bit. (The device sink over a sub-range is tested in
// test_gpu_bake.cpp, GpuBake.DeviceSinkOverASubRangeEqualsTheHostRows.)
#include "bake_test_util.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/transfer/sink.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace shprt {
namespace {

BakeOptions options_for_room() {
    BakeOptions o;
    o.K = 25;
    o.samples = 256;
    o.seed = 11;
    o.threads = 2;
    return o;
}

const Mesh& room() {
    static const Mesh mesh = make_builtin("room");
    return mesh;
}

const TransferSet& whole_bake() {
    static const TransferSet t = bake(room(), options_for_room());
    return t;
}

// Rows [first, first + count) of the whole bake.
std::vector<float> rows_of_whole(std::size_t first, std::size_t count) {
    const TransferSet& t = whole_bake();
    return {t.coeffs.begin() + std::ptrdiff_t(t.layout.offset(first)),
            t.coeffs.begin() + std::ptrdiff_t(t.layout.offset(first + count))};
}

TransferInfo bake_range(std::size_t first, std::size_t count, TransferSink& sink,
                        BakeOptions o = options_for_room()) {
    BakeJob job;
    job.occluders = &room();
    job.receivers = vertex_receivers(room()).range(first, count);
    job.sink = &sink;
    return bake(job, o);
}

TEST(BakeSeams, HostSinkOverSubRangesGivesTheWholeBakesRowsBitForBit) {
    const std::size_t V = room().vertex_count();
    // Aligned and unaligned starts, one receiver, the tail, the whole.
    const std::pair<std::size_t, std::size_t> ranges[] = {
        {0, 1000}, {1000, 1000}, {333, 4097}, {V - 1, 1}, {V - 777, 777}, {0, V}, {12345, 1}};
    for (const auto& [first, count] : ranges) {
        HostSink sink;
        const TransferInfo info = bake_range(first, count, sink);
        EXPECT_EQ(sink.first(), first);
        EXPECT_EQ(info.layout, whole_bake().layout);
        ASSERT_EQ(sink.rows().size(), info.layout.floats(count));
        EXPECT_TRUE(sink.rows() == rows_of_whole(first, count))
            << "rows [" << first << ", " << first + count << ") differ from the whole bake";
    }
}

// Shards whose edges cut chunks of the grid, on one thread, against the whole bake on two, with
// a chunk size of the test's choosing (a grid of 100-row chunks) and the automatic one.
TEST(BakeSeams, ShardsInAnyThreadCountGiveTheSameBits) {
    const std::size_t V = room().vertex_count();
    for (const std::size_t chunk : {std::size_t(100), std::size_t(0)}) {
        SCOPED_TRACE("chunk_receivers " + std::to_string(chunk));
        BakeOptions o = options_for_room();
        o.chunk_receivers = chunk;
        const TransferSet whole = bake(room(), o);
        o.threads = 1;
        std::vector<float> joined;
        const std::size_t shards = 3;
        for (std::size_t i = 0; i < shards; ++i) {
            const std::size_t first = V * i / shards, end = V * (i + 1) / shards;
            HostSink sink;
            bake_range(first, end - first, sink, o);
            joined.insert(joined.end(), sink.rows().begin(), sink.rows().end());
        }
        EXPECT_TRUE(joined == whole.coeffs) << "3 shards, 1 thread";
    }
}

TEST(BakeSeams, FileRegionSinkWritesTheRowsWhereTheyBelong) {
    const std::string path =
        (std::filesystem::temp_directory_path() / fmt::format("shprt_sink_{}.bin", ::getpid()))
            .string();
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    ASSERT_GE(fd, 0);
    constexpr std::uint64_t kOffset = 4096 + 3;  // a region inside a larger file, unaligned
    const std::size_t first = 2000, count = 5000;
    FileRegionSink sink(fd, kOffset);
    const TransferInfo info = bake_range(first, count, sink);
    EXPECT_EQ(sink.region_bytes(), info.layout.floats(count) * sizeof(float));
    std::vector<float> back(info.layout.floats(count));
    ASSERT_EQ(::pread(fd, back.data(), back.size() * sizeof(float), off_t(kOffset)),
              ssize_t(back.size() * sizeof(float)));
    ::close(fd);
    std::remove(path.c_str());
    EXPECT_TRUE(back == rows_of_whole(first, count));

    FileRegionSink f16(fd, 0);
    TransferLayout half = info.layout;
    half.encoding = TransferEncoding::f16;
    EXPECT_THROW(f16.begin(half, 0, 1), Error) << "a file region holds float32 rows";
}

TEST(BakeSeams, BadJobsAreRefusedAtTheBoundary) {
    HostSink sink;
    const Receivers all = vertex_receivers(room());
    EXPECT_THROW(all.range(0, 0), Error);
    EXPECT_THROW(all.range(all.total, 1), Error);
    EXPECT_THROW(all.range(10, all.total), Error);
    BakeJob job;
    job.occluders = &room();
    job.receivers = all;
    EXPECT_THROW(bake(job, options_for_room()), Error) << "no sink";
    job.sink = &sink;
    job.receivers.count = 0;
    EXPECT_THROW(bake(job, options_for_room()), Error) << "an empty range";
    job.receivers = all;
    BakeOptions o = options_for_room();
    o.device_index = -1;
    EXPECT_THROW(bake(job, o), Error);
    // A device buffer cannot be filled by the CPU bake.
    float dummy = 0;
    DeviceSink device(&dummy, 1u << 30);
    job.sink = &device;
    try {
        bake(job, options_for_room());
        ADD_FAILURE() << "a CPU bake into a device sink must fail";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::unsupported) << e.what();
    }
}

}  // namespace
}  // namespace shprt
