// Light specs and light operations: every spec form parses to the light its function gives,
// files by shape (equirect 2:1, cross 4:3/3:4, faces), sums, errors that name the spec or file,
// rotation through SH rotation (a rotated sun is the sun in the rotated direction), windowing.
#include "light/image_fixture.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/light/cubemap.hpp"
#include "shprt/light/equirect.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/window.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace shprt {
namespace {

namespace fs = std::filesystem;

class LightSpec : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("shprt_test_spec_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    fs::path m_dir;
};

Image sky_image(int W, int H) {
    Image image = Image::make(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c)
                image.pixel(x, y)[c] = float(1 + c) * float(x + 2 * y) / float(W + H);
    return image;
}

double max_abs_diff(const ShLight& a, const ShLight& b) {
    EXPECT_EQ(a.K, b.K);
    double m = 0.0;
    for (std::size_t i = 0; i < a.coeffs.size(); ++i)
        m = std::max(m, std::abs(double(a.coeffs[i]) - double(b.coeffs[i])));
    return m;
}

// Expects parse_light(spec) to throw Error(code) whose message contains every `needles` entry.
void expect_spec_error(const std::string& spec, ErrorCode code,
                       std::initializer_list<std::string> needles) {
    try {
        parse_light(spec, 9);
        ADD_FAILURE() << "no error for '" << spec << "'";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), code) << e.what();
        for (const std::string& n : needles)
            EXPECT_NE(std::string(e.what()).find(n), std::string::npos)
                << "'" << n << "' not in: " << e.what();
    }
}

TEST_F(LightSpec, FilesByShape) {
    const int K = 16;
    const Image eq = sky_image(64, 32);
    test_support::write_test_image(path("sky.exr"), eq);
    test_support::write_test_image(path("sky.hdr"), eq);
    EXPECT_EQ(parse_light(path("sky.exr"), K).coeffs, project_equirect(eq, K).coeffs);
    EXPECT_EQ(parse_light("equirect:" + path("sky.exr"), K).coeffs, project_equirect(eq, K).coeffs);
    EXPECT_EQ(parse_light(path("sky.hdr"), K).coeffs,
              project_equirect(load_image(path("sky.hdr")), K).coeffs);
    // Explicit equirect: any aspect.
    const Image wide = sky_image(30, 20);
    test_support::write_test_image(path("wide.exr"), wide);
    EXPECT_EQ(parse_light("equirect:" + path("wide.exr"), K).coeffs,
              project_equirect(wide, K).coeffs);

    const Image hcross = sky_image(64, 48), vcross = sky_image(48, 64);
    test_support::write_test_image(path("h.exr"), hcross);
    test_support::write_test_image(path("v.exr"), vcross);
    test_support::write_test_image(path("h.png"), hcross);
    EXPECT_EQ(parse_light(path("h.exr"), K).coeffs, project_cube_cross(hcross, K).coeffs);
    EXPECT_EQ(parse_light("cross:" + path("h.exr"), K).coeffs,
              project_cube_cross(hcross, K).coeffs);
    EXPECT_EQ(parse_light(path("v.exr"), K).coeffs, project_cube_cross(vcross, K).coeffs);
    EXPECT_EQ(parse_light(path("h.png"), K).coeffs,
              project_cube_cross(load_image(path("h.png")), K).coeffs);

    // Six faces: the horizontal cross cut into its faces.
    CrossCell cells[6];
    cross_cells(CrossLayout::horizontal, cells);
    std::string spec = "faces:";
    for (int f = 0; f < 6; ++f) {
        Image face = Image::make(16, 16);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                for (int c = 0; c < 3; ++c)
                    face.pixel(x, y)[c] =
                        hcross.pixel(cells[f].col * 16 + x, cells[f].row * 16 + y)[c];
        const std::string p = path("face" + std::to_string(f) + ".exr");
        test_support::write_test_image(p, face);
        spec += (f ? "," : "") + p;
    }
    EXPECT_LT(max_abs_diff(parse_light(spec, K), project_cube_cross(hcross, K)), 1e-6);
}

TEST_F(LightSpec, BadFilesNameTheFile) {
    test_support::write_test_image(path("odd.exr"), sky_image(30, 20));
    expect_spec_error(path("odd.exr"), ErrorCode::format, {path("odd.exr"), "30x20", "2:1"});
    expect_spec_error("cross:" + path("odd.exr"), ErrorCode::format, {path("odd.exr"), "4:3"});
    expect_spec_error(path("missing.hdr"), ErrorCode::io, {path("missing.hdr")});
    std::ofstream(path("trunc.hdr")) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n\x02\x02";
    expect_spec_error(path("trunc.hdr"), ErrorCode::format, {path("trunc.hdr"), "truncated"});
    expect_spec_error("faces:" + path("a.exr") + "," + path("b.exr"), ErrorCode::invalid_argument,
                      {"faces:PX,NX,PY,NY,PZ,NZ"});
    test_support::write_test_image(path("sq.exr"), sky_image(8, 8));
    test_support::write_test_image(path("rect.exr"), sky_image(8, 4));
    const std::string sq = path("sq.exr");
    expect_spec_error(
        "faces:" + sq + "," + sq + "," + sq + "," + sq + "," + sq + "," + path("rect.exr"),
        ErrorCode::format, {"not square"});
}

// A light's radiance is ≥ 0, from a file as from constant:V (which refuses -1): a negative
// pixel in a map (EXR can hold one; RGBE and PNG cannot) is refused, naming the file and pixel.
TEST_F(LightSpec, NegativeRadianceIsRefusedEverywhere) {
    Image image = sky_image(64, 32);
    image.pixel(5, 3)[1] = -5.0f;
    test_support::write_test_image(path("neg.exr"), image);
    expect_spec_error(path("neg.exr"), ErrorCode::format,
                      {path("neg.exr"), "negative value -5 at pixel (5, 3) channel G", "≥ 0"});
    expect_spec_error("equirect:" + path("neg.exr"), ErrorCode::format, {"negative"});
    Image face = sky_image(8, 8);
    face.pixel(0, 0)[0] = -0.5f;
    test_support::write_test_image(path("negface.exr"), face);
    test_support::write_test_image(path("face.exr"), sky_image(8, 8));
    const std::string f = path("face.exr");
    expect_spec_error(
        "faces:" + f + "," + f + "," + path("negface.exr") + "," + f + "," + f + "," + f,
        ErrorCode::format, {path("negface.exr"), "negative"});
    expect_spec_error("constant:-1", ErrorCode::invalid_argument, {"non-negative"});
    expect_spec_error("constant:1,-1,1", ErrorCode::invalid_argument, {"non-negative"});
    expect_spec_error("sun:0,1,0,2,1,-1,1", ErrorCode::invalid_argument, {"non-negative"});
    expect_spec_error("gradient:1,1,1:1,-1,1", ErrorCode::invalid_argument, {"non-negative"});
}

// A finite radiance too large for float once projected (constant:1e38; an RGBE pixel ff ff ff ff
// is 1.7e38) would shade to inf and NaN: refused, naming the light.
TEST_F(LightSpec, LightsThatOverflowFloatAreRefused) {
    expect_spec_error("constant:1e38", ErrorCode::invalid_argument,
                      {"'constant:1e38'", "too bright", "overflows float"});
    std::ofstream(path("ff.hdr"), std::ios::binary)
        << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n"
        << std::string(8, '\xff');
    expect_spec_error(path("ff.hdr"), ErrorCode::invalid_argument, {path("ff.hdr"), "too bright"});
    // Each finite, the sum not.
    try {
        make_light({"constant:3e37", "constant:3e37", "constant:3e37", "constant:3e37"}, 9);
        ADD_FAILURE() << "an overflowing sum accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the sum of the lights is too bright"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_NO_THROW(parse_light("constant:3e37", 9));
}

// The shape of a map is checked from its header, before its pixels are decoded (a 389 KB
// 20000 x 20000 PNG was decoded in full, 5.7 GB, before its aspect was refused).
TEST_F(LightSpec, TheShapeIsCheckedBeforeDecoding) {
    // A 30 x 20 PNG header followed by corrupt pixel data: the shape error, not a decode error.
    const auto be32 = [](std::uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    std::string png = "\x89PNG\r\n\x1a\n";
    png += be32(13) + "IHDR" + be32(30) + be32(20) + std::string("\x08\x02\0\0\0", 5) + be32(0);
    png += be32(4) + "IDATjunk" + be32(0) + std::string("\0\0\0\0IEND\xAE\x42\x60\x82", 12);
    std::ofstream(path("odd.png"), std::ios::binary) << png;
    expect_spec_error(path("odd.png"), ErrorCode::format, {path("odd.png"), "30x20", "2:1"});
}

TEST(LightSpecParse, BadSpecsSayWhatIsExpected) {
    expect_spec_error("", ErrorCode::invalid_argument, {"expected"});
    expect_spec_error("nope", ErrorCode::invalid_argument, {"'nope'", "sun:X,Y,Z", "builtin"});
    expect_spec_error("sky.jpg", ErrorCode::invalid_argument, {"'sky.jpg'", "FILE.hdr"});
    expect_spec_error("sun", ErrorCode::invalid_argument, {"'sun'", "sun:X,Y,Z"});
    expect_spec_error("sun:1,2", ErrorCode::invalid_argument, {"'sun:1,2'", "3, 4 or 7"});
    expect_spec_error("sun:0,0,0", ErrorCode::invalid_argument, {"'sun:0,0,0'", "non-zero"});
    expect_spec_error("sun:0,1,0,0", ErrorCode::invalid_argument, {"(0, 90]"});
    expect_spec_error("sun:0,1,0,2,1,1", ErrorCode::invalid_argument, {"3, 4 or 7"});
    expect_spec_error("sun:0,1,x", ErrorCode::invalid_argument, {"'x' is not a number"});
    expect_spec_error("sun:0,1,nan", ErrorCode::invalid_argument, {"not a number"});
    expect_spec_error("sun:0,1,0,2,-1,1,1", ErrorCode::invalid_argument, {"non-negative"});
    expect_spec_error("constant:1,2", ErrorCode::invalid_argument, {"constant:R,G,B"});
    expect_spec_error("constant:", ErrorCode::invalid_argument, {"not a number"});
    expect_spec_error("constant:-1", ErrorCode::invalid_argument, {"non-negative"});
    expect_spec_error("gradient:1,2", ErrorCode::invalid_argument, {"three numbers"});
    expect_spec_error("gradient:1,1,1:2,2,2:3,3,3:4,4,4", ErrorCode::invalid_argument,
                      {"gradient[:ZENITH"});
    expect_spec_error("builtin:3", ErrorCode::invalid_argument, {"no arguments"});
    EXPECT_THROW(parse_light("constant", 0), Error);
    EXPECT_THROW(make_light({"constant", "bad"}, 9), Error);
}

TEST(LightSpecParse, AnalyticSpecsAndSums) {
    const int K = 25;
    EXPECT_EQ(parse_light("sun:1,2,3", K).coeffs,
              sun_light({1, 2, 3}, 2.0, sun_radiance_for_irradiance({3, 3, 3}, 2.0), K).coeffs);
    EXPECT_EQ(parse_light("sun:1,2,3,5", K).coeffs,
              sun_light({1, 2, 3}, 5.0, sun_radiance_for_irradiance({3, 3, 3}, 5.0), K).coeffs);
    EXPECT_EQ(parse_light("sun:+1,2e0,3,5,10,20,30", K).coeffs,
              sun_light({1, 2, 3}, 5.0, {10, 20, 30}, K).coeffs);
    const ShLight sum = make_light({"constant:0.5", "sun:0,1,0", "gradient"}, K);
    ShLight expected = constant_light({0.5, 0.5, 0.5}, K);
    add_light(expected, parse_light("sun:0,1,0", K));
    add_light(expected, gradient_light(GradientSky{}, K));
    EXPECT_EQ(sum.coeffs, expected.coeffs);
    ShLight small = ShLight::zero(4);
    EXPECT_THROW(add_light(small, expected), Error);
    for (const Vec3d d : {Vec3d{0, 1, 0}, Vec3d{0.6, 0, -0.8}})
        EXPECT_NEAR(light_radiance(parse_light("constant:2", 9), d).y, 2.0, 1e-6);
}

// `--sun` and `sun:` share one model (light/sun.hpp): the same numbers give the same sun, and
// every bad value is one line that begins with what the caller named (the option).
TEST(SunSpec, OneModelForBothSpellings) {
    const std::string syntax = "X,Y,Z[,RADIUS_DEG[,R,G,B]]";
    const Sun sun = parse_sun("1,2,3,5", "--sun '1,2,3,5'", syntax);
    EXPECT_NEAR(length(sun.direction), 1.0, 1e-15);
    EXPECT_EQ(sun.radius_deg, 5.0);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sun_irradiance(sun)[c], kDefaultSunIrradiance, 1e-12);
    EXPECT_NEAR(sun_solid_angle(sun), 2 * kPi * (1 - std::cos(5 * kDeg)), 1e-15);
    for (const int K : {1, 25, 256})
        EXPECT_EQ(sun_light(sun, K).coeffs, parse_light("sun:1,2,3,5", K).coeffs) << K;
    EXPECT_EQ(parse_sun("0,1,0,2,10,20,30", "x", syntax).radiance, (Vec3d{10, 20, 30}));

    const auto expect_error = [&](const std::string& numbers, const std::string& needle) {
        const std::string what = "--sun '" + numbers + "'";
        try {
            (void)parse_sun(numbers, what, syntax);
            ADD_FAILURE() << numbers << ": no error";
        } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << m;
            EXPECT_EQ(m.rfind(what, 0), 0u) << m;
            EXPECT_NE(m.find(needle), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    };
    expect_error("1,2", "expected X,Y,Z[,RADIUS_DEG[,R,G,B]] (3, 4 or 7 numbers), got 2");
    expect_error("0,1,0,2,1,1", "(3, 4 or 7 numbers), got 6");
    expect_error("0,0,0", "non-zero");
    expect_error("0,1,0,0", "(0, 90]");
    expect_error("0,1,0,90.5", "(0, 90]");
    expect_error("0,1,0,2,1,-1,1", "non-negative");
    expect_error("0,1,nan", "not a number");
    expect_error("0,1,x", "'x' is not a number");
    expect_error("", "");
}

// The disc directions: inside the cap, uniform in solid angle (stratified: the mean of
// (1 − cos θ)/(1 − cos r) is 1/2 and of cos θ is (1 + cos r)/2, to the strata's error), the centre
// alone for one sample, a pure function of (sun, count, seed), and counts that are not squares
// refused.
TEST(SunSpec, DiscDirections) {
    const Sun sun = make_sun({0.3, 1, -0.2}, 10, {1, 1, 1});
    const double cos_r = std::cos(10 * kDeg);
    for (const int n : {2, 8, 32}) {
        const std::vector<Vec3d> dirs = sun_disc_directions(sun, n * n, 7);
        ASSERT_EQ(dirs.size(), std::size_t(n * n));
        double u = 0, c = 0, x = 0, y = 0;
        const Vec3d t = normalize(cross(sun.direction, Vec3d{1, 0, 0}));
        const Vec3d b = cross(sun.direction, t);
        for (const Vec3d& d : dirs) {
            EXPECT_NEAR(length(d), 1.0, 1e-14);
            EXPECT_GE(dot(d, sun.direction), cos_r - 1e-14);
            u += (1 - dot(d, sun.direction)) / (1 - cos_r);
            c += dot(d, sun.direction);
            x += dot(d, t);
            y += dot(d, b);
        }
        const double N = n * n;
        // A jittered grid: each stratum's mean is off by at most its extent.
        EXPECT_NEAR(u / N, 0.5, 1.0 / n) << n;
        EXPECT_NEAR(c / N, (1 + cos_r) / 2, (1 - cos_r) / n) << n;
        EXPECT_NEAR(x / N, 0.0, std::sin(10 * kDeg) / n) << n;
        EXPECT_NEAR(y / N, 0.0, std::sin(10 * kDeg) / n) << n;
    }
    EXPECT_EQ(sun_disc_directions(sun, 64, 7), sun_disc_directions(sun, 64, 7));
    EXPECT_NE(sun_disc_directions(sun, 64, 7), sun_disc_directions(sun, 64, 8));
    const std::vector<Vec3d> one = sun_disc_directions(sun, 1, 7);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0], sun.direction);
    for (const int bad : {0, -4, 2, 10, 63, kMaxSunSamples + 1, 65 * 65})
        EXPECT_THROW(sun_disc_directions(sun, bad, 7), Error) << bad;
}

// A sun toward s, rotated by R through the SH rotation, is the sun toward R·s (projected
// directly, exactly): "rotate, never re-project" loses nothing for full bands.
TEST(LightOps, RotatedSunIsTheSunInTheRotatedDirection) {
    const Vec3d s = normalize(Vec3d{0.3, 0.8, -0.5});
    for (int K : {9, 36, 256}) {
        for (const Mat3d& R : {matrix_from_yaw_pitch_roll_deg(90, 0, 0),
                               matrix_from_yaw_pitch_roll_deg(-30, 45, 170),
                               matrix_from_quat({0.3, -0.2, 0.9, 0.1})}) {
            ShLight light = sun_light(s, 5.0, {10, 20, 30}, K);
            rotate_light(light, R);
            const ShLight direct = sun_light(R * s, 5.0, {10, 20, 30}, K);
            double cmax = 0.0;
            for (float c : direct.coeffs) cmax = std::max(cmax, double(std::abs(c)));
            EXPECT_LT(max_abs_diff(light, direct), 2e-6 * cmax) << "K=" << K;
        }
    }
    // Yaw 90° turns −Z toward −X: the peak of a sun at −Z moves to −X.
    ShLight light = sun_light({0, 0, -1}, 10.0, {1, 1, 1}, 36);
    rotate_light(light, matrix_from_yaw_pitch_roll_deg(90, 0, 0));
    EXPECT_GT(light_radiance(light, {-1, 0, 0}).x,
              10 * std::abs(light_radiance(light, {0, 0, -1}).x));
    // Identity and a partial last band: defined, and the identity leaves it unchanged.
    ShLight partial = sun_light(s, 5.0, {1, 1, 1}, 10);
    const std::vector<float> before = partial.coeffs;
    rotate_light(partial, Mat3d::identity());
    for (std::size_t i = 0; i < before.size(); ++i) EXPECT_NEAR(partial.coeffs[i], before[i], 1e-6);
    Mat3d not_rotation = Mat3d::identity();
    not_rotation.m[0][0] = 2.0;
    EXPECT_THROW(rotate_light(partial, not_rotation), Error);
}

TEST(LightOps, WindowAppliesToEveryChannel) {
    const int K = 49;
    const ShLight light = sun_light({0.2, 0.9, 0.1}, 2.0, {100, 50, 25}, K);
    for (WindowKind kind : {WindowKind::hann, WindowKind::lanczos, WindowKind::sloan}) {
        const double strength = kind == WindowKind::sloan ? 0.01 : 0.0;
        ShLight windowed = light;
        window_light(windowed, kind, strength);
        for (int c = 0; c < 3; ++c) {
            std::vector<double> expected(light.channel(c), light.channel(c) + K);
            apply_window(kind, expected.data(), K, strength);
            for (int i = 0; i < K; ++i)
                EXPECT_NEAR(windowed.channel(c)[i], expected[i], 1e-6 * std::abs(expected[0]));
            EXPECT_FLOAT_EQ(windowed.channel(c)[0], light.channel(c)[0]);  // w_0 = 1
            // The last band is damped.
            EXPECT_LT(std::abs(windowed.channel(c)[K - 1]), std::abs(light.channel(c)[K - 1]));
        }
    }
    ShLight same = light;
    window_light(same, WindowKind::none);
    EXPECT_EQ(same.coeffs, light.coeffs);
    EXPECT_THROW(window_light(same, WindowKind::sloan, -1.0), Error);
}

}  // namespace
}  // namespace shprt
