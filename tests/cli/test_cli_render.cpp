// `shprt shade` and `shprt render` run as programs: the white furnace through the CLI, every
// export format read back in vertex order, the CLI agrees with the library, pictures come out;
// bad input (corrupt file, missing light file, bad options, no OpenGL 4.3) gives a one-line
// error, a non-zero exit code and no output file.
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/math.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/image.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/shade.hpp"

#include "cli/cli_test.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace shprt {
namespace {

using test_support::expect_one_line_error;
using test_support::RunResult;

// The unit sphere with analytic unshadowed transfer (clamped cosine about each normal, K = 16).
TransferSet sphere_transfer(const Mesh& mesh, int K) {
    TransferSet t;
    t.kind = TransferKind::unshadowed;
    t.layout.K = K;
    t.coeffs.resize(mesh.vertex_count() * std::size_t(K));
    const std::vector<double> z = clamped_cosine_zonal(sh_bands_for(K));
    std::vector<double> c(K);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        rotate_zonal(z.data(), K, normalize(cast<double>(mesh.normals[v])), c.data());
        for (int i = 0; i < K; ++i) t.coeffs[v * K + i] = static_cast<float>(c[i]);
    }
    return t;
}

class CliRender : public test_support::CliTest {
protected:
    void SetUp() override {
        CliTest::SetUp();
        m_mesh = make_builtin("sphere");
        m_file = (m_dir / "sphere.shprt").string();
        write_shprt(m_file, m_mesh, sphere_transfer(m_mesh, 16));
    }
    static std::vector<std::vector<double>> read_csv(const std::string& path, std::string& header) {
        std::istringstream in(read_file(path));
        std::getline(in, header);
        std::vector<std::vector<double>> rows;
        std::string line, cell;
        while (std::getline(in, line)) {
            std::istringstream row(line);
            rows.emplace_back();
            while (std::getline(row, cell, ','))
                rows.back().push_back(std::strtod(cell.c_str(), nullptr));
        }
        return rows;
    }

    static bool have_gl() {
        try {
            HeadlessGlContext context;
            return true;
        } catch (const Error&) {
            return false;
        }
    }

    Mesh m_mesh;
    std::string m_file;
};

TEST_F(CliRender, ShadeWhiteFurnaceCsvIsPiAtEveryVertexInInputOrder) {
    const RunResult r = shprt("shade '" + m_file + "' --light constant -o '" + out("e.csv") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("shaded 642 vertices"), std::string::npos) << r.out;
    std::string header;
    const auto rows = read_csv(out("e.csv"), header);
    EXPECT_EQ(header, "x,y,z,E_r,E_g,E_b,L_r,L_g,L_b");
    ASSERT_EQ(rows.size(), m_mesh.vertex_count());
    for (std::size_t v = 0; v < rows.size(); ++v) {
        ASSERT_EQ(rows[v].size(), 9u);
        for (int k = 0; k < 3; ++k) ASSERT_EQ(float(rows[v][k]), m_mesh.positions[v][k]) << v;
        for (int k = 3; k < 6; ++k) ASSERT_NEAR(rows[v][k], kPi, 1e-5) << v;
        for (int k = 6; k < 9; ++k) ASSERT_NEAR(rows[v][k], m_mesh.albedo[v][k - 6], 1e-6) << v;
    }
}

TEST_F(CliRender, ShadeAgreesWithTheLibraryAndWritesNpyAndPly) {
    const std::string opts =
        " --light builtin --light constant:0.2 --rotate 30,10,0 --window hann "
        "--k 0.5 --gloss 8 --eye 0.5,2,3 --shading-coeffs 12";
    ASSERT_EQ(shprt("shade '" + m_file + "'" + opts + " -o '" + out("s.csv") + "'").exit_code, 0);
    ASSERT_EQ(shprt("shade '" + m_file + "'" + opts + " -o '" + out("s.npy") + "'").exit_code, 0);
    const RunResult ply = shprt("shade '" + m_file + "'" + opts + " -o '" + out("s.ply") + "'");
    ASSERT_EQ(ply.exit_code, 0) << ply.err;

    LightSetup setup;
    setup.specs = {"builtin", "constant:0.2"};
    setup.yaw_pitch_roll_deg = {30, 10, 0};
    setup.window = WindowKind::hann;
    const ShprtFile file = read_shprt(m_file);
    ShadeOptions options;
    options.k = 0.5;
    options.gloss = 8;
    options.eye = {0.5f, 2, 3};
    options.K_used = 12;
    const ShadeResult want =
        shade_vertices(file.mesh, file.transfer, prepare_light(setup, 16), options);
    std::string header;
    const auto rows = read_csv(out("s.csv"), header);
    ASSERT_EQ(rows.size(), m_mesh.vertex_count());
    const std::string npy = read_file(out("s.npy"));
    const std::size_t data = 10 + (std::size_t(static_cast<unsigned char>(npy[8])) |
                                   std::size_t(static_cast<unsigned char>(npy[9])) << 8);
    ASSERT_EQ(npy.size() - data, rows.size() * 9 * sizeof(float));
    for (std::size_t v = 0; v < rows.size(); ++v)
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(float(rows[v][3 + c]), want.irradiance[v][c]) << v;
            ASSERT_EQ(float(rows[v][6 + c]), want.radiance[v][c]) << v;
            float n[2];
            std::memcpy(n, npy.data() + data + (v * 9 + 3 + c) * sizeof(float), sizeof(float));
            std::memcpy(n + 1, npy.data() + data + (v * 9 + 6 + c) * sizeof(float), sizeof(float));
            ASSERT_EQ(n[0], want.irradiance[v][c]);
            ASSERT_EQ(n[1], want.radiance[v][c]);
        }
    const std::string plybytes = read_file(out("s.ply"));
    EXPECT_EQ(plybytes.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    EXPECT_NE(plybytes.find("element vertex 642\n"), std::string::npos);
}

TEST_F(CliRender, ShadeDefaultLightIsBuiltin) {
    ASSERT_EQ(shprt("shade '" + m_file + "' -o '" + out("a.csv") + "'").exit_code, 0);
    ASSERT_EQ(shprt("shade '" + m_file + "' --light builtin -o '" + out("b.csv") + "'").exit_code,
              0);
    EXPECT_EQ(read_file(out("a.csv")), read_file(out("b.csv")));
}

// The CLI's linear picture against the library's: the same code on the same GL, and not black.
void expect_same_picture(const Image& got, const Image& want) {
    ASSERT_EQ(got.rgb.size(), want.rgb.size());
    double worst = 0, sum = 0;
    for (std::size_t i = 0; i < want.rgb.size(); ++i) {
        worst = std::max(worst, double(std::abs(got.rgb[i] - want.rgb[i])));
        sum += got.rgb[i];
    }
    EXPECT_LT(worst, 1e-5);
    EXPECT_GT(sum, 0.0);
}

TEST_F(CliRender, RenderWritesPngAndExrThatMatchTheLibrary) {
    if (!have_gl()) GTEST_SKIP() << "no headless OpenGL 4.3 (EGL) on this machine";
    const std::string cam = " --camera 2.5,1.5,2,0,0,0 --fov 40 --size 96x64 --k 0.7";
    RunResult r =
        shprt("render '" + m_file + "' --light builtin" + cam + " -o '" + out("s.exr") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("rendered 96x64"), std::string::npos) << r.out;
    r = shprt("render '" + m_file + "' --light builtin" + cam + " --exposure 2 -o '" +
              out("s.png") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Image exr = load_image(out("s.exr"));
    const Image png = load_image(out("s.png"));
    ASSERT_EQ(exr.width, 96);
    ASSERT_EQ(exr.height, 64);
    ASSERT_EQ(png.width, 96);

    const ShprtFile file = read_shprt(m_file);
    DrawSettings settings;
    settings.camera.eye = {2.5f, 1.5f, 2};
    settings.camera.target = {0, 0, 0};
    settings.camera.fov_y_deg = 40;
    fit_clip_planes(settings.camera, mesh_bounds(file.mesh));
    settings.k = 0.7;
    const Image want =
        render_image(file.mesh, file.transfer, prepare_light({}, 16), settings, 96, 64);
    expect_same_picture(exr, want);
}

TEST_F(CliRender, RenderDefaultCameraAndOptions) {
    if (!have_gl()) GTEST_SKIP() << "no headless OpenGL 4.3 (EGL) on this machine";
    const RunResult r = shprt("render '" + m_file +
                              "' --size 64x48 --background --view irradiance "
                              "--samples 1 -o '" +
                              out("d.png") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Image img = load_image(out("d.png"));
    EXPECT_EQ(img.width, 64);
    EXPECT_EQ(img.height, 48);
}

TEST_F(CliRender, RenderOfATexelFileIsTheLibrarysPerFragmentPicture) {
    if (!have_gl()) GTEST_SKIP() << "no headless OpenGL 4.3 (EGL) on this machine";
    const std::string file = out("t.shprt");
    RunResult r =
        shprt("bake builtin:quad_box --domain texel --resolution 32 --samples 64 --coeffs 9 -o '" +
              file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string cam = " --camera 0,5,3,0,0,0 --fov 40 --size 64x48 --light builtin";
    r = shprt("render '" + file + "'" + cam + " -o '" + out("t.exr") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("rendered 64x48 (K'=9"), std::string::npos) << r.out;
    const Image exr = load_image(out("t.exr"));
    const ShprtFile f = read_shprt(file);
    DrawSettings settings;
    settings.camera.eye = {0, 5, 3};
    settings.camera.target = {0, 0, 0};
    settings.camera.fov_y_deg = 40;
    fit_clip_planes(settings.camera, mesh_bounds(f.mesh));
    const Image want = render_image(f.mesh, f.transfer, prepare_light({}, 9), settings, 64, 48);
    expect_same_picture(exr, want);
    // The paper's glossy term is not drawn per texel: one line, no picture.
    expect_one_line_error(
        shprt("render '" + file + "'" + cam + " --k 0.5 -o '" + out("g.png") + "'"),
        "the paper's glossy term is not drawn per texel");
    EXPECT_FALSE(fs::exists(out("g.png")));
}

TEST_F(CliRender, BadInputGivesOneLineErrorsAndNoOutput) {
    // A corrupt file: the first half of a valid one.
    const std::string bytes = read_file(m_file);
    const std::string corrupt = (m_dir / "corrupt.shprt").string();
    std::ofstream(corrupt, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
    expect_one_line_error(shprt("shade '" + corrupt + "' -o '" + out("c.csv") + "'"),
                          "corrupt.shprt");
    expect_one_line_error(shprt("render '" + corrupt + "' -o '" + out("c.png") + "'"),
                          "corrupt.shprt");
    // A missing light file.
    expect_one_line_error(
        shprt("shade '" + m_file + "' --light /no/such/sky.hdr -o '" + out("m.csv") + "'"),
        "/no/such/sky.hdr");
    expect_one_line_error(
        shprt("render '" + m_file + "' --light /no/such/sky.exr -o '" + out("m.png") + "'"),
        "/no/such/sky.exr");
    // A light file whose decoder reports several problems on several lines (tinyexr: one line
    // per missing header attribute): still one line.
    const std::string exr = (m_dir / "sky.exr").string();
    save_image(exr, Image::make(16, 8));
    std::string sky = read_file(exr);
    for (const std::string name : {"displayWindow", "lineOrder"}) {
        const std::size_t at = sky.find(name);
        ASSERT_NE(at, std::string::npos) << name;
        sky[at + name.size() - 1] = 'X';  // the attribute is now missing
    }
    std::ofstream(exr, std::ios::binary) << sky;
    const RunResult two =
        shprt("shade '" + m_file + "' --light '" + exr + "' -o '" + out("e.csv") + "'");
    expect_one_line_error(two, "\"displayWindow\" attribute not found");
    EXPECT_NE(two.err.find("\"lineOrder\" attribute not found"), std::string::npos) << two.err;
    // Bad options.
    expect_one_line_error(shprt("shade '" + m_file + "' -o '" + out("x.txt") + "'"), "x.txt");
    expect_one_line_error(shprt("shade '" + m_file + "' --k 1.5 -o '" + out("k.csv") + "'"), "--k");
    expect_one_line_error(shprt("shade '" + m_file + "' --window box -o '" + out("w.csv") + "'"),
                          "box");
    expect_one_line_error(shprt("shade '" + m_file + "' --rotate 1,2 -o '" + out("r.csv") + "'"),
                          "1,2");
    expect_one_line_error(shprt("render '" + m_file + "' --size 12 -o '" + out("s.png") + "'"),
                          "12");
    expect_one_line_error(
        shprt("render '" + m_file + "' --camera 1,2,3 -o '" + out("c2.png") + "'"), "1,2,3");
    expect_one_line_error(shprt("render '" + m_file + "' -o '" + out("img.jpg") + "'"), "img.jpg");
    expect_one_line_error(shprt("shade /no/such/file.shprt -o '" + out("n.csv") + "'"),
                          "/no/such/file.shprt");
    EXPECT_TRUE(out_dir_empty());
}

// Non-finite lights and results are an error in shade as in render, never an output: a light too
// bright for float (constant:1e38), an RGBE .hdr whose pixels are ff ff ff ff (1.7e38), and a
// negative radiance in an EXR map (refused as constant:-1 is).
TEST_F(CliRender, ShadeAndRenderRefuseNonFiniteAndNegativeLights) {
    const std::string ff = (m_dir / "ff.hdr").string();
    std::ofstream(ff, std::ios::binary) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n"
                                        << std::string(8, '\xff');
    const std::string neg = (m_dir / "neg.exr").string();
    Image sky = Image::make(16, 8);
    std::fill(sky.rgb.begin(), sky.rgb.end(), 1.0f);
    sky.pixel(3, 2)[0] = -5.0f;
    save_image(neg, sky);
    const std::pair<std::string, std::string> lights[] = {
        {"constant:1e38", "too bright"},
        {"'" + ff + "'", "too bright"},
        {"'" + neg + "'", "negative value -5 at pixel (3, 2)"},
        {"constant:-1", "non-negative"},
    };
    for (const auto& [light, message] : lights) {
        for (const char* name : {"l.csv", "l.npy", "l.ply"})
            expect_one_line_error(
                shprt("shade '" + m_file + "' --light " + light + " -o '" + out(name) + "'"),
                message);
        expect_one_line_error(
            shprt("render '" + m_file + "' --light " + light + " -o '" + out("l.png") + "'"),
            message);
    }
    EXPECT_TRUE(out_dir_empty());
}

// An output that names an input (the .shprt file or a light file; directly, through a symbolic
// link or as a hard link) is refused before any work, and the input is left as it was.
TEST_F(CliRender, ShadeAndRenderNeverWriteOverTheirInput) {
    const std::string before = read_file(m_file);
    const std::string link = (m_dir / "link.ply").string(), hard = (m_dir / "hard.png").string();
    fs::create_symlink(m_file, link);
    fs::create_hard_link(m_file, hard);
    const std::string sky = (m_dir / "sky.exr").string();
    save_image(sky, Image::make(16, 8));
    const std::string sky_before = read_file(sky);
    expect_one_line_error(shprt("shade '" + m_file + "' -o '" + link + "'"),
                          "is the input file " + m_file);
    expect_one_line_error(shprt("render '" + m_file + "' -o '" + hard + "'"),
                          "is the input file " + m_file);
    expect_one_line_error(shprt("render '" + m_file + "' --light '" + sky + "' -o '" + sky + "'"),
                          "output " + sky + " is the input file " + sky);
    expect_one_line_error(
        shprt("render '" + m_file + "' --light 'equirect:" + sky + "' -o '" + sky + "'"),
        "is the input file " + sky);
    EXPECT_EQ(read_file(m_file), before);
    EXPECT_EQ(read_file(sky), sky_before);
}

TEST_F(CliRender, RenderWithoutOpenGl43ReportsTheVersionFound) {
    if (!have_gl()) GTEST_SKIP() << "no headless OpenGL at all on this machine";
    // Mesa honours MESA_GL_VERSION_OVERRIDE: capped at 3.3, no 4.3 core context can be made.
    const RunResult r = shprt("render '" + m_file + "' --size 32x32 -o '" + out("old.png") + "'",
                              {.prefix = "MESA_GL_VERSION_OVERRIDE=3.3"});
    if (r.exit_code == 0) GTEST_SKIP() << "the GL driver ignores MESA_GL_VERSION_OVERRIDE";
    expect_one_line_error(r, "4.3");
    EXPECT_NE(r.err.find("found"), std::string::npos) << r.err;
    EXPECT_TRUE(out_dir_empty());
}

}  // namespace
}  // namespace shprt
