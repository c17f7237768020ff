// The .shprt file with interreflected transfer: the optional "transfer_direct" section (before
// "transfer", one channel per receiver, in the transfer's precision) and the "interreflection"
// metadata round-trip; a file without a direct part has no such section; a direct part of the
// wrong size is refused by the writer.
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

Mesh fan() {
    Mesh mesh;
    for (int i = 0; i < 10; ++i) {
        mesh.positions.push_back({float(i % 5), 0.0f, float(i / 5)});
        mesh.normals.push_back({0.0f, 1.0f, 0.0f});
        mesh.albedo.push_back({0.5f, 0.25f, 0.125f});
    }
    for (std::uint32_t i = 1; i + 1 < 10; ++i) mesh.triangles.push_back({0, i, i + 1});
    mesh.source = "test:fan";
    return mesh;
}

TransferSet interreflected(std::size_t V, int K) {
    TransferSet t;
    t.kind = TransferKind::interreflected;
    t.layout.K = K;
    t.layout.channels = 3;
    t.samples = 64;
    t.seed = 5;
    t.coeffs.resize(t.layout.floats(V));
    for (std::size_t i = 0; i < t.coeffs.size(); ++i) t.coeffs[i] = 0.25f * float(i % 17);
    t.direct.resize(V * std::size_t(K));
    for (std::size_t i = 0; i < t.direct.size(); ++i) t.direct[i] = 0.5f * float(i % 13);
    InterreflectionInfo& ir = t.interreflection;
    ir.bounces = 7;
    ir.converge = true;
    ir.converged = true;
    ir.tolerance = 1e-4;
    ir.last_change = 5e-5;
    ir.albedo_source = "vertex colours";
    ir.operator_nnz = 123;
    ir.operator_bytes = 4567;
    ir.operator_rays = 890;
    return t;
}

class ShprtInterreflected : public ::testing::Test {
protected:
    void SetUp() override {
        m_path =
            (fs::temp_directory_path() / ("shprt_io_ir_" + std::to_string(::getpid()) + ".shprt"))
                .string();
    }
    void TearDown() override { fs::remove(m_path); }
    std::string m_path;
};

TEST_F(ShprtInterreflected, DirectPartAndMetadataRoundTrip) {
    const Mesh mesh = fan();
    for (TransferEncoding encoding : {TransferEncoding::f32, TransferEncoding::f16}) {
        TransferSet t = interreflected(mesh.vertex_count(), 4);
        t.layout.encoding = encoding;
        write_shprt(m_path, mesh, t);
        const ShprtFile f = read_shprt(m_path);
        EXPECT_EQ(f.transfer.kind, TransferKind::interreflected);
        EXPECT_EQ(f.transfer.coeffs, t.coeffs);  // every value is exact in float16 too
        EXPECT_EQ(f.transfer.direct, t.direct);
        const InterreflectionInfo& ir = f.transfer.interreflection;
        EXPECT_EQ(ir.bounces, 7);
        EXPECT_TRUE(ir.converge);
        EXPECT_TRUE(ir.converged);
        EXPECT_EQ(ir.tolerance, 1e-4);
        EXPECT_EQ(ir.albedo_source, "vertex colours");
        EXPECT_EQ(ir.operator_nnz, 123u);
        EXPECT_EQ(ir.operator_bytes, 4567u);
        EXPECT_EQ(ir.operator_rays, 890u);
        EXPECT_NE(f.metadata_json.find("\"transfer_direct\""), std::string::npos);
        // The direct part as a shadowed set of its own.
        const TransferSet d = f.transfer.direct_only();
        EXPECT_EQ(d.layout.channels, 1);
        EXPECT_EQ(d.coeffs, t.direct);
        EXPECT_NO_THROW(d.check(mesh));
    }
}

TEST_F(ShprtInterreflected, NoDirectPartNoSection) {
    const Mesh mesh = fan();
    TransferSet t = interreflected(mesh.vertex_count(), 4);
    t.direct.clear();
    write_shprt(m_path, mesh, t);
    const ShprtFile f = read_shprt(m_path);
    EXPECT_TRUE(f.transfer.direct.empty());
    EXPECT_EQ(f.metadata_json.find("\"transfer_direct\""), std::string::npos);
    EXPECT_THROW((void)f.transfer.direct_only(), Error);
}

TEST_F(ShprtInterreflected, WrongSizedDirectPartIsRefused) {
    const Mesh mesh = fan();
    TransferSet t = interreflected(mesh.vertex_count(), 4);
    t.direct.pop_back();
    EXPECT_THROW(write_shprt(m_path, mesh, t), Error);
    EXPECT_FALSE(fs::exists(m_path));
}

}  // namespace
}  // namespace shprt
