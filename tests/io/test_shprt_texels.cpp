// The .shprt sections of texel-domain transfer ("uvs", "texel_index" and the "texels" metadata)
// and of adaptive refinement ("vertex_parents") round-trip; vertex files stay as they were (no
// UVs stored); the writer refuses an atlas out of order; a file whose texel list is corrupt is
// refused by the reader.
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

std::string temp(const std::string& name) {
    return (fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".shprt"))
        .string();
}

Mesh quad() {
    Mesh m;
    m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}};
    m.normals.assign(4, {0, 1, 0});
    m.albedo.assign(4, {0.5f, 0.5f, 0.5f});
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.source = "test:quad";
    return m;
}

TransferSet texel_transfer(TransferEncoding encoding) {
    TransferSet t;
    t.layout.domain = ReceiverDomain::texel;
    t.layout.K = 4;
    t.layout.encoding = encoding;
    t.samples = 16;
    t.texels.width = 4;
    t.texels.height = 3;
    t.texels.uv_set = 1;
    t.texels.texel = {0, 1, 5, 6, 11};
    t.coeffs.resize(t.layout.floats(5));
    for (std::size_t i = 0; i < t.coeffs.size(); ++i) t.coeffs[i] = 0.125f * float(i);
    return t;
}

TEST(ShprtTexels, TexelTransferRoundTrips) {
    const std::string path = temp("texels");
    for (TransferEncoding enc : {TransferEncoding::f32, TransferEncoding::f16}) {
        const Mesh mesh = quad();
        const TransferSet t = texel_transfer(enc);
        write_shprt(path, mesh, t);
        const ShprtFile f = read_shprt(path);
        EXPECT_EQ(f.transfer.layout, t.layout);
        EXPECT_EQ(f.transfer.texels, t.texels);
        EXPECT_EQ(f.transfer.coeffs, t.coeffs);  // multiples of 1/8 are exact in float16
        EXPECT_EQ(f.mesh.uvs, mesh.uvs);
        EXPECT_FALSE(f.is_part());
        EXPECT_NE(f.metadata_json.find("\"domain\": \"texel\""), std::string::npos);
        EXPECT_NE(shprt_summary(f).find("4x3 image, 5 covered"), std::string::npos);
    }
    fs::remove(path);
}

TEST(ShprtTexels, VertexFilesStoreNoUvsAndRefinedParentsRoundTrip) {
    const std::string path = temp("parents");
    Mesh mesh = quad();
    mesh.positions.push_back({0.5f, 0, 0.5f});
    mesh.normals.push_back({0, 1, 0});
    mesh.albedo.push_back({0.5f, 0.5f, 0.5f});
    mesh.uvs.push_back({0.5f, 0.5f});
    mesh.parents = {{Mesh::kNoParent, Mesh::kNoParent},
                    {Mesh::kNoParent, Mesh::kNoParent},
                    {Mesh::kNoParent, Mesh::kNoParent},
                    {Mesh::kNoParent, Mesh::kNoParent},
                    {0, 2}};
    mesh.triangles = {{0, 1, 4}, {1, 2, 4}, {0, 4, 3}, {4, 2, 3}};
    TransferSet t;
    t.layout.K = 4;
    t.samples = 16;
    t.coeffs.assign(t.layout.floats(5), 0.5f);
    write_shprt(path, mesh, t);
    const ShprtFile f = read_shprt(path);
    EXPECT_TRUE(f.mesh.uvs.empty());  // vertex transfer: no "uvs" section
    EXPECT_EQ(f.mesh.parents, mesh.parents);
    EXPECT_NE(shprt_summary(f).find("1 vertices added by adaptive refinement"), std::string::npos);
    fs::remove(path);
}

TEST(ShprtTexels, WriterRefusesAnAtlasOutOfOrderAndReaderACorruptOne) {
    const std::string path = temp("bad_atlas");
    const Mesh mesh = quad();
    TransferSet t = texel_transfer(TransferEncoding::f32);
    t.texels.texel = {0, 5, 1, 6, 11};
    EXPECT_THROW(write_shprt(path, mesh, t), Error);
    EXPECT_FALSE(fs::exists(path));
    t.texels.texel = {0, 1, 5, 6, 12};  // outside the 4x3 image
    EXPECT_THROW(write_shprt(path, mesh, t), Error);

    // A written file whose texel_index is then swapped (CRC fixed too): the reader's own check.
    t = texel_transfer(TransferEncoding::f32);
    write_shprt(path, mesh, t);
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    // The section holds uint32 0, 1, 5, 6, 11: find it and make it 0, 1, 6, 5, 11.
    const std::string want("\0\0\0\0\1\0\0\0\5\0\0\0\6\0\0\0\13\0\0\0", 20);
    const std::size_t at = bytes.find(want);
    ASSERT_NE(at, std::string::npos);
    std::swap(bytes[at + 8], bytes[at + 12]);
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
    }
    try {
        read_shprt(path);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::format);  // the CRC (or the order check) catches it
    }
    fs::remove(path);
}

}  // namespace
}  // namespace shprt
