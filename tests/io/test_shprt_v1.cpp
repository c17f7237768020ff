// Version 1 files, written by shprt 0.1.0 before the transfer layout existed (commit ca44670,
// committed as tests/data/shprt_v1/), still read with today's reader: their layout defaults to
// per-vertex vectors, their optional section is found by name, and their coefficients are those
// today's bake gives for the same options bit for bit.
//   box_on_plane_k9.shprt:        shprt bake builtin:box_on_plane --coeffs 9 --samples 256
//                                 --seed 7 (the sampler was the paper's uniform set then)
//   red_triangle_k16_half.shprt:  shprt bake tests/data/scene/red_triangle.obj --coeffs 16
//                                 --samples 128 --half --transfer unshadowed (has source_vertex)
#include "shprt/bake/bake.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

const std::string kDir = std::string(SHPRT_TEST_DATA_DIR) + "/shprt_v1/";

TEST(IoShprtV1, ABakedFileReadsWithItsLayoutAndTheSameBitsAsTodaysBake) {
    const ShprtFile f = read_shprt(kDir + "box_on_plane_k9.shprt");
    EXPECT_EQ(nlohmann::json::parse(f.metadata_json)["format_version"], 1);
    const TransferSet& t = f.transfer;
    EXPECT_EQ(t.layout.domain, ReceiverDomain::vertex);
    EXPECT_EQ(t.layout.shape, TransferShape::vector);
    EXPECT_EQ(t.layout.encoding, TransferEncoding::f32);
    EXPECT_EQ(t.layout.K, 9);
    EXPECT_EQ(t.layout.channels, 1);
    EXPECT_EQ(t.kind, TransferKind::shadowed);
    EXPECT_EQ(t.sampler, SamplerKind::uniform);
    EXPECT_EQ(t.samples, 256);
    EXPECT_EQ(t.seed, 7u);
    EXPECT_EQ(f.mesh.source, "builtin:box_on_plane");
    EXPECT_TRUE(f.mesh.source_vertex.empty());
    ASSERT_EQ(t.receiver_count(), f.mesh.vertex_count());
    EXPECT_NO_THROW(t.check(f.mesh));

    BakeOptions o;
    o.K = 9;
    o.samples = 256;
    o.seed = 7;
    o.sampler = SamplerKind::uniform;
    o.direction_frame = DirectionFrame::sphere;  // the default when the file was made
    // The same rows to the last bits of float32, not the same bits: the file was baked on
    // another CPU, and OpenBLAS's SGEMM kernel (chosen by CPU) rounds differently on each
    // (include/shprt/bake/bake.hpp, "Determinism").
    const TransferSet today = bake(make_builtin("box_on_plane"), o);
    ASSERT_EQ(today.coeffs.size(), t.coeffs.size());
    float largest = 0, worst = 0;
    for (std::size_t i = 0; i < t.coeffs.size(); ++i) {
        largest = std::max(largest, std::abs(t.coeffs[i]));
        worst = std::max(worst, std::abs(today.coeffs[i] - t.coeffs[i]));
    }
    EXPECT_GT(largest, 0.1f);
    EXPECT_LE(worst, 1e-6f * largest) << "a bake with the same options gives the same rows";
}

TEST(IoShprtV1, OptionalSectionAndFloat16ReadAndRewriteAsVersion2) {
    const ShprtFile f = read_shprt(kDir + "red_triangle_k16_half.shprt");
    const TransferSet& t = f.transfer;
    EXPECT_EQ(t.layout.encoding, TransferEncoding::f16);
    EXPECT_EQ(t.kind, TransferKind::unshadowed);
    EXPECT_EQ(t.layout.K, 16);
    ASSERT_EQ(f.mesh.vertex_count(), 3u);
    EXPECT_EQ(f.mesh.source_vertex.size(), 3u) << "found by name, not by counting sections";

    const std::string again =
        (std::filesystem::temp_directory_path() / "shprt_v1_rewritten.shprt").string();
    write_shprt(again, f.mesh, t);
    const ShprtFile g = read_shprt(again);
    std::filesystem::remove(again);
    EXPECT_EQ(nlohmann::json::parse(g.metadata_json)["format_version"], kShprtFormatVersion);
    EXPECT_EQ(g.transfer.layout, t.layout);
    EXPECT_TRUE(g.transfer.coeffs == t.coeffs) << "float16 values survive a second round trip";
    EXPECT_EQ(g.mesh.source_vertex, f.mesh.source_vertex);
}

}  // namespace
}  // namespace shprt
