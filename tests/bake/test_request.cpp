// The bake request (bake/request.hpp): its one list of refusals, and run() giving the bare bake's
// bits for every receiver set and output — in memory, in a file, streamed, sharded, resumed from
// a checkpoint of a cancelled bake — and refusing a texel bake past its memory limit before
// rasterising it.
#include "shprt/bake/probe_bake.hpp"
#include "shprt/bake/request.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>

namespace shprt {
namespace {

namespace fs = std::filesystem;

class BakeRequestTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("shprt_request_" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
        m_options.K = 9;
        m_options.samples = 64;
        m_options.threads = 2;
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const char* name) const { return (m_dir / name).string(); }
    BakeRequest request() const {
        BakeRequest r;
        r.options = m_options;
        return r;
    }
    static FileOutput file(std::string path) {
        FileOutput f;
        f.path = std::move(path);
        f.write.reproducible = true;
        return f;
    }

    fs::path m_dir;
    BakeOptions m_options;
    const Mesh m_room = make_builtin("box_on_plane");
};

std::string refusal(const BakeRequest& r) { return request_refusal(r).value_or(""); }

TEST_F(BakeRequestTest, TheOneListOfRefusals) {
    EXPECT_EQ(refusal(request()), "");
    BakeRequest r = request();
    r.receivers = TexelGrid{64, 64, 0, std::nullopt};
    r.output = file(path("a.shprt"));
    r.output->stream = true;
    EXPECT_EQ(refusal(r), "--stream does not go with --domain texel");
    r.output->stream = false;
    r.distributed = true;
    EXPECT_EQ(refusal(r), "--mpi does not go with --domain texel");
    r.distributed = false;
    r.checkpoint = CheckpointRequest{path("a.ckpt")};
    EXPECT_NE(refusal(r).find("texel and refined bakes cannot be checkpointed"), std::string::npos);

    BakeRequest ir = request();
    ir.options.transfer = TransferKind::interreflected;
    ir.receivers = VertexShard{0, 2};
    EXPECT_NE(refusal(ir).find("cannot be sharded"), std::string::npos);
    ir.receivers = AllVertices{};
    ir.output = file(path("a.shprt"));
    ir.output->stream = true;
    EXPECT_NE(refusal(ir).find("--stream: interreflected"), std::string::npos);
    ir.output->stream = false;
    ir.distributed = true;
    EXPECT_NE(refusal(ir).find("between MPI ranks"), std::string::npos);
    ir.distributed = false;
    ir.receivers = RefinedVertices{};
    EXPECT_NE(refusal(ir).find("--refine: interreflected"), std::string::npos);
    ir.receivers = AllVertices{};
    ir.checkpoint = CheckpointRequest{path("a.ckpt")};
    EXPECT_NE(refusal(ir).find("--checkpoint: interreflected transfer cannot be checkpointed"),
              std::string::npos);

    BakeRequest mpi = request();
    mpi.distributed = true;
    mpi.receivers = VertexShard{1, 2};
    EXPECT_NE(refusal(mpi).find("the ranks already share the bake"), std::string::npos);
    mpi.receivers = AllVertices{};
    mpi.checkpoint = CheckpointRequest{path("a.ckpt"), true};
    EXPECT_EQ(refusal(mpi), "--resume: an MPI bake cannot be checkpointed yet; bake without MPI");

    // check() throws the same line, and the values out of range.
    try {
        check(mpi);
        ADD_FAILURE() << "check() accepted a refused request";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::unsupported);
    }
    BakeRequest bad = request();
    bad.receivers = VertexShard{2, 2};
    EXPECT_THROW(check(bad), Error);
    bad.receivers = TexelGrid{0, 16, 0, std::nullopt};
    EXPECT_THROW(check(bad), Error);
    bad.receivers = AllVertices{};
    bad.output = file(path("same.shprt"));
    bad.checkpoint = CheckpointRequest{path("same.shprt")};
    EXPECT_THROW(check(bad), Error);
}

TEST_F(BakeRequestTest, InMemoryShardsAndFilesGiveTheBareBakesBits) {
    const TransferSet whole = bake(m_room, m_options);
    const BakeResult memory = run(request(), m_room);
    EXPECT_EQ(memory.transfer.coeffs, whole.coeffs);
    EXPECT_EQ(memory.receivers, m_room.vertex_count());

    BakeRequest shard = request();
    shard.receivers = VertexShard{1, 3};
    const BakeResult part = run(shard, m_room);
    const std::size_t V = m_room.vertex_count(), K = std::size_t(m_options.K);
    ASSERT_EQ(part.first, V / 3);
    ASSERT_EQ(part.transfer.coeffs.size(), part.receivers * K);
    EXPECT_TRUE(std::equal(part.transfer.coeffs.begin(), part.transfer.coeffs.end(),
                           whole.coeffs.begin() + std::ptrdiff_t(part.first * K)));

    for (const bool stream : {false, true}) {
        BakeRequest written = request();
        written.output = file(path(stream ? "s.shprt" : "w.shprt"));
        written.output->stream = stream;
        int before_bake = 0, before_write = 0;
        written.before_bake = [&] { ++before_bake; };
        written.before_write = [&] { ++before_write; };
        const BakeResult r = run(written, m_room);
        EXPECT_TRUE(r.transfer.coeffs.empty()) << "the rows went to the file";
        EXPECT_EQ(before_bake, 1);
        EXPECT_EQ(before_write, 1);
        EXPECT_EQ(read_shprt(written.output->path).transfer.coeffs, whole.coeffs);
    }
}

TEST_F(BakeRequestTest, CancelledCheckpointedBakeResumesToTheSameBits) {
    const Mesh room = make_builtin("room");  // long enough for the progress to be called midway
    BakeRequest r = request();
    r.options.samples = 512;
    r.options.chunk_receivers = 64;  // many chunks, so that some are done before the cancel
    const TransferSet whole = bake(room, r.options);
    r.output = file(path("c.shprt"));
    r.checkpoint = CheckpointRequest{path("c.ckpt")};
    std::uint64_t done_at_cancel = 0;
    r.options.progress = [&](const ProgressInfo& info) {
        if (info.done == 0 || info.done == info.total) return true;
        done_at_cancel = info.done;
        return false;
    };
    try {
        run(r, room);
        ADD_FAILURE() << "the cancelled bake returned";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::cancelled);
        EXPECT_NE(std::string(e.what()).find("receivers are saved in " + path("c.ckpt")),
                  std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(fs::exists(path("c.shprt")));
    ASSERT_TRUE(fs::exists(path("c.ckpt")));
    r.options.progress = {};
    r.checkpoint->resume = true;
    EXPECT_GT(done_at_cancel, 0u);
    run(r, room);
    EXPECT_EQ(read_shprt(path("c.shprt")).transfer.coeffs, whole.coeffs);
    EXPECT_FALSE(fs::exists(path("c.ckpt"))) << "the checkpoint outlived its bake";
}

// A texel bake is held to the memory limit like a vertex bake (issue 41, item 5: it ignored
// --max-memory): refused before it rasterises, with the estimate and the limit in the line.
TEST_F(BakeRequestTest, TexelBakePastTheMemoryLimitIsRefusedFirst) {
    const Mesh room = make_builtin("room");
    BakeRequest r = request();
    r.receivers = TexelGrid{4096, 4096, 0, std::nullopt};
    r.max_memory = 128ull << 20;  // above the coverage image's 96 MiB, below the whole bake's
    r.output = file(path("t.shprt"));
    try {
        run(r, room);
        ADD_FAILURE() << "a 4096x4096 texel bake ran under a 128 MiB limit";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::out_of_memory);
        const std::string line = e.what();
        EXPECT_NE(line.find("texels ("), std::string::npos) << line;
        EXPECT_NE(line.find("more than --max-memory 128.0 MiB"), std::string::npos) << line;
    }
    EXPECT_FALSE(fs::exists(path("t.shprt")));
    // Within the limit it runs, and the file carries the atlas.
    r.receivers = TexelGrid{32, 32, 0, std::nullopt};
    r.max_memory = 1ull << 30;
    const BakeResult ok = run(r, room);
    EXPECT_GT(ok.covered_texels, 0u);
    EXPECT_EQ(ok.info.layout.encoding, TransferEncoding::f16);
    const ShprtFile f = read_shprt(path("t.shprt"));
    EXPECT_EQ(f.transfer.receiver_count(), ok.covered_texels);
    EXPECT_EQ(f.transfer.texels.width, 32);
}

TEST_F(BakeRequestTest, RefinedBakeReturnsItsMesh) {
    BakeRequest r = request();
    r.receivers = RefinedVertices{RefineOptions{0.05, 2 * m_room.vertex_count(), 2}};
    const BakeResult out = run(r, m_room);
    ASSERT_TRUE(out.refined_mesh.has_value());
    EXPECT_GT(out.refined_mesh->vertex_count(), m_room.vertex_count());
    EXPECT_EQ(out.transfer.receiver_count(), out.refined_mesh->vertex_count());
    EXPECT_EQ(out.receivers, out.refined_mesh->vertex_count());
}

}  // namespace
}  // namespace shprt

namespace shprt {
namespace {

// A bake that casts enough rays builds a HIGH-quality Embree scene (bake_tracer_options), chosen
// over the whole receiver set: a shard asks the same as the whole bake, and its rows are the
// whole bake's, bit for bit (box_on_plane, 2 208 triangles: a local S = 2048 casts 2.5 M rays,
// over the 2.2 M threshold; S = 64 does not).
TEST(BakeTracerOptions, ChosenForTheWholeBakeSoShardsTraceTheSameScene) {
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions options;
    options.K = 9;
    options.samples = 2048;
    options.threads = 2;
    options.direction_frame = DirectionFrame::local;
    HostSink sink;
    const Receivers all = vertex_receivers(mesh);
    const BakeJob whole{&mesh, all, &sink, nullptr, nullptr, nullptr};
    const BakeJob shard{&mesh, all.range(300, 400), &sink, nullptr, nullptr, nullptr};
    EXPECT_TRUE(bake_tracer_options(whole, options, 2048).high_quality);
    EXPECT_TRUE(bake_tracer_options(shard, options, 2048).high_quality);
    EXPECT_FALSE(bake_tracer_options(whole, options, 64).high_quality);
    options.direction_frame = DirectionFrame::sphere;  // half its rays are below the horizon
    EXPECT_FALSE(bake_tracer_options(whole, options, 2048).high_quality);
    EXPECT_TRUE(bake_tracer_options(whole, options, 4096).high_quality);
    options.direction_frame = DirectionFrame::local;

    const TransferSet all_rows = bake(mesh, options);
    const TransferSet part = bake(mesh, all.range(300, 400), options);
    const std::size_t row = all_rows.layout.floats_per_receiver();
    ASSERT_EQ(part.coeffs.size(), 400 * row);
    EXPECT_TRUE(std::equal(part.coeffs.begin(), part.coeffs.end(),
                           all_rows.coeffs.begin() + std::ptrdiff_t(300 * row)));
}

// Each bake builds the scenes it traces: visibility on merged coplanar triangles where it casts
// enough rays to pay for the merge, the mesh's own triangles where it needs closest hits
// (interreflected transfer, probes).
TEST(BakeTracerOptions, EachBakeGetsTheScenesItTraces) {
    const Mesh mesh = make_builtin("box_on_plane");  // 2 208 triangles, 1 214 vertices
    BakeOptions options;
    options.K = 9;
    options.direction_frame = DirectionFrame::local;
    const BakeJob direct{&mesh, vertex_receivers(mesh), nullptr, nullptr, nullptr, nullptr};
    EmbreeTracerOptions o = bake_tracer_options(direct, options, 512);  // 622 k rays ≥ 442 k
    EXPECT_TRUE(o.merge_coplanar);
    EXPECT_TRUE(o.blocker_cones);
    EXPECT_FALSE(o.closest_hits);
    o = bake_tracer_options(direct, options, 256);  // 311 k rays: the merge would not pay
    EXPECT_FALSE(o.merge_coplanar);
    EXPECT_FALSE(o.blocker_cones) << "no cones on unmerged triangles";
    EXPECT_FALSE(o.closest_hits);

    options.transfer = TransferKind::interreflected;
    o = bake_tracer_options(direct, options, 512);
    EXPECT_FALSE(o.merge_coplanar) << "its rays are all closest hits";
    EXPECT_FALSE(o.blocker_cones);
    EXPECT_TRUE(o.closest_hits);

    options.transfer = TransferKind::shadowed;
    ProbeGrid grid;
    BakeJob with_probes = direct;
    with_probes.probes = &grid;
    o = bake_tracer_options(with_probes, options, 512);
    EXPECT_TRUE(o.merge_coplanar) << "the receivers' visibility";
    EXPECT_TRUE(o.closest_hits) << "the probes' closest hits";
}

}  // namespace
}  // namespace shprt
