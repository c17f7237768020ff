// CPCA .shprt files (format version 3): the code is stored instead of the rows and the reader
// rebuilds the same rows; plain files stay version 2.
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/transfer/cpca.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

class ShprtCpca : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("shprt_cpca_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
        m_mesh = make_builtin("box_on_plane");
        BakeOptions o;
        o.transfer = TransferKind::glossy;
        o.K = 9;
        o.samples = 64;
        m_glossy = bake(m_mesh, o);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    fs::path m_dir;
    Mesh m_mesh;
    TransferSet m_glossy;
};

std::uint32_t header_version(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char h[16] = {};
    in.read(reinterpret_cast<char*>(h), sizeof h);
    return std::uint32_t(h[12]) | std::uint32_t(h[13]) << 8 | std::uint32_t(h[14]) << 16 |
           std::uint32_t(h[15]) << 24;
}

TEST_F(ShprtCpca, RoundTripRebuildsTheSameRowsInFloat32AndFloat16) {
    for (bool half : {false, true}) {
        SCOPED_TRACE(half ? "float16" : "float32");
        CpcaOptions o;
        o.clusters = 8;
        o.vectors = 4;
        const CpcaResult r = compress_transfer(m_glossy, m_mesh.normals, o, half);
        const std::string file = path(half ? "h.shprt" : "f.shprt");
        write_shprt(file, m_mesh, r.compressed);
        EXPECT_EQ(header_version(file), kShprtCpcaFormatVersion);
        const ShprtFile back = read_shprt(file);
        EXPECT_EQ(back.transfer.cpca.clusters, 8);
        EXPECT_EQ(back.transfer.cpca.vectors, 4);
        EXPECT_EQ(back.transfer.cpca.cluster, r.compressed.cpca.cluster);
        EXPECT_EQ(back.transfer.coeffs, r.compressed.coeffs);
        EXPECT_EQ(back.transfer.layout, r.compressed.layout);
        const auto meta = nlohmann::json::parse(back.metadata_json);
        EXPECT_EQ(meta["format_version"], kShprtCpcaFormatVersion);
        EXPECT_EQ(meta["cpca"]["clusters"], 8);
        // The file is smaller than the raw rows.
        const std::string raw = path("raw.shprt");
        write_shprt(raw, m_mesh, m_glossy);
        EXPECT_EQ(header_version(raw), kShprtFormatVersion);
        EXPECT_LT(fs::file_size(file), fs::file_size(raw));
    }
}

TEST_F(ShprtCpca, ACodeWithAClusterOutOfRangeIsAFormatError) {
    CpcaOptions o;
    o.clusters = 4;
    o.vectors = 2;
    CpcaResult r = compress_transfer(m_glossy, m_mesh.normals, o, false);
    r.compressed.cpca.cluster[3] = 7;  // the writer stores what it is given; the reader checks
    const std::string file = path("bad.shprt");
    write_shprt(file, m_mesh, r.compressed);
    try {
        read_shprt(file);
        FAIL() << "a cluster index past the clusters should be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::format);
        EXPECT_NE(std::string(e.what()).find("cluster 7"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace shprt
