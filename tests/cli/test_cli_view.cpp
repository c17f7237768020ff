// `shprt view` run as a program: --screenshot gives `shprt render`'s PNG byte for byte (one picture
// path: render_image, then save_image), --benchmark prints
// one line per basis size, --bake bakes in the same process, bad input gives one line and exit 1,
// and (when xvfb-run exists) the real window opens under Xvfb, draws its panel and shows the
// same picture as --screenshot beside it.
#include "cli/cli_test.hpp"

#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using shprt::test_support::expect_one_line_error;
using shprt::test_support::has_program;
using shprt::test_support::RunOptions;
using shprt::test_support::RunResult;
using shprt::test_support::slurp;
using shprt::test_support::without_leak_check;

// PNG codes of the same picture made in two OpenGL contexts (EGL and a hidden GLX window): the
// drivers may round differently, by one level at most.
constexpr int kMaxLevelDifference = 1;
constexpr double kMaxMeanLevelDifference = 0.05;
// The window against --screenshot outside the panel: the orbit controller rebuilds eye and
// target from yaw/pitch/distance (float rounding), which may move a few edge pixels.
constexpr double kMaxMeanWindowDifference = 1.0;
// Inside the panel's rectangle the picture must differ clearly (the panel is drawn).
constexpr double kMinMeanPanelDifference = 10.0;

struct Png {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;
};

Png read_png(const std::string& path) {
    Png png;
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &png.width, &png.height, &channels, 3);
    if (!data) return png;
    png.rgb.assign(data, data + std::size_t(png.width) * png.height * 3);
    stbi_image_free(data);
    return png;
}

// Mean and max absolute difference of two PNGs over the rectangle [x0, x1) × [y0, y1).
struct Diff {
    double mean = 0;
    int max = 0;
};
Diff compare(const Png& a, const Png& b, int x0, int y0, int x1, int y1) {
    Diff d;
    double sum = 0;
    std::size_t n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (std::size_t(y) * a.width + x) * 3 + c;
                const int diff = std::abs(int(a.rgb[i]) - int(b.rgb[i]));
                d.max = std::max(d.max, diff);
                sum += diff;
                ++n;
            }
    d.mean = n ? sum / double(n) : 0;
    return d;
}

// Each test runs in its own directory (CliTest); the suite bakes one file for all of them.
class CliView : public shprt::test_support::CliTest {
protected:
    static void SetUpTestSuite() {
        s_dir = fs::temp_directory_path() / ("shprt_cli_view_" + std::to_string(::getpid()));
        fs::remove_all(s_dir);
        fs::create_directories(s_dir);
        s_file = (s_dir / "box64.shprt").string();
        const RunResult r = shprt::test_support::run_shprt(
            "bake builtin:box_on_plane -o '" + s_file + "' --coeffs 64 --samples 128 --seed 2",
            s_dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        // An interreflected bake, for --direct.
        const RunResult ir = shprt::test_support::run_shprt(
            "bake builtin:box_on_plane -o '" + (s_dir / "ir.shprt").string() +
                "' --transfer interreflected --bounces 2 --bands 3 --samples 128",
            s_dir);
        ASSERT_EQ(ir.exit_code, 0) << ir.err;
    }
    static void TearDownTestSuite() { fs::remove_all(s_dir); }

    // quad_box baked per texel (32², K = 9) into the test's directory: what the texel tests show.
    std::string bake_texel_file() const {
        const std::string texel = out("t.shprt");
        const RunResult r = shprt(
            "bake builtin:quad_box --domain texel --resolution 32 --samples 64 --coeffs 9 -o '" +
            texel + "'");
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return texel;
    }

    static fs::path s_dir;
    static std::string s_file;
};

fs::path CliView::s_dir;
std::string CliView::s_file;

TEST_F(CliView, ScreenshotEqualsRender) {
    const std::string common[] = {
        " --size 120x80",
        " --size 96x64 --light builtin --rotate 40,10,0 --k 0.4 --exposure 1.6 --camera "
        "3,2.5,3.5,0,0.3,0 --fov 45",
        " --size 64x64 --light sun:1,2,1,6 --light constant:0.2 --shading-coeffs 20 --view "
        "irradiance "
        "--window hann"};
    for (const std::string& options : common) {
        const RunResult v =
            shprt("view '" + s_file + "' --screenshot '" + out("view.png") + "'" + options);
        ASSERT_EQ(v.exit_code, 0) << v.err;
        EXPECT_NE(v.out.find("screenshot "), std::string::npos) << v.out;
        const RunResult r =
            shprt("render '" + s_file + "' -o '" + out("render.png") + "'" + options);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        // The same path, so the same file.
        EXPECT_EQ(slurp(out("view.png")), slurp(out("render.png"))) << options;
        const Png a = read_png(out("view.png"));
        ASSERT_FALSE(a.rgb.empty());
        // Not a trivially equal pair of blank pictures.
        int distinct_levels = 0;
        std::vector<bool> seen(256, false);
        for (unsigned char c : a.rgb)
            if (!seen[c]) seen[c] = true, ++distinct_levels;
        EXPECT_GT(distinct_levels, 10) << options;
    }
}

// An interreflected bake: --direct shows its direct part, the picture of `render --direct`, and
// not the picture with the bounces; a file without a direct part is refused.
TEST_F(CliView, DirectShowsTheDirectPartAsRenderDoes) {
    const std::string ir = (s_dir / "ir.shprt").string();
    const std::string options = " --size 96x64 --light sun:1,2,1,6";
    for (const char* name : {"view", "render"}) {
        const std::string flag = std::string(name) == "view" ? " --screenshot '" : " -o '";
        ASSERT_EQ(shprt(std::string(name) + " '" + ir + "'" + flag +
                        out(std::string(name) + "-direct.png") + "' --direct" + options)
                      .exit_code,
                  0);
        ASSERT_EQ(shprt(std::string(name) + " '" + ir + "'" + flag +
                        out(std::string(name) + "-all.png") + "'" + options)
                      .exit_code,
                  0);
    }
    EXPECT_EQ(slurp(out("view-direct.png")), slurp(out("render-direct.png")));
    EXPECT_EQ(slurp(out("view-all.png")), slurp(out("render-all.png")));
    EXPECT_NE(slurp(out("view-direct.png")), slurp(out("view-all.png")));
    expect_one_line_error(
        shprt("view '" + s_file + "' --direct --screenshot '" + out("x.png") + "'"),
        "has no direct part");
    EXPECT_FALSE(fs::exists(out("x.png")));
}

// A sun kept out of the SH sum (--sun): the viewer's screenshot is `render`'s picture, turned with
// --rotate in both; it differs from the picture without it; the interreflected file says its
// bounced light comes from T − T_0; a glossy draw is refused with one line.
TEST_F(CliView, ASunKeptOutOfTheShSumShowsAsRenderDrawsIt) {
    const std::string ir = (s_dir / "ir.shprt").string();
    const std::string options = " --size 96x64 --light gradient --sun 1,1.2,0.3,2 --rotate 20,0,0";
    const RunResult v = shprt("view '" + ir + "' --screenshot '" + out("sv.png") + "'" + options);
    ASSERT_EQ(v.exit_code, 0) << v.err;
    const RunResult r = shprt("render '" + ir + "' -o '" + out("sr.png") + "'" + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("bounced light from the file's T - T_0"), std::string::npos) << r.out;
    EXPECT_EQ(slurp(out("sv.png")), slurp(out("sr.png")));
    ASSERT_EQ(shprt("render '" + ir + "' -o '" + out("nosun.png") +
                    "' --size 96x64 --light gradient --rotate 20,0,0")
                  .exit_code,
              0);
    EXPECT_NE(slurp(out("sr.png")), slurp(out("nosun.png")));
    expect_one_line_error(shprt("render '" + ir + "' -o '" + out("g.png") + "' --k 0.5" + options),
                          "lights diffuse receivers only");
    EXPECT_FALSE(fs::exists(out("g.png")));
}

// A texel file (per-fragment shading): --screenshot is `render`'s picture; the glossy term is
// refused with one line, as in `render`.
TEST_F(CliView, ATexelFileShowsAsRenderDrawsIt) {
    const std::string texel = bake_texel_file();
    const std::string options = " --size 96x64 --light sun:1,2,1,6 --shading-coeffs 7";
    const RunResult v = shprt("view '" + texel + "' --screenshot '" + out("v.png") + "'" + options);
    ASSERT_EQ(v.exit_code, 0) << v.err;
    const RunResult r = shprt("render '" + texel + "' -o '" + out("r.png") + "'" + options);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(slurp(out("v.png")), slurp(out("r.png")));
    expect_one_line_error(
        shprt("view '" + texel + "' --k 0.5 --screenshot '" + out("g.png") + "'" + options),
        "the paper's glossy term is not drawn per texel");
    EXPECT_FALSE(fs::exists(out("g.png")));
}

TEST_F(CliView, BenchmarkPrintsALinePerBasisSize) {
    const RunResult r = shprt("view '" + s_file + "' --benchmark 3 --size 64x48 --msaa 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("benchmark: 1214 vertices"), std::string::npos) << r.out;
    for (int K : {32, 48, 64}) {
        const std::regex line("K'=" + std::to_string(K) +
                              " +frames=3  fps=([0-9.]+)  mean_ms=([0-9.]+)  min_ms=[0-9.]+  "
                              "max_ms=[0-9.]+  cpu_ms=[0-9.]+\n");
        std::smatch m;
        ASSERT_TRUE(std::regex_search(r.out, m, line)) << "K'=" << K << " in\n" << r.out;
        EXPECT_GT(std::stod(m[1].str()), 0.0);
        EXPECT_GT(std::stod(m[2].str()), 0.0);
    }
    EXPECT_NE(r.out.find("K'=128  skipped: larger than the file's K=64"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("K'=256  skipped"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frame time K'=256 / K'=32: n/a"), std::string::npos) << r.out;
}

TEST_F(CliView, BakesInTheSameProcessBeforeAHeadlessMode) {
    const RunResult r = shprt(
        "view builtin:box_on_plane --bake --coeffs 32 --samples 32 --seed 4 "
        "--benchmark 2 --size 32x32 --msaa 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("baked 1214 vertices, K=32, S=32"), std::string::npos) << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex("K'=32 +frames=2  fps=[0-9.]+"))) << r.out;
    EXPECT_NE(r.out.find("K'=48   skipped"), std::string::npos) << r.out;
}

TEST_F(CliView, DeviceCudaBakesOnTheGpuOrSaysWhyNot) {
    const RunResult r = shprt(
        "view builtin:box_on_plane --bake --device cuda --coeffs 16 "
        "--samples 32 --benchmark 1 --size 32x32 --msaa 1");
    if (r.exit_code == 0) {
        // A CUDA build on a machine with a GPU.
        EXPECT_NE(r.out.find("baked 1214 vertices, K=16"), std::string::npos) << r.out;
        return;
    }
    expect_one_line_error(r, "device 'cuda': ");
    EXPECT_TRUE(r.err.find("no CUDA") != std::string::npos ||
                r.err.find("CUDA device") != std::string::npos)
        << r.err;
}

TEST_F(CliView, BadInputGivesOneLineAndExitOne) {
    // Corrupt, truncated and missing files.
    const std::string garbage = (m_dir / "garbage.shprt").string();
    std::ofstream(garbage) << "this is not a shprt file";
    expect_one_line_error(shprt("view '" + garbage + "' --screenshot '" + out("x.png") + "'"),
                          "garbage.shprt");
    const std::string bytes = slurp(s_file), truncated = (m_dir / "truncated.shprt").string();
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    expect_one_line_error(shprt("view '" + truncated + "' --benchmark 1"), "truncated.shprt");
    expect_one_line_error(shprt("view '" + (m_dir / "missing.shprt").string() + "' --screenshot '" +
                                out("x.png") + "'"),
                          "missing.shprt");
    // A light file that does not exist.
    expect_one_line_error(
        shprt("view '" + s_file + "' --light /nonexistent/sky.hdr --screenshot '" + out("x.png") +
              "'"),
        "sky.hdr");
    EXPECT_TRUE(out_dir_empty()) << "nothing written on failure";
    // Options.
    expect_one_line_error(shprt("view '" + s_file + "' --samples 64"),
                          "--samples is a bake option");
    expect_one_line_error(shprt("view '" + s_file + "' --screenshot '" + out("x.exr") + "'"),
                          "PNG");
    expect_one_line_error(shprt("view '" + s_file + "' --benchmark 0"), "--benchmark 0");
    expect_one_line_error(
        shprt("view '" + s_file + "' --benchmark 2 --screenshot '" + out("x.png") + "'"),
        "use one");
    expect_one_line_error(shprt("view '" + s_file + "' --k 2 --screenshot '" + out("x.png") + "'"),
                          "--k 2");
    expect_one_line_error(
        shprt("view '" + s_file + "' --size 0x5 --screenshot '" + out("x.png") + "'"), "size");
    expect_one_line_error(shprt("view builtin:nonesuch --bake --benchmark 1"), "nonesuch");
    // The window without a display.
    expect_one_line_error(
        shprt("view '" + s_file + "'", {.prefix = "env -u DISPLAY -u WAYLAND_DISPLAY"}),
        "cannot open a window");
    EXPECT_TRUE(out_dir_empty());
}

TEST_F(CliView, NoOpenGl43GivesOneLine) {
    // Mesa caps the version it offers when asked to; other drivers ignore the variable.
    const RunResult r =
        shprt("view '" + s_file + "' --screenshot '" + out("old.png") + "' --offscreen egl",
              {.prefix = "MESA_GL_VERSION_OVERRIDE=3.3"});
    if (r.exit_code == 0) GTEST_SKIP() << "this driver ignores MESA_GL_VERSION_OVERRIDE";
    expect_one_line_error(r, "OpenGL 4.3 core profile needed");
}

class CliViewWindow : public CliView {
protected:
    void SetUp() override {
        CliView::SetUp();  // first: TearDown removes the test's directory even after a skip
        if (!has_program("xvfb-run"))
            GTEST_SKIP() << "xvfb-run is missing (apt-get install xvfb xauth): window not tested";
    }
    // GLFW unloads Mesa's GLX driver at exit: no leak check there under ASan (cli_test.hpp).
    static RunOptions xvfb() {
        return {.prefix = without_leak_check() + " xvfb-run -a -s '-screen 0 1280x1024x24'"};
    }

    // The window's last frame, out("window.png") at 800×500, against --screenshot of `file` with
    // the same options: the same picture right of the panel, and clearly not the diffuse part
    // alone (k = 1, the same `size` and light). Returns the window's frame.
    Png expect_window_shows_glossy(const std::string& file, const std::string& size,
                                   const std::string& shading) {
        EXPECT_EQ(
            shprt("view '" + file + "' --screenshot '" + out("shot.png") + "'" + size + shading)
                .exit_code,
            0);
        EXPECT_EQ(
            shprt("view '" + file + "' --screenshot '" + out("diffuse.png") + "'" + size + " --k 1")
                .exit_code,
            0);
        const Png win = read_png(out("window.png")), shot = read_png(out("shot.png")),
                  diffuse = read_png(out("diffuse.png"));
        EXPECT_LE(compare(win, shot, 400, 0, 800, 500).mean, kMaxMeanWindowDifference) << file;
        EXPECT_GT(compare(win, diffuse, 400, 0, 800, 500).mean,
                  compare(win, shot, 400, 0, 800, 500).mean + 0.5)
            << file;
        return win;
    }
};

// Pixels right of the panel's column (x ≥ 400) whose green is over 100: a lit scene has some.
int bright_pixels_right_of_the_panel(const Png& png) {
    int bright = 0;
    for (int y = 0; y < png.height; ++y)
        for (int x = 400; x < png.width; ++x)
            bright += png.rgb[(std::size_t(y) * png.width + x) * 3 + 1] > 100;
    return bright;
}

TEST_F(CliViewWindow, OpensUnderXvfbDrawsThePanelAndTheSamePicture) {
    const std::string size = " --size 800x500";
    const RunResult w = shprt(
        "view '" + s_file + "' --frames 3 --window-screenshot '" + out("window.png") + "'" + size,
        xvfb());
    ASSERT_EQ(w.exit_code, 0) << w.err;
    EXPECT_NE(w.out.find("view: 3 frames"), std::string::npos) << w.out;
    const RunResult s =
        shprt("view '" + s_file + "' --screenshot '" + out("shot.png") + "'" + size);
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const Png win = read_png(out("window.png")), shot = read_png(out("shot.png"));
    ASSERT_EQ(win.width, 800);
    ASSERT_EQ(win.height, 500);
    ASSERT_EQ(shot.width, 800);
    // Right of the panel (at x = 8, 340 wide): the same picture as --screenshot.
    const Diff right = compare(win, shot, 400, 0, 800, 500);
    EXPECT_LE(right.mean, kMaxMeanWindowDifference);
    // The panel: clearly different from the picture, and not blank.
    const Diff panel = compare(win, shot, 10, 10, 340, 200);
    EXPECT_GE(panel.mean, kMinMeanPanelDifference);
    std::vector<bool> seen(256 * 256, false);
    int colours = 0;
    for (std::size_t i = 0; i < win.rgb.size(); i += 3) {
        const int key =
            (win.rgb[i] >> 2) * 1024 + (win.rgb[i + 1] >> 2) * 16 + (win.rgb[i + 2] >> 4);
        if (key < int(seen.size()) && !seen[key]) seen[key] = true, ++colours;
    }
    EXPECT_GT(colours, 50) << "the window is not blank";
}

// A texel file in the window: the panel without the glossy sliders, the same picture.
TEST_F(CliViewWindow, ShowsATexelFile) {
    const std::string texel = bake_texel_file();
    const std::string size = " --size 800x500";
    const RunResult w = shprt(
        "view '" + texel + "' --frames 2 --window-screenshot '" + out("window.png") + "'" + size,
        xvfb());
    ASSERT_EQ(w.exit_code, 0) << w.err;
    const RunResult s = shprt("view '" + texel + "' --screenshot '" + out("shot.png") + "'" + size);
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const Diff right =
        compare(read_png(out("window.png")), read_png(out("shot.png")), 400, 0, 800, 500);
    EXPECT_LE(right.mean, kMaxMeanWindowDifference);
}

// The window starts with --direct's picture (the panel's toggle uploads the same way).
TEST_F(CliViewWindow, StartsWithTheDirectPartWithDirect) {
    const std::string ir = (s_dir / "ir.shprt").string();
    const std::string size = " --size 800x500 --light sun:1,2,1,6";
    for (const std::string direct : {"", " --direct"}) {
        const RunResult w = shprt("view '" + ir + "' --frames 2 --window-screenshot '" +
                                      out("window.png") + "'" + size + direct,
                                  xvfb());
        ASSERT_EQ(w.exit_code, 0) << w.err;
        ASSERT_EQ(shprt("view '" + ir + "' --screenshot '" + out("shot.png") + "'" + size + direct)
                      .exit_code,
                  0);
        ASSERT_EQ(shprt("view '" + ir + "' --screenshot '" + out("other.png") + "'" + size +
                        (direct.empty() ? " --direct" : ""))
                      .exit_code,
                  0);
        const Png win = read_png(out("window.png")), shot = read_png(out("shot.png")),
                  other = read_png(out("other.png"));
        ASSERT_EQ(win.width, 800);
        // Right of the panel: this picture, and clearly not the other one.
        EXPECT_LE(compare(win, shot, 400, 0, 800, 500).mean, kMaxMeanWindowDifference) << direct;
        EXPECT_GT(compare(win, other, 400, 0, 800, 500).mean,
                  compare(win, shot, 400, 0, 800, 500).mean + 0.5)
            << direct;
    }
}

// Glossy matrices and their CPCA code in the window: the glossy term drawn live, as --screenshot
// draws it (and clearly not the diffuse part alone).
TEST_F(CliViewWindow, ShadesGlossyMatricesAndCpcaCodes) {
    const std::string glossy = out("glossy.shprt"), cpca = out("cpca.shprt");
    ASSERT_EQ(shprt("bake builtin:box_on_plane --transfer glossy --bands 4 --samples 256 -o '" +
                    glossy + "'")
                  .exit_code,
              0);
    ASSERT_EQ(shprt("compress '" + glossy + "' -o '" + cpca + "' --cpca 8,4").exit_code, 0);
    const std::string size = " --size 800x500 --light sun:1,2,1,6";
    for (const std::string& file : {glossy, cpca}) {
        const std::string shading = " --brdf phong:24 --k 0.2";
        const RunResult w = shprt("view '" + file + "' --frames 2 --window-screenshot '" +
                                      out("window.png") + "'" + size + shading,
                                  xvfb());
        ASSERT_EQ(w.exit_code, 0) << w.err;
        expect_window_shows_glossy(file, size, shading);
    }
}

// Glossy matrices per texel, and a scene whose materials give BRDFs, in the window: the panel
// starts from the options (k below 1 for texels, the material BRDFs on), as --screenshot draws.
TEST_F(CliViewWindow, ShadesGlossyTexelsAndMaterialBrdfs) {
    const std::string texel = out("texel.shprt"), spheres = out("spheres.shprt");
    ASSERT_EQ(shprt("bake builtin:quad_box --domain texel --resolution 64 --transfer glossy "
                    "--bands 3 --samples 128 -o '" +
                    texel + "'")
                  .exit_code,
              0);
    ASSERT_EQ(shprt("bake builtin:gloss_spheres --transfer glossy --bands 3 --samples 128 -o '" +
                    spheres + "'")
                  .exit_code,
              0);
    const std::string size = " --size 800x500 --light sun:1,2,1,6";
    for (const auto& [file, shading] :
         {std::pair<std::string, std::string>{texel, " --brdf phong:24 --k 0.2"},
          {spheres, " --k 0.2 --camera 0,1.6,4,0,0.55,0"}}) {
        const RunResult w = shprt("view '" + file + "' --frames 2 --window-screenshot '" +
                                      out("window.png") + "'" + size + shading,
                                  xvfb());
        ASSERT_EQ(w.exit_code, 0) << w.err;
        expect_window_shows_glossy(file, size, shading);
    }
    // The spheres' window is not the one-BRDF picture either.
    ASSERT_EQ(shprt("view '" + spheres + "' --screenshot '" + out("one.png") + "'" + size +
                    " --k 0.2 --camera 0,1.6,4,0,0.55,0 --brdf phong:16")
                  .exit_code,
              0);
    EXPECT_GT(
        compare(read_png(out("window.png")), read_png(out("one.png")), 400, 0, 800, 500).mean,
        compare(read_png(out("window.png")), read_png(out("shot.png")), 400, 0, 800, 500).mean +
            0.2);
}

// A glossy bake shown while it refines: once it ends, the window draws what --screenshot draws
// for the baked file (and clearly not its diffuse part alone).
TEST_F(CliViewWindow, ShowsAGlossyBakeWhileItRefines) {
    const std::string bake = " --transfer glossy --bands 4 --samples 128 --seed 3";
    const std::string size = " --size 800x500 --light sun:1,2,1,6 --light constant:0.5";
    const std::string shading = " --brdf phong:24 --k 0.3";
    const RunResult w =
        shprt("view builtin:box_on_plane --bake" + bake + " --frames 2 --window-screenshot '" +
                  out("window.png") + "'" + size + shading,
              xvfb());
    ASSERT_EQ(w.exit_code, 0) << w.err;
    EXPECT_NE(w.out.find("baked 1214 vertices, K=16"), std::string::npos) << w.out;
    const std::string file = (m_dir / "glossy.shprt").string();
    ASSERT_EQ(shprt("bake builtin:box_on_plane" + bake + " -o '" + file + "'").exit_code, 0);
    const Png win = expect_window_shows_glossy(file, size, shading);
    // The plane and the box are lit: a tenth of the window's pixels right of the panel is bright.
    EXPECT_GT(bright_pixels_right_of_the_panel(win), (win.width - 400) * win.height / 10);
}

TEST_F(CliViewWindow, ShowsABakeWhileItRefinesAndFinishesIt) {
    const RunResult r = shprt(
        "view builtin:box_on_plane --bake --coeffs 16 --samples 64 --frames 2 "
        "--size 640x360 --window-screenshot '" +
            out("bake.png") + "'",
        xvfb());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("baked 1214 vertices, K=16"), std::string::npos) << r.out;
    const Png png = read_png(out("bake.png"));
    ASSERT_EQ(png.width, 640);
    // The baked scene is lit: some bright pixels outside the panel's column.
    EXPECT_GT(bright_pixels_right_of_the_panel(png), 0);
}

TEST_F(CliViewWindow, TheWindowFallbackGivesTheSameScreenshotAsEgl) {
    const RunResult e = shprt("view '" + s_file + "' --screenshot '" + out("egl.png") +
                              "' --size 100x70 --offscreen egl");
    ASSERT_EQ(e.exit_code, 0) << e.err;
    const RunResult g = shprt("view '" + s_file + "' --screenshot '" + out("glx.png") +
                                  "' --size 100x70 --offscreen window",
                              xvfb());
    ASSERT_EQ(g.exit_code, 0) << g.err;
    const Png a = read_png(out("egl.png")), b = read_png(out("glx.png"));
    ASSERT_EQ(a.width, b.width);
    const Diff d = compare(a, b, 0, 0, a.width, a.height);
    EXPECT_LE(d.max, kMaxLevelDifference);
    EXPECT_LE(d.mean, kMaxMeanLevelDifference);
}

}  // namespace
