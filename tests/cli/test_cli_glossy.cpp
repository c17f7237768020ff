// Glossy transfer matrices and CPCA from the command line: bake → shade (the white furnace on
// the plane), --stream and --shard give the same rows, compress → shade, render, and the
// one-line refusals.
#include "shprt/config.hpp"
#include "shprt/io/shprt_file.hpp"

#include "cli/cli_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace shprt {
namespace {

using test_support::expect_one_line_error;

class CliGlossy : public test_support::CliTest {
protected:
    std::string bake_plane(const std::string& name, const std::string& extra = "") {
        const std::string file = (m_dir / name).string();
        const auto r = shprt(
            "bake builtin:plane --transfer glossy --bands 4 --samples 1024 "
            "--reproducible -o '" +
            file + "' " + extra);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return file;
    }
};

// The radiance column L_r of a `shade` CSV at the vertex nearest (x, z) = (0, 0).
double centre_radiance(const std::string& csv) {
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);  // header
    double best = 1e30, value = 0;
    while (std::getline(in, line)) {
        std::vector<double> v;
        std::stringstream ss(line);
        std::string cell;
        while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
        const double d = v[0] * v[0] + v[2] * v[2];
        if (d < best) {
            best = d;
            value = v[6];
        }
    }
    return value;
}

TEST_F(CliGlossy, BakeInfoAndStreamAndShardsGiveTheSameRows) {
    const std::string whole = bake_plane("whole.shprt");
    const ShprtFile f = read_shprt(whole);
    EXPECT_EQ(f.transfer.kind, TransferKind::glossy);
    EXPECT_EQ(f.transfer.layout.shape, TransferShape::symmetric_matrix);
    EXPECT_EQ(f.transfer.layout.K, 16);
    auto r = shprt("info '" + whole + "'");
    EXPECT_THAT(r.out, ::testing::HasSubstr("symmetric_matrix"));

    const std::string streamed = bake_plane("stream.shprt", "--stream");
    EXPECT_EQ(read_shprt(streamed).transfer.coeffs, f.transfer.coeffs);
    const std::string a = bake_plane("a.shprt", "--shard 0/2"),
                      b = bake_plane("b.shprt", "--shard 1/2");
    const std::string merged = (m_dir / "merged.shprt").string();
    ASSERT_EQ(shprt("merge '" + a + "' '" + b + "' -o '" + merged + "'").exit_code, 0);
    EXPECT_EQ(read_shprt(merged).transfer.coeffs, f.transfer.coeffs);
}

// A lobe whose zonal fit is poor gets a word on what its error means (issue 40: the README's own
// example printed "zonal fit error 47.5 %" with none); a smooth one (phong:2, 2.9 %) does not.
TEST_F(CliGlossy, ALargeZonalFitErrorSaysItIsExpected) {
    const std::string file = bake_plane("plane.shprt");
    const std::string csv = (m_dir / "s.csv").string();
    auto r = shprt("shade '" + file + "' --brdf phong:64 --k 0.5 -o '" + csv + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::MatchesRegex(
                           ".*zonal fit error [0-9.]+% at 4 bands \\(expected of a zonal lobe in "
                           "4 bands: it is shaded as fitted, blurred; [0-9.]+% at 8 bands\\).*"));
    r = shprt("shade '" + file + "' --brdf phong:2 --k 0.5 -o '" + csv + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("zonal fit error"));
    EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("expected:")));
}

#if SHPRT_HAS_RENDER
TEST_F(CliGlossy, ShadeWhiteFurnaceCompressAndRender) {
    const std::string file = bake_plane("plane.shprt");
    const std::string csv = (m_dir / "furnace.csv").string();
    // A white normalised Phong lobe, seen along the normal, under constant light 1: radiance 1
    // up to the 4-band truncation (fit error · ‖g‖ · √(2π) ≈ 0.10 for phong:8, docs/glossy.md)
    // and Monte Carlo.
    auto r = shprt("shade '" + file +
                   "' --brdf phong:8 --k 0 --albedo 1,1,1 --light constant "
                   "--eye 0,10,0 -o '" +
                   csv + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("brdf=phong:8"));
    EXPECT_NEAR(centre_radiance(csv), 1.0, 0.1);

    // CPCA: one cluster, full rank: the same shading to rounding.
    const std::string cpca = (m_dir / "plane_cpca.shprt").string();
    r = shprt("compress '" + file + "' -o '" + cpca + "' --cpca 1,136");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("B/vertex"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("relative RMSE"));
    const std::string csv2 = (m_dir / "furnace_cpca.csv").string();
    r = shprt("shade '" + cpca +
              "' --brdf phong:8 --k 0 --albedo 1,1,1 --light constant "
              "--eye 0,10,0 -o '" +
              csv2 + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NEAR(centre_radiance(csv2), centre_radiance(csv), 1e-4);

    const std::string png = (m_dir / "g.png").string();
    r = shprt("render '" + cpca + "' --brdf ggx:0.3 --k 0.5 --size 64x36 -o '" + png + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(png));
    r = shprt("render '" + file + "' --glossy paper --k 0.5 --size 64x36 -o '" + png + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The viewer shades matrices and CPCA codes as `render` does (one Renderer): its screenshot
    // is render's picture byte for byte, with the BRDF, k and the colour override.
    const std::string shot = (m_dir / "view.png").string();
    for (const std::string& input : {file, cpca}) {
        const std::string options =
            " --brdf blinn:30 --k 0.3 --albedo 0.9,0.6,0.3 --size 64x36 --camera 0.5,1.2,1.5,0,0,0";
        r = shprt("view '" + input + "' --screenshot '" + shot + "'" + options);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(r.err, "");
        r = shprt("render '" + input + "' -o '" + png + "'" + options);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(test_support::slurp(shot), test_support::slurp(png)) << input;
    }
    // Without --brdf the viewer takes --gloss's Phong lobe: what `render --brdf phong:16` draws.
    r = shprt("view '" + file + "' --k 0.5 --size 64x36 --screenshot '" + shot + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = shprt("render '" + file + "' --brdf phong:16 --k 0.5 --size 64x36 -o '" + png + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(test_support::slurp(shot), test_support::slurp(png));
    // A specular colour in the spec: the viewer draws render's picture, which the colour changes.
    const std::string gold = " --brdf ggx:0.4:1,0.71,0.29 --k 0.3 --size 64x36";
    r = shprt("view '" + file + "' --screenshot '" + shot + "'" + gold);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = shprt("render '" + file + "' -o '" + png + "'" + gold);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("brdf=ggx:0.4:1,0.71,0.29"));
    EXPECT_EQ(test_support::slurp(shot), test_support::slurp(png));
    const std::string white = (m_dir / "white.png").string();
    ASSERT_EQ(shprt("render '" + file + "' -o '" + white + "' --brdf ggx:0.4 --k 0.3 --size 64x36")
                  .exit_code,
              0);
    EXPECT_NE(test_support::slurp(white), test_support::slurp(png));
    expect_one_line_error(shprt("render '" + file + "' -o '" + png + "' --brdf ggx:0.4:1,2,0"),
                          "specular colour (1, 2, 0) must be in [0, 1]");
    expect_one_line_error(
        shprt("shade '" + file + "' -o x.csv --glossy paper --brdf phong:16:1,0.5,0.5"),
        "--glossy paper: the paper's term has no specular colour");

    // A glossy bake in the viewer's own process: its screenshot is the picture of the baked file,
    // and --albedo is the glossy colour override there too (a glossy bake has no albedo).
    const std::string bake = " --transfer glossy --bands 4 --samples 256 --seed 5";
    const std::string options =
        " --brdf blinn:30 --k 0.3 --albedo 0.9,0.6,0.3 --size 64x36 --camera 0.5,1.2,1.5,0,0,0";
    r = shprt("view builtin:box_on_plane --bake" + bake + options + " --screenshot '" + shot + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("baked 1214 vertices, K=16, S=256"), std::string::npos) << r.out;
    const std::string baked = (m_dir / "box.shprt").string();
    ASSERT_EQ(shprt("bake builtin:box_on_plane" + bake + " -o '" + baked + "'").exit_code, 0);
    r = shprt("render '" + baked + "' -o '" + png + "'" + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(test_support::slurp(shot), test_support::slurp(png));
    // --glossy paper needs finished matrices: the window refuses it (before opening), a
    // screenshot bakes first and takes it; --brdf needs a glossy bake.
    expect_one_line_error(shprt("view builtin:plane --bake --transfer glossy --glossy paper"),
                          "--glossy paper: the window shows a glossy bake's matrices");
    r = shprt(
        "view builtin:plane --bake --transfer glossy --bands 2 --samples 64 --glossy paper "
        "--k 0.5 --size 32x18 --screenshot '" +
        shot + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    expect_one_line_error(
        shprt("view builtin:plane --bake --brdf phong:8 --screenshot '" + shot + "'"),
        "with --bake, add --transfer glossy");
}

// The rows of a `shade` CSV (one per vertex, header skipped).
std::vector<std::string> csv_rows(const std::string& csv) {
    std::ifstream in(csv);
    std::vector<std::string> rows;
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) rows.push_back(line);
    return rows;
}

// A scene file whose materials give BRDFs (OBJ Ns and Ks: phong:64 on vertices 0-2, none on 3-5,
// phong:10000 clamped from 50000 with specular colour 0.9,0.6,0.2 on 6-8): baked, described, and
// shaded without --brdf.
TEST_F(CliGlossy, MaterialBrdfsFromTheSceneFileShadeWithoutBrdf) {
    const std::string scene = std::string(SHPRT_TEST_DATA_DIR) + "/scene/glossy_materials.obj";
    const std::string file = (m_dir / "m.shprt").string();
    auto r =
        shprt("bake '" + scene + "' --transfer glossy --bands 3 --samples 256 -o '" + file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = shprt("info '" + file + "'");
    EXPECT_THAT(r.out, ::testing::HasSubstr("brdfs        phong:64 (3 vertices), "
                                            "phong:10000:0.9,0.6,0.2 (3 vertices), none (3 "
                                            "vertices) (from the materials)"));
    // A streamed bake and a sharded one keep them too.
    const Mesh whole = read_shprt(file).mesh;
    const std::string streamed = (m_dir / "s.shprt").string(), a = (m_dir / "a.shprt").string(),
                      b = (m_dir / "b.shprt").string(), merged = (m_dir / "ab.shprt").string();
    const std::string bake = "bake '" + scene + "' --transfer glossy --bands 3 --samples 256 ";
    ASSERT_EQ(shprt(bake + "--stream -o '" + streamed + "'").exit_code, 0);
    ASSERT_EQ(shprt(bake + "--shard 0/2 -o '" + a + "'").exit_code, 0);
    ASSERT_EQ(shprt(bake + "--shard 1/2 -o '" + b + "'").exit_code, 0);
    ASSERT_EQ(shprt("merge '" + a + "' '" + b + "' -o '" + merged + "'").exit_code, 0);
    for (const std::string& f : {streamed, merged}) {
        EXPECT_EQ(read_shprt(f).mesh.brdfs, whole.brdfs) << f;
        EXPECT_EQ(read_shprt(f).mesh.brdf_index, whole.brdf_index) << f;
    }
    // The same geometry with another shininess: its part is not merged with the first's.
    const std::filesystem::path other = m_dir / "other";
    std::filesystem::create_directories(other);
    std::filesystem::copy_file(scene, other / "glossy_materials.obj");
    {
        std::ofstream mtl(other / "glossy_materials.mtl");
        mtl << "newmtl shiny\nKd 0.5 0.5 0.5\nNs 32\nnewmtl matte\nKd 0.8 0.2 0.2\n"
               "newmtl mirror\nKd 0.1 0.1 0.1\nNs 50000\n";
    }
    const std::string b2 = (m_dir / "b2.shprt").string();
    ASSERT_EQ(shprt("bake '" + (other / "glossy_materials.obj").string() +
                    "' --transfer glossy --bands 3 --samples 256 --shard 1/2 -o '" + b2 + "'")
                  .exit_code,
              0);
    expect_one_line_error(shprt("merge '" + a + "' '" + b2 + "' -o '" + merged + "'"),
                          "other material BRDFs than");
    const std::string light = " --light sun:0.3,1,0.2,20 --light constant:0.1 --eye 0.5,2,1.5 ";
    const std::string materials = (m_dir / "materials.csv").string(),
                      phong64 = (m_dir / "phong64.csv").string(),
                      gloss64 = (m_dir / "gloss64.csv").string(),
                      mirror = (m_dir / "mirror.csv").string();
    r = shprt("shade '" + file + "' --k 0.2" + light + "-o '" + materials + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("brdf=materials: phong:64 (3 vertices), "
                                            "phong:10000:0.9,0.6,0.2 (3 vertices), none (3 "
                                            "vertices); none = phong:16"));
    ASSERT_EQ(shprt("shade '" + file + "' --k 0.2 --brdf phong:64" + light + "-o '" + phong64 + "'")
                  .exit_code,
              0);
    // --gloss sets the lobe of the vertices whose material gives none.
    ASSERT_EQ(
        shprt("shade '" + file + "' --k 0.2 --gloss 64" + light + "-o '" + gloss64 + "'").exit_code,
        0);
    // The mirror material's lobe and specular colour, given as --brdf.
    ASSERT_EQ(shprt("shade '" + file + "' --k 0.2 --brdf phong:10000:0.9,0.6,0.2" + light + "-o '" +
                    mirror + "'")
                  .exit_code,
              0);
    const auto m = csv_rows(materials), p = csv_rows(phong64), g = csv_rows(gloss64),
               c = csv_rows(mirror);
    ASSERT_EQ(c.size(), 9u);
    ASSERT_EQ(m.size(), 9u);
    ASSERT_EQ(p.size(), 9u);
    ASSERT_EQ(g.size(), 9u);
    for (int v = 0; v < 9; ++v) {
        SCOPED_TRACE(v);
        if (v < 3) {
            EXPECT_EQ(m[v], p[v]);  // the material's phong:64 = --brdf phong:64
        }
        if (v >= 3 && v < 6) {
            EXPECT_NE(m[v], p[v]);  // none: phong:16, not 64
            EXPECT_EQ(g[v], p[v]);  // ... unless --gloss 64
        }
        if (v >= 6) {
            EXPECT_NE(m[v], p[v]);  // phong:10000:0.9,0.6,0.2
            EXPECT_EQ(m[v], c[v]);
        }
    }
    // render takes the materials too, and the viewer's screenshot is render's picture.
    const std::string png = (m_dir / "m.png").string(), shot = (m_dir / "v.png").string();
    const std::string options = " --k 0.3 --size 48x32 --camera 2.5,2,2,2.5,0,-0.5";
    r = shprt("render '" + file + "' -o '" + png + "'" + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("brdf=materials: "));
    r = shprt("view '" + file + "' --screenshot '" + shot + "'" + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(test_support::slurp(shot), test_support::slurp(png));
}

// Glossy matrices per texel: shade writes the texel image, render and the viewer draw them with
// the glossy term (the same picture).
TEST_F(CliGlossy, TexelMatricesShadeRenderAndView) {
    const std::string file = (m_dir / "t.shprt").string();
    auto r = shprt(
        "bake builtin:quad_box --domain texel --resolution 32 --transfer glossy --bands 3 "
        "--samples 64 -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string npy = (m_dir / "t.npy").string();
    r = shprt("shade '" + file + "' --brdf ggx:0.5 --k 0.3 --quantity radiance -o '" + npy + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("texels of 32x32 (radiance, K'=9, brdf=ggx:0.5"));
    EXPECT_NE(test_support::slurp(npy).find("'shape': (32, 32, 3)"), std::string::npos);
    const std::string png = (m_dir / "r.png").string(), shot = (m_dir / "v.png").string();
    const std::string options = " --brdf ggx:0.5 --k 0.3 --size 48x32";
    r = shprt("render '" + file + "' -o '" + png + "'" + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = shprt("view '" + file + "' --screenshot '" + shot + "'" + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(test_support::slurp(shot), test_support::slurp(png));
    // Their diffuse transfer per texel: --glossy paper shades it, export writes it as planes.
    const std::string paper = (m_dir / "p.npy").string(), exr = (m_dir / "planes.exr").string();
    r = shprt("shade '" + file + "' --glossy paper -o '" + paper + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(test_support::slurp(paper).find("'shape': (32, 32, 3)"), std::string::npos);
    r = shprt("export '" + file + "' -o '" + exr + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("planes, the glossy matrices' diffuse transfer"));
    EXPECT_THAT(test_support::slurp(exr), ::testing::HasSubstr("sh008.Y"));
}

TEST_F(CliGlossy, DiffuseAndGlossyFilesRefuseTheOtherShading) {
    const std::string glossy = bake_plane("g.shprt");
    const std::string diffuse = (m_dir / "d.shprt").string();
    ASSERT_EQ(shprt("bake builtin:plane --samples 64 -o '" + diffuse + "'").exit_code, 0);
    const std::string csv = out("x.csv");
    expect_one_line_error(
        shprt("shade '" + diffuse + "' --brdf phong:8 --light constant -o '" + csv + "'"),
        "--brdf needs a glossy bake");
    expect_one_line_error(shprt("shade '" + glossy + "' --light constant -o '" + csv + "'"),
                          "glossy transfer matrices need --brdf");
    expect_one_line_error(
        shprt("shade '" + glossy + "' --brdf wood:3 --light constant -o '" + csv + "'"),
        "unknown model 'wood'");
    expect_one_line_error(
        shprt("shade '" + glossy + "' --brdf phong:8 --albedo 2,0,0 --light constant -o '" + csv +
              "'"),
        "--albedo 2,0,0");
    EXPECT_TRUE(out_dir_empty());
}
#endif

TEST_F(CliGlossy, CompressRefusesBadParameters) {
    const std::string file = bake_plane("p.shprt");
    const std::string o = out("c.shprt");
    expect_one_line_error(shprt("compress '" + file + "' -o '" + o + "' --cpca 100000,4"),
                          "clusters for 289 vertices");
    expect_one_line_error(shprt("compress '" + file + "' -o '" + o + "' --cpca 4,137"),
                          "137 vectors, more than the 136 floats");
    expect_one_line_error(shprt("compress '" + file + "' -o '" + o + "' --cpca 4"),
                          "--cpca CLUSTERS,VECTORS");
    expect_one_line_error(shprt("compress '" + file + "' -o '" + o + "' --cpca 4,8 --sun 1,1,1"),
                          "the error is reported under --light SKY");
    expect_one_line_error(
        shprt("compress '" + file + "' -o '" + o + "' --cpca 4,8 --light nothing.hdr"),
        "nothing.hdr");
    EXPECT_TRUE(out_dir_empty());
}

// --light: the error under that light too, a --sun kept out of it (named in the line).
TEST_F(CliGlossy, CompressReportsTheErrorUnderAGivenLight) {
    // Not the plane: its transfer is the same at every vertex, which one vector holds exactly.
    const std::string file = out("bp.shprt");
    ASSERT_EQ(shprt("bake builtin:box_on_plane --transfer glossy --samples 64 -q -o '" + file + "'")
                  .exit_code,
              0);
    const auto r = shprt("compress '" + file + "' -o '" + out("c.shprt") +
                         "' --cpca 2,1 --light gradient --sun 1,1,1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::regex line(
        "error under --light gradient \\(the sun of --sun 1,1,1 kept out of the SH sum\\): exit "
        "radiance relative RMSE ([0-9.]+)% \\(5 views\\)\n");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.out, m, line)) << r.out;
    EXPECT_GT(std::stod(m[1].str()), 0.0);
}

}  // namespace
}  // namespace shprt
