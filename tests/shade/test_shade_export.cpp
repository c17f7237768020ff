// CSV, NPY and PLY exports of per-vertex shading: each parsed back here, values and vertex order
// checked; bad paths leave no file behind.
#include "shade_test_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/shade/shade_export.hpp"
#include "shprt/shade/tonemap.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

namespace shprt {
namespace {

// A mesh whose vertex order is recognisable (x = vertex index) and a result with distinct values.
struct Fixture {
    Mesh mesh;
    ShadeResult result;
};

Fixture make_fixture() {
    Fixture f;
    f.mesh = make_builtin("sphere");
    const std::size_t V = f.mesh.vertex_count();
    for (std::size_t v = 0; v < V; ++v) {
        const float i = float(v);
        f.mesh.positions[v].x = i;
        f.result.irradiance.push_back({i * 0.5f, 1.0f / (i + 1), 3.25f});
        f.result.radiance.push_back({i * 0.001f, 0.2f + 1e-7f * i, -0.01f * float(v % 3)});
    }
    return f;
}

std::vector<float> columns(const Fixture& f, std::size_t v) {
    const Vec3f p = f.mesh.positions[v], e = f.result.irradiance[v], l = f.result.radiance[v];
    return {p.x, p.y, p.z, e.x, e.y, e.z, l.x, l.y, l.z};
}

TEST(ShadeExport, CsvHasHeaderAndEveryVertexInOrderExactly) {
    test::TempDir dir;
    const Fixture f = make_fixture();
    write_shade(dir.file("out.csv"), f.mesh, f.result);
    std::istringstream in(read_file(dir.file("out.csv")));
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "x,y,z,E_r,E_g,E_b,L_r,L_g,L_b");
    std::size_t v = 0;
    while (std::getline(in, line)) {
        ASSERT_LT(v, f.mesh.vertex_count());
        std::istringstream row(line);
        std::string cell;
        const std::vector<float> want = columns(f, v);
        for (int c = 0; c < 9; ++c) {
            ASSERT_TRUE(std::getline(row, cell, ',')) << "row " << v;
            // 9 significant digits: float32 round-trips bit for bit.
            ASSERT_EQ(std::strtof(cell.c_str(), nullptr), want[c]) << "row " << v << " col " << c;
        }
        EXPECT_FALSE(std::getline(row, cell, ','));
        ++v;
    }
    EXPECT_EQ(v, f.mesh.vertex_count());
}

TEST(ShadeExport, NpyIsAFloat32VByNineArrayInOrder) {
    test::TempDir dir;
    const Fixture f = make_fixture();
    write_shade(dir.file("out.NPY"), f.mesh, f.result);
    const std::string bytes = read_file(dir.file("out.NPY"));
    ASSERT_GE(bytes.size(), 10u);
    EXPECT_EQ(bytes.substr(0, 6), "\x93NUMPY");
    EXPECT_EQ(bytes[6], 1);  // format 1.0
    EXPECT_EQ(bytes[7], 0);
    const std::size_t header_len = std::size_t(static_cast<unsigned char>(bytes[8])) |
                                   std::size_t(static_cast<unsigned char>(bytes[9])) << 8;
    const std::size_t data_start = 10 + header_len;
    EXPECT_EQ(data_start % 64, 0u);
    const std::string header = bytes.substr(10, header_len);
    EXPECT_EQ(header.back(), '\n');
    EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos) << header;
    EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
    EXPECT_NE(header.find("'shape': (" + std::to_string(f.mesh.vertex_count()) + ", 9)"),
              std::string::npos)
        << header;
    ASSERT_EQ(bytes.size() - data_start, f.mesh.vertex_count() * 9 * sizeof(float));
    for (std::size_t v = 0; v < f.mesh.vertex_count(); ++v) {
        float row[9];
        std::memcpy(row, bytes.data() + data_start + v * 9 * sizeof(float), sizeof(row));
        const std::vector<float> want = columns(f, v);
        for (int c = 0; c < 9; ++c) ASSERT_EQ(row[c], want[c]) << v << "," << c;
    }
}

TEST(ShadeExport, PlyCarriesPositionsNormalsDisplayColoursAndFaces) {
    test::TempDir dir;
    const Fixture f = make_fixture();
    const float exposure = 2.0f;
    write_shade(dir.file("out.ply"), f.mesh, f.result, exposure);
    const std::string bytes = read_file(dir.file("out.ply"));
    const std::size_t end = bytes.find("end_header\n");
    ASSERT_NE(end, std::string::npos);
    const std::string header = bytes.substr(0, end);
    EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    const std::string expect_props =
        "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float "
        "ny\n"
        "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "property float irradiance_r\nproperty float irradiance_g\nproperty float irradiance_b\n"
        "property float radiance_r\nproperty float radiance_g\nproperty float radiance_b\n";
    EXPECT_NE(header.find("element vertex " + std::to_string(f.mesh.vertex_count()) + "\n" +
                          expect_props),
              std::string::npos)
        << header;
    EXPECT_NE(header.find("element face " + std::to_string(f.mesh.triangle_count()) +
                          "\nproperty list uchar uint vertex_indices\n"),
              std::string::npos);
    const char* p = bytes.data() + end + std::strlen("end_header\n");
    const std::size_t V = f.mesh.vertex_count();
    ASSERT_EQ(bytes.size() - (p - bytes.data()), V * 51 + f.mesh.triangle_count() * 13);
    for (std::size_t v = 0; v < V; ++v, p += 51) {
        float xyzn[6];
        std::memcpy(xyzn, p, sizeof(xyzn));
        ASSERT_EQ(xyzn[0], f.mesh.positions[v].x);
        ASSERT_EQ(xyzn[2], f.mesh.positions[v].z);
        ASSERT_EQ(xyzn[4], f.mesh.normals[v].y);
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(static_cast<unsigned char>(p[24 + c]),
                      display_encode8(f.result.radiance[v][c], exposure))
                << v;
        float exact[6];  // E and L, linear, without the exposure
        std::memcpy(exact, p + 27, sizeof(exact));
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(exact[c], f.result.irradiance[v][c]) << v;
            ASSERT_EQ(exact[3 + c], f.result.radiance[v][c]) << v;
        }
    }
    for (std::size_t t = 0; t < f.mesh.triangle_count(); ++t, p += 13) {
        ASSERT_EQ(p[0], 3);
        std::uint32_t idx[3];
        std::memcpy(idx, p + 1, sizeof(idx));
        for (int k = 0; k < 3; ++k) ASSERT_EQ(idx[k], f.mesh.triangles[t][k]);
    }
    // What the colours mean, in the header; and the file loads as a scene, vertex for vertex.
    EXPECT_NE(header.find("\ncomment shprt shade: colours are radiance L, filmic tone map, sRGB, "
                          "exposure 2; irradiance_* and radiance_* are E and L, linear floats\n"),
              std::string::npos)
        << header;
    const Mesh back = load_scene(dir.file("out.ply"));
    ASSERT_EQ(back.vertex_count(), V);
    for (std::size_t v = 0; v < V; ++v) ASSERT_EQ(back.positions[v], f.mesh.positions[v]) << v;
    EXPECT_EQ(back.triangles, f.mesh.triangles);
}

TEST(ShadeExport, BadPathsThrowAndLeaveNothing) {
    test::TempDir dir;
    const Fixture f = make_fixture();
    EXPECT_THROW(write_shade(dir.file("out.txt"), f.mesh, f.result), Error);
    EXPECT_THROW(write_shade(dir.file("no_such_dir/out.csv"), f.mesh, f.result), Error);
    ShadeResult short_result = f.result;
    short_result.radiance.pop_back();
    EXPECT_THROW(write_shade(dir.file("out.csv"), f.mesh, short_result), Error);
    EXPECT_THROW(write_shade(dir.file("out.ply"), f.mesh, f.result, 0.0f), Error);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
    EXPECT_EQ(shade_format_for_path("a/b.Csv"), ShadeFormat::csv);
    EXPECT_EQ(shade_format_for_path("b.ply"), ShadeFormat::ply);
    EXPECT_EQ(shade_format_for_path("b.NPZ"), ShadeFormat::npz);
    try {
        shade_format_for_path("result.json");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("result.json"), std::string::npos);
    }
}

// A non-finite result (a light or transfer that overflows float) is an error in every format,
// never an output: no file, and the message names the file and the first such vertex.
TEST(ShadeExport, NonFiniteResultsAreRefusedInEveryFormat) {
    test::TempDir dir;
    const float bad[] = {std::numeric_limits<float>::infinity(),
                         std::numeric_limits<float>::quiet_NaN()};
    for (const float value : bad) {
        for (const bool in_radiance : {false, true}) {
            Fixture f = make_fixture();
            (in_radiance ? f.result.radiance : f.result.irradiance)[7].y = value;
            for (const char* name : {"out.csv", "out.npy", "out.npz", "out.ply"}) {
                try {
                    write_shade(dir.file(name), f.mesh, f.result);
                    ADD_FAILURE() << name << ": a non-finite value was written";
                } catch (const Error& e) {
                    const std::string what = e.what();
                    EXPECT_NE(what.find(dir.file(name)), std::string::npos) << what;
                    EXPECT_NE(what.find("vertex 7"), std::string::npos) << what;
                    EXPECT_NE(what.find("non-finite"), std::string::npos) << what;
                }
            }
        }
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace shprt
