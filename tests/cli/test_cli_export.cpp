// `shprt export` run as a program: a .glb comes out (and --half and --bands shrink it); bad input
// (missing or truncated .shprt, a bad light, a bad extension or --bands, output = input) gives a
// one-line error, exit code 1 and no output file. The glb's content is tested in
// tests/shade/test_gltf_export.cpp, its validity by the Khronos validator (web_gltf_validator).
#include "cli/cli_test.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/shade/glossy.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace shprt {
namespace {

using test_support::expect_one_line_error;

class CliExport : public test_support::CliTest {
protected:
    void SetUp() override {
        CliTest::SetUp();
        m_shprt = (m_dir / "sphere.shprt").string();
        const auto r = shprt("bake builtin:sphere -o '" + m_shprt + "' --coeffs 16 --samples 64");
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    std::string m_shprt;
};

TEST_F(CliExport, WritesAGlbAndHalfAndBandsMakeItSmaller) {
    auto r = shprt("export '" + m_shprt + "' -o '" + out("a.glb") + "' --light sun:0,1,0");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("K=16, float32"));
    EXPECT_EQ(r.err, "");
    std::ifstream in(out("a.glb"), std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    EXPECT_EQ(std::string(magic, 4), "glTF");

    r = shprt("export '" + m_shprt + "' -o '" + out("h.glb") + "' --half");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("int16 normalized"));
    r = shprt("export '" + m_shprt + "' -o '" + out("b.glb") + "' --bands 2");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("K=4"));
    EXPECT_LT(fs::file_size(out("h.glb")), fs::file_size(out("a.glb")));
    EXPECT_LT(fs::file_size(out("b.glb")), fs::file_size(out("h.glb")));
}

// A glossy bake exports its diffuse part t = M·a(n) (glTF carries vectors): the very file that
// exporting that diffuse transfer writes.
TEST_F(CliExport, GlossyMatricesExportTheirDiffuseTransfer) {
    const std::string glossy = (m_dir / "g.shprt").string(), diffuse = (m_dir / "d.shprt").string();
    auto r = shprt("bake builtin:box_on_plane --transfer glossy --bands 3 --samples 64 -o '" +
                   glossy + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const ShprtFile file = read_shprt(glossy);
    write_shprt(diffuse, file.mesh, glossy_to_diffuse(file.mesh, file.transfer));
    r = shprt("export '" + glossy + "' -o '" + out("g.glb") + "' --light sun:0,1,0");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("K=9, float32, custom attributes, the glossy matrices' diffuse transfer"));
    r = shprt("export '" + diffuse + "' -o '" + out("d.glb") + "' --light sun:0,1,0");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(test_support::slurp(out("g.glb")), test_support::slurp(out("d.glb")));
}

TEST_F(CliExport, BadInputIsOneLineAndNoFile) {
    const std::string in = "'" + m_shprt + "'";
    expect_one_line_error(shprt("export missing.shprt -o '" + out("a.glb") + "'"), "missing.shprt");
    expect_one_line_error(shprt("export " + in + " -o '" + out("a.gltf") + "'"), ".glb");
    expect_one_line_error(shprt("export " + in + " -o '" + out("a.glb") + "' --bands 5"),
                          "--bands 5");
    expect_one_line_error(shprt("export " + in + " -o '" + out("a.glb") + "' --bands -1"),
                          "--bands -1");
    expect_one_line_error(shprt("export " + in + " -o '" + out("a.glb") + "' --light nope.hdr"),
                          "nope.hdr");
    expect_one_line_error(
        shprt("export " + in + " -o '" + out("a.glb") + "' --light constant:1e38"), "");
    // A truncated file.
    const std::string bytes = [&] {
        std::ifstream f(m_shprt, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    std::ofstream(m_dir / "cut.shprt", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    expect_one_line_error(
        shprt("export '" + (m_dir / "cut.shprt").string() + "' -o '" + out("a.glb") + "'"),
        "cut.shprt");
    EXPECT_TRUE(out_dir_empty());
    // The output is the input, through a symbolic link: refused before anything is read.
    fs::create_symlink(m_shprt, m_dir / "out" / "link.glb");
    expect_one_line_error(shprt("export " + in + " -o '" + out("link.glb") + "'"),
                          "is the input file");
    EXPECT_EQ(fs::file_size(m_shprt), bytes.size());
}

}  // namespace
}  // namespace shprt
