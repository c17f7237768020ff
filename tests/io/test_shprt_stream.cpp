// The streaming writer: rows written through its sink by a bake (in any order, from several
// threads) give the file write_shprt writes for the same rows, float32 and float16, whole or a
// part; a stream that misses rows, repeats them or meets a bad value leaves no file.
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_stream.hpp"
#include "shprt/scene/builtin.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

class IoShprtStream : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("shprt_stream_" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
        m_mesh = make_builtin("box_on_plane");
        m_options.K = 25;
        m_options.samples = 200;
        m_options.threads = 2;
        m_options.chunk_receivers = 37;  // many chunks, finishing in any order
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    // Streams a bake of receivers [first, first + count) into `file`.
    TransferInfo stream(const std::string& file, std::size_t first, std::size_t count,
                        TransferEncoding encoding) {
        TransferInfo description = bake_description(m_options);
        description.layout.encoding = encoding;
        ShprtStreamWriter writer(file, m_mesh, description, first, count);
        const TransferInfo info =
            bake(BakeJob{&m_mesh, vertex_receivers(m_mesh).range(first, count), &writer.sink(),
                         nullptr, nullptr},
                 m_options);
        writer.commit(info);
        return info;
    }

    fs::path m_dir;
    Mesh m_mesh;
    BakeOptions m_options;
};

std::uint64_t transfer_crc(const ShprtFile& f) {
    const nlohmann::json metadata = nlohmann::json::parse(f.metadata_json);
    for (const auto& s : metadata["sections"])
        if (s["name"] == "transfer") return s["crc32"].get<std::uint64_t>();
    return 0;
}

TEST_F(IoShprtStream, StreamedFilesEqualWrittenOnesWholeOrPartFloat32OrFloat16) {
    const std::size_t V = m_mesh.vertex_count();
    for (TransferEncoding encoding : {TransferEncoding::f32, TransferEncoding::f16}) {
        for (const auto& [first, count] : {std::pair<std::size_t, std::size_t>{0, V}, {100, 500}}) {
            const TransferInfo info = stream(path("s.shprt"), first, count, encoding);
            TransferSet rows =
                bake(m_mesh, vertex_receivers(m_mesh).range(first, count), m_options);
            rows.layout.encoding = encoding;
            WriteOptions options;
            options.receiver_first = first;
            write_shprt(path("w.shprt"), m_mesh, rows, options);
            const ShprtFile s = read_shprt_part(path("s.shprt"));
            const ShprtFile w = read_shprt_part(path("w.shprt"));
            EXPECT_EQ(s.receiver_first, first);
            EXPECT_EQ(s.transfer.layout, w.transfer.layout);
            EXPECT_TRUE(s.transfer.coeffs == w.transfer.coeffs)
                << to_string(encoding) << " rows [" << first << ", " << first + count << ")";
            EXPECT_EQ(transfer_crc(s), transfer_crc(w)) << "the combined chunk CRCs";
            EXPECT_EQ(s.transfer.stats.rays_cast, info.stats.rays_cast);
            EXPECT_EQ(s.mesh.positions, w.mesh.positions);
            EXPECT_EQ(s.mesh.triangles, w.mesh.triangles);
        }
    }
}

TEST_F(IoShprtStream, MissingRepeatedOrBadRowsLeaveNoFile) {
    const TransferInfo description = bake_description(m_options);
    const std::size_t row = description.layout.floats_per_receiver();
    std::vector<float> rows(10 * row, 0.5f);
    {
        ShprtStreamWriter writer(path("gap.shprt"), m_mesh, description, 0, 20);
        writer.sink().begin(description.layout, 0, 20);
        writer.sink().write(0, 10, rows.data());
        EXPECT_THROW(writer.commit(description), Error) << "rows 10..19 never written";
    }
    {
        ShprtStreamWriter writer(path("twice.shprt"), m_mesh, description, 0, 20);
        writer.sink().write(0, 10, rows.data());
        writer.sink().write(0, 10, rows.data());
        EXPECT_THROW(writer.commit(description), Error) << "rows 0..9 written twice";
    }
    {
        ShprtStreamWriter writer(path("nan.shprt"), m_mesh, description, 0, 10);
        rows[3 * row + 2] = std::nanf("");
        EXPECT_THROW(writer.sink().write(0, 10, rows.data()), Error);
    }
    {
        ShprtStreamWriter writer(path("k.shprt"), m_mesh, description, 0, 10);
        TransferLayout other = description.layout;
        other.K = 9;
        EXPECT_THROW(writer.sink().begin(other, 0, 10), Error) << "another layout";
    }
    EXPECT_THROW(
        ShprtStreamWriter(path("far.shprt"), m_mesh, description, m_mesh.vertex_count() - 5, 10),
        Error)
        << "rows past the mesh";
    for (const char* name : {"gap.shprt", "twice.shprt", "nan.shprt", "k.shprt", "far.shprt"})
        EXPECT_FALSE(fs::exists(path(name))) << name;
    EXPECT_TRUE(fs::is_empty(m_dir)) << "no temporary file left";
}

}  // namespace
}  // namespace shprt
