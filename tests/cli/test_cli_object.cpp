// `shprt render --object` and `shprt view --object` (docs/probes.md "Lighting objects") run as
// programs: bad input gives one line each, a non-zero exit and no picture — a file without
// probes, an object that does not load, a bad or missing --at — before anything is baked.
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"

#include "cli/cli_test.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace shprt {
namespace {

using test_support::expect_one_line_error;

class CliObject : public test_support::CliTest {
protected:
    void SetUp() override {
        CliTest::SetUp();
        // The unit sphere with unshadowed transfer and no probes.
        const Mesh mesh = make_builtin("sphere");
        TransferSet t;
        t.kind = TransferKind::unshadowed;
        t.layout.K = 9;
        t.coeffs.resize(mesh.vertex_count() * 9);
        const std::vector<double> z = clamped_cosine_zonal(3);
        std::vector<double> c(9);
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            rotate_zonal(z.data(), 9, normalize(cast<double>(mesh.normals[v])), c.data());
            for (int i = 0; i < 9; ++i) t.coeffs[v * 9 + i] = float(c[i]);
        }
        m_file = (m_dir / "sphere.shprt").string();
        write_shprt(m_file, mesh, t);
    }
    std::string render(const std::string& options, const std::string& image = "o.png") {
        return "render '" + m_file + "' --size 64x36 " + options + " -o '" + out(image) + "'";
    }
    std::string m_file;
};

TEST_F(CliObject, BadInputGivesOneLineBeforeAnyWork) {
    // A file without probes, named, before the object is read.
    expect_one_line_error(shprt(render("--object builtin:sphere --at 0,0,0")),
                          "sphere.shprt: the file has no transfer probes (bake it with shprt "
                          "bake --probes)");
    // The object's placement, checked before the file is read.
    expect_one_line_error(shprt(render("--object builtin:sphere")),
                          "--object builtin:sphere: give its position with --at X,Y,Z");
    expect_one_line_error(shprt(render("--object builtin:sphere --at 1,2")), "--at X,Y,Z");
    expect_one_line_error(shprt(render("--object builtin:sphere --at 0,0,0 --object-scale 0")),
                          "--object-scale 0: must be a finite number > 0");
    expect_one_line_error(shprt(render("--object builtin:sphere --at 0,0,0 --object-rotate 1,x,3")),
                          "1,x,3");
    expect_one_line_error(shprt(render("--at 0,0,0")), "give --object MESH");
    expect_one_line_error(
        shprt("view '" + m_file + "' --object builtin:sphere --at 0,0,0 --screenshot '" +
              out("v.png") + "'"),
        "sphere.shprt: the file has no transfer probes");
    EXPECT_TRUE(out_dir_empty());
}

// End to end from a real baked file: builtin:box_on_plane with a 4×2×4 grid of probes (skipped
// where `shprt bake` has no --probes yet: the bake half of issue 37).
TEST_F(CliObject, ARealBakedFileLightsTheObject) {
    if (shprt("bake --help").out.find("--probes") == std::string::npos)
        GTEST_SKIP() << "this shprt bakes no probes (shprt bake --probes)";
    const std::string file = (m_dir / "box.shprt").string();
    const auto baked =
        shprt("bake builtin:box_on_plane --bands 3 --samples 32 --probes 4,2,4 -o '" + file + "'");
    ASSERT_EQ(baked.exit_code, 0) << baked.err;
    m_file = file;
    const auto r = shprt(render("--object builtin:sphere --at 1.2,0.5,1.2 --object-scale 0.3"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("object: builtin:sphere (642 vertices, self-shadowing baked) at "
                         "1.2,0.5,1.2 lit from 32 probes"),
              std::string::npos)
        << r.out;
    // Outside the grid: the picture, and exactly one warning line.
    const auto outside =
        shprt(render("--object builtin:sphere --at 9,0.5,0 --object-scale 0.3", "outside.png"));
    ASSERT_EQ(outside.exit_code, 0) << outside.err;
    EXPECT_EQ(std::count(outside.err.begin(), outside.err.end(), '\n'), 1) << outside.err;
    EXPECT_EQ(outside.err.rfind("shprt: warning: --at 9,0.5,0 is outside the probe grid (", 0), 0u)
        << outside.err;
    EXPECT_TRUE(fs::exists(out("outside.png")));
    // An object file that does not load: one line naming it, no picture.
    expect_one_line_error(shprt(render("--object /no/such/object.ply --at 0,0.5,0", "n.png")),
                          "/no/such/object.ply");
    EXPECT_FALSE(fs::exists(out("n.png")));
}

// `shprt compress --probe-cpca`: the probes stored as a code light the object as the raw ones
// do (to the code's error), `info` says so, and bad requests are one line before any work.
TEST_F(CliObject, CompressedProbesLightTheObject) {
    const std::string raw = (m_dir / "box.shprt").string(), code = out("boxc.shprt");
    const auto baked =
        shprt("bake builtin:box_on_plane --bands 3 --samples 32 --probes 4,2,4 -o '" + raw + "'");
    ASSERT_EQ(baked.exit_code, 0) << baked.err;
    const auto c = shprt("compress '" + raw + "' -o '" + code + "' --cpca 8,2 --probe-cpca 6,4");
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(c.out.find("probes: 6 clusters x 4 vectors, float32"), std::string::npos) << c.out;
    EXPECT_NE(c.out.find("probe error: incident radiance relative RMSE"), std::string::npos)
        << c.out;
    EXPECT_NE(shprt("info '" + code + "'").out.find("; CPCA 6 clusters x 4 vectors"),
              std::string::npos);
    for (const std::string& file : {raw, code}) {
        m_file = file;
        const auto r = shprt(render("--object builtin:sphere --at 1.2,0.5,1.2 --object-scale 0.3",
                                    fs::path(file).stem().string() + ".png"));
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.out.find("lit from 32 probes"), std::string::npos) << r.out;
    }
    expect_one_line_error(
        shprt("compress '" + raw + "' -o '" + out("x.shprt") + "' --cpca 8,2 --probe-cpca 33,4"),
        "at most 32 clusters (the valid probes) and 81 vectors");
    expect_one_line_error(
        shprt("compress '" + raw + "' -o '" + out("x.shprt") + "' --cpca 8,2 --probe-cpca 4"),
        "--probe-cpca");
    expect_one_line_error(shprt("compress '" + m_dir.string() + "/sphere.shprt' -o '" +
                                out("x.shprt") + "' --cpca 8,2 --probe-cpca 2,2"),
                          "the file has no probes (bake with --probes)");
    EXPECT_FALSE(fs::exists(out("x.shprt")));
}

// `shprt view --object`: the screenshot shows the object, and the window (under Xvfb, when
// xvfb-run exists) runs its frames with the object shaded and uploaded.
TEST_F(CliObject, TheViewerShowsTheObject) {
    if (shprt("bake --help").out.find("--probes") == std::string::npos)
        GTEST_SKIP() << "this shprt bakes no probes (shprt bake --probes)";
    const std::string file = (m_dir / "box.shprt").string();
    ASSERT_EQ(
        shprt("bake builtin:box_on_plane --bands 3 --samples 32 --probes 4,2,4 -o '" + file + "'")
            .exit_code,
        0);
    const std::string view = "view '" + file + "' --size 320x200 ";
    const std::string object = " --object builtin:sphere --at 1.2,0.5,1.2 --object-scale 0.4";
    const auto with = shprt(view + "--screenshot '" + out("with.png") + "'" + object);
    ASSERT_EQ(with.exit_code, 0) << with.err;
    EXPECT_NE(with.out.find("object: builtin:sphere (642 vertices"), std::string::npos) << with.out;
    ASSERT_EQ(shprt(view + "--screenshot '" + out("without.png") + "'").exit_code, 0);
    EXPECT_NE(test_support::slurp(out("with.png")), test_support::slurp(out("without.png")));
    if (!test_support::has_program("xvfb-run"))
        GTEST_SKIP() << "xvfb-run is missing: the window is not tested";
    const auto window =
        shprt(view + "--frames 3 --window-screenshot '" + out("window.png") + "'" + object,
              {.prefix = test_support::without_leak_check() +
                         " xvfb-run -a -s '-screen 0 1280x1024x24'"});
    ASSERT_EQ(window.exit_code, 0) << window.err;
    EXPECT_NE(window.out.find("view: 3 frames"), std::string::npos) << window.out;
    EXPECT_TRUE(fs::exists(out("window.png")));
}

}  // namespace
}  // namespace shprt
