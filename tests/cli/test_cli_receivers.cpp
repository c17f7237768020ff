// `shprt bake --domain texel` and `shprt bake --refine` run as a program: the files they write
// (texel atlas, refined mesh with parents), `shade` of a texel file as an H×W×3 .npy with NaN
// outside the charts, `export` of its coefficient planes as EXR, the budget warning, and the
// refusals (no UVs, bad options, options that do not go together) as one line on stderr.
#include "shprt/config.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"

#include "cli/cli_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

using test_support::expect_one_line_error;

class CliReceivers : public test_support::CliTest {};

TEST_F(CliReceivers, TexelBakeShadeExport) {
    const std::string file = (m_dir / "t.shprt").string();
    auto r = shprt(
        "bake builtin:quad_box --domain texel --resolution 32x16 --samples 64 "
        "--coeffs 4 -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("texels: 32x16"));
    const ShprtFile f = read_shprt(file);
    EXPECT_EQ(f.transfer.layout.domain, ReceiverDomain::texel);
    EXPECT_EQ(f.transfer.layout.encoding, TransferEncoding::f16);  // the texel default
    EXPECT_EQ(f.transfer.texels.width, 32);
    EXPECT_EQ(f.transfer.texels.height, 16);
    EXPECT_EQ(f.transfer.receiver_count(), f.transfer.texels.texel.size());
#if SHPRT_HAS_RENDER
    const std::string npy = (m_dir / "e.npy").string();
    r = shprt("shade '" + file + "' --light constant -o '" + npy + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string bytes = test_support::slurp(npy);
    EXPECT_NE(bytes.find("'shape': (16, 32, 3)"), std::string::npos);
    const std::size_t data = bytes.size() - 16 * 32 * 3 * 4;
    std::size_t nan = 0;
    for (std::size_t i = 0; i < 16 * 32 * 3; ++i) {
        float v;
        std::memcpy(&v, bytes.data() + data + 4 * i, 4);
        nan += std::isnan(v);
    }
    EXPECT_EQ(nan, 3 * (16 * 32 - f.transfer.texels.texel.size()));
    const std::string exr = (m_dir / "c.exr").string();
    r = shprt("export '" + file + "' -o '" + exr + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(test_support::slurp(exr), ::testing::HasSubstr("sh003.Y"));
    expect_one_line_error(
        shprt("shade '" + file + "' --light constant -o '" + (m_dir / "e.csv").string() + "'"),
        ".npy (H x W x 3), .exr or .png");
#endif
    // The standard images: one RGBA image per 4 coefficients (K = 4, grey: one), a sidecar.
    r = shprt("export '" + file + "' -o '" + (m_dir / "i.png").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("-> 1 RGBA PNG images"));
    EXPECT_TRUE(std::filesystem::exists(m_dir / "i_Y000.png"));
    EXPECT_THAT(test_support::slurp((m_dir / "i.json").string()),
                ::testing::HasSubstr("\"encoding\": \"png16_unorm\""));
    r = shprt("export '" + file + "' -o '" + (m_dir / "s.exr").string() +
              "' --attributes standard");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(m_dir / "s_Y000.exr"));
    EXPECT_TRUE(std::filesystem::exists(m_dir / "s.json"));
}

// CPCA of a texel file: the error report is measured at the texels (their normals from the
// atlas), the compressed file keeps the atlas, and a full-rank code rebuilds the rows.
TEST_F(CliReceivers, TexelFilesCompress) {
    const std::string file = (m_dir / "t.shprt").string(), cpca = (m_dir / "c.shprt").string();
    auto r = shprt(
        "bake builtin:quad_box --domain texel --resolution 16 --samples 64 --coeffs 4 "
        "--float32 -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const ShprtFile f = read_shprt(file);
    r = shprt("compress '" + file + "' -o '" + cpca + "' --cpca 1,4");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr(" B/texel (raw float32: 16 B/texel"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("worst texels: "));
    const ShprtFile c = read_shprt(cpca);
    EXPECT_EQ(c.transfer.texels, f.transfer.texels);
    EXPECT_EQ(c.transfer.cpca.clusters, 1);
    ASSERT_EQ(c.transfer.coeffs.size(), f.transfer.coeffs.size());
    for (std::size_t i = 0; i < f.transfer.coeffs.size(); ++i)
        ASSERT_NEAR(c.transfer.coeffs[i], f.transfer.coeffs[i], 1e-5) << i;
    const std::size_t texels = f.transfer.texels.texel.size();
    expect_one_line_error(shprt("compress '" + file + "' -o '" + cpca + "' --cpca " +
                                std::to_string(texels + 1) + ",2"),
                          std::to_string(texels) + " texels (at most one per texel)");
}

TEST_F(CliReceivers, RefineWritesTheRefinedMeshAndWarnsAtTheBudget) {
    const std::string file = (m_dir / "r.shprt").string();
    auto r = shprt(
        "bake builtin:box_on_plane --refine 0.001 --max-vertices 1300 --samples 64 "
        "--coeffs 4 -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("refined: 1214 -> 1300 vertices"));
    EXPECT_THAT(r.err, ::testing::HasSubstr("shprt: warning: refinement stopped at --max-vertices "
                                            "1300"));
    // ... and says that this is the budget doing its job, not a failure (issue 40).
    EXPECT_THAT(r.err, ::testing::HasSubstr("as asked (a larger --max-vertices refines further)"));
    const ShprtFile f = read_shprt(file);
    EXPECT_EQ(f.mesh.vertex_count(), 1300u);
    ASSERT_EQ(f.mesh.parents.size(), 1300u);
    EXPECT_EQ(f.mesh.parents[0][0], Mesh::kNoParent);
    EXPECT_LT(f.mesh.parents[1299][0], 1214u + 86u);
    EXPECT_NE(f.metadata_json.find("\"refinement\""), std::string::npos);
    const std::string ply = (m_dir / "r.ply").string();
    r = shprt("scene mesh '" + file + "' -o '" + ply + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("1300 vertices"));
}

// --reproducible keeps the refinement's and the texel bake's metadata (deterministic facts) and
// drops the run's (the memory estimate depends on the thread count): the same bytes whatever
// --threads.
TEST_F(CliReceivers, ReproducibleKeepsRefinementAndTexelMetadata) {
    const std::string refine = (m_dir / "r.shprt").string();
    ASSERT_EQ(shprt("bake builtin:box_on_plane --refine 0.01 --max-vertices 1300 --samples 32 "
                    "--coeffs 4 --reproducible -o '" +
                    refine + "'")
                  .exit_code,
              0);
    EXPECT_NE(read_shprt(refine).metadata_json.find("\"refinement\""), std::string::npos);
    std::string bytes[2];
    for (int threads : {1, 2}) {
        const std::string file = (m_dir / fmt::format("t{}.shprt", threads)).string();
        ASSERT_EQ(shprt(fmt::format("bake builtin:quad_box --domain texel --resolution 16 "
                                    "--samples 32 --coeffs 4 --reproducible --threads {} -o '{}'",
                                    threads, file))
                      .exit_code,
                  0);
        const std::string meta = read_shprt(file).metadata_json;
        EXPECT_NE(meta.find("\"covered_texels\""), std::string::npos) << meta;
        EXPECT_EQ(meta.find("estimated_bytes"), std::string::npos) << meta;
        bytes[threads - 1] = test_support::slurp(file);
    }
    EXPECT_EQ(bytes[0], bytes[1]);
}

// `--unwrap`: a mesh without UVs gets a conformal atlas at the asked density; the file keeps the
// unwrapped mesh (more vertices, its UVs) and the atlas's record; `scene unwrap` writes the same
// atlas as PLY, and bad input is one line.
TEST_F(CliReceivers, UnwrapBakesAMeshWithoutUvs) {
    const std::string file = (m_dir / "u.shprt").string();
    auto r = shprt(
        "bake builtin:box_on_plane --domain texel --unwrap --texel-density 12 --samples 16 "
        "--coeffs 4 --reproducible -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("unwrap: "));
    EXPECT_THAT(r.out, ::testing::HasSubstr("at 12 texels/m"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("overlap 0"));
    const ShprtFile f = read_shprt(file);
    EXPECT_EQ(f.transfer.layout.domain, ReceiverDomain::texel);
    EXPECT_EQ(f.mesh.uvs.size(), f.mesh.vertex_count());
    EXPECT_GE(f.mesh.vertex_count(), make_builtin("box_on_plane").vertex_count());
    EXPECT_EQ(f.transfer.texels.width, f.transfer.texels.height);
    EXPECT_THAT(f.metadata_json, ::testing::HasSubstr("\"texels_per_metre\": 12"));

    const std::string ply = (m_dir / "u.ply").string();
    r = shprt("scene unwrap builtin:box_on_plane --texel-density 12 -o '" + ply + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("overlap 0"));
    r = shprt("bake '" + ply + "' --domain texel --resolution 64 --samples 16 --coeffs 4 -o '" +
              (m_dir / "v.shprt").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;  // the PLY's s, t are a valid atlas

    const std::string base = "bake --samples 16 --coeffs 4 -o '" + file + "' builtin:plane ";
    expect_one_line_error(shprt(base + "--unwrap"), "--unwrap needs --domain texel");
    expect_one_line_error(shprt(base + "--domain texel --texel-density 4"),
                          "--texel-density needs --unwrap");
    expect_one_line_error(shprt(base + "--domain texel --unwrap --resolution 16x8"),
                          "square atlas");
    expect_one_line_error(shprt(base + "--domain texel --unwrap --texel-density -2"),
                          "--texel-density -2");
    expect_one_line_error(shprt(base + "--domain texel --unwrap --texel-density 1e6"),
                          "texels per metre at most");
    expect_one_line_error(
        shprt("scene unwrap '" + (m_dir / "none.obj").string() + "' -o '" + ply + "'"), "none.obj");
}

TEST_F(CliReceivers, RefusalsAreOneLine) {
    const std::string out = (m_dir / "x.shprt").string();
    const std::string base = "bake --samples 16 --coeffs 4 -o '" + out + "' ";
    expect_one_line_error(shprt(base + "builtin:plane --domain texel --resolution 8"),
                          "has no texture coordinates");
    expect_one_line_error(shprt(base + "builtin:quad_box --domain texel"), "needs --resolution");
    expect_one_line_error(shprt(base + "builtin:quad_box --domain texel --resolution 8y8"),
                          "--resolution '8y8'");
    expect_one_line_error(shprt(base + "builtin:quad_box --domain voxel"),
                          "unknown receiver domain 'voxel'");
    expect_one_line_error(shprt(base + "builtin:quad_box --resolution 8"), "need --domain texel");
    expect_one_line_error(
        shprt(base + "builtin:quad_box --domain texel --resolution 8 --shard 0/2"),
        "--shard does not go with --domain texel");
    expect_one_line_error(shprt(base + "builtin:plane --refine 0.05 --stream"),
                          "--stream does not go with --refine");
    expect_one_line_error(shprt(base + "builtin:plane --refine -1"), "--refine -1");
    expect_one_line_error(shprt(base + "builtin:plane --max-vertices 10"), "need --refine");
    expect_one_line_error(shprt(base + "builtin:plane --refine 0.1 --max-edge-split-depth 99"),
                          "--max-edge-split-depth 99");
    expect_one_line_error(shprt(base + "builtin:plane --refine 0.1 --max-vertices 10"),
                          "--max-vertices 10");
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace shprt
