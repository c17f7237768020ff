// The one path for a light (light/light_setup.hpp): prepare_light is light_source + rotated_light
// bit for bit, rotated_light rotates before it truncates (exact for a partial last band), the
// identity leaves the source's bits alone, and --rotate's text goes through the one number parser.
#include "shprt/core/error.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/sh/basis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace shprt {
namespace {

// The steps of the path written out with the primitives of light/light.hpp.
ShLight by_hand(const LightSetup& setup, const Mat3d& R, int K) {
    ShLight full = make_light(setup.specs, sh_count(sh_bands_for(K)));
    window_light(full, setup.window, setup.window_strength);
    rotate_light(full, R);
    ShLight out = ShLight::zero(K);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < K; ++i) out.channel(c)[i] = full.channel(c)[i];
    return out;
}

LightSetup sun_setup() {
    LightSetup setup;
    setup.specs = {"sun:1,2,0.5,6", "gradient"};
    setup.window = WindowKind::hann;
    setup.yaw_pitch_roll_deg = {35, -20, 10};
    return setup;
}

TEST(LightPath, RotatedSourceIsPrepareLightBitForBit) {
    const LightSetup setup = sun_setup();
    for (int K : {9, 16, 20, 32, 48}) {  // full bands and partial ones
        const ShLight source = light_source(setup, K);
        EXPECT_EQ(source.K, sh_count(sh_bands_for(K))) << "the source has full bands";
        const ShLight got = rotated_light(source, light_rotation(setup), K);
        const ShLight want = prepare_light(setup, K);
        ASSERT_EQ(got.K, K);
        EXPECT_EQ(got.coeffs, want.coeffs) << "K=" << K;
        EXPECT_EQ(got.coeffs, by_hand(setup, light_rotation(setup), K).coeffs) << "K=" << K;
    }
}

TEST(LightPath, RotatesBeforeItTruncates) {
    // For a partial last band, truncating first and rotating the padded band is not the same
    // light: the path must rotate the full bands, then keep the first K coefficients.
    const LightSetup setup = sun_setup();
    const int K = 20;  // bands 0..3 complete, 4 of band 4's 9 coefficients
    const Mat3d R = light_rotation(setup);
    const ShLight source = light_source(setup, K);
    const ShLight right = rotated_light(source, R, K);
    ShLight wrong = rotated_light(source, Mat3d::identity(), K);  // truncated, unrotated
    rotate_light(wrong, R);                                       // padded band rotated
    double cmax = 0, differ = 0;
    for (std::size_t i = 0; i < right.coeffs.size(); ++i) {
        cmax = std::max(cmax, double(std::abs(right.coeffs[i])));
        differ = std::max(differ, double(std::abs(right.coeffs[i] - wrong.coeffs[i])));
    }
    EXPECT_GT(differ, 1e-3 * cmax) << "the order matters for a partial band";
    // The complete bands agree either way (16 coefficients per channel), to float rounding.
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 16; ++i)
            EXPECT_NEAR(right.channel(c)[i], wrong.channel(c)[i], 2e-6 * cmax) << c << "," << i;
}

TEST(LightPath, TheIdentityKeepsTheSourceBitsAndOnlyTruncates) {
    LightSetup setup = sun_setup();
    setup.yaw_pitch_roll_deg = {0, 0, 0};
    EXPECT_TRUE(light_rotation(setup) == Mat3d::identity());
    const ShLight source = light_source(setup, 20);
    ASSERT_EQ(source.K, 25);
    EXPECT_EQ(rotated_light(source, Mat3d::identity(), 25).coeffs, source.coeffs);
    const ShLight cut = rotated_light(source, Mat3d::identity(), 20);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 20; ++i) EXPECT_EQ(cut.channel(c)[i], source.channel(c)[i]);
    EXPECT_EQ(prepare_light(setup, 20).coeffs, cut.coeffs);
}

// A sun kept out of the SH sum (setup.sun) goes the same way as a `sun:` spec: its projection is
// what the spec gives through the path, bit for bit; its direction turns with --rotate; and the
// SH light of the setup never holds it (no sky at all when there are no specs, not the built-in
// light with its own sun).
TEST(LightPath, TheSunTurnsWithTheRestAndStaysOutOfTheSum) {
    LightSetup setup = sun_setup();
    const Sun sun = parse_sun("1,2,0.5,6", "--sun", "X,Y,Z[,RADIUS_DEG[,R,G,B]]");
    setup.sun = sun;
    LightSetup spec_only = setup;
    spec_only.sun.reset();
    spec_only.specs = {"sun:1,2,0.5,6"};
    for (int K : {16, 48}) {
        const PreparedSun prepared = prepare_sun(setup, K);
        EXPECT_EQ(prepared.sh.coeffs, prepare_light(spec_only, K).coeffs) << K;
        EXPECT_EQ(prepare_light(setup, K).coeffs, [&] {
            LightSetup s = setup;
            s.sun.reset();
            return prepare_light(s, K).coeffs;
        }()) << K;
        const Vec3d expected = light_rotation(setup) * sun.direction;
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(prepared.sun.direction[i], expected[i], 1e-15);
        EXPECT_EQ(prepared.sun.radius_deg, 6.0);
    }
    LightSetup alone;
    alone.sun = sun;
    const ShLight sky = prepare_light(alone, 16);
    EXPECT_TRUE(std::all_of(sky.coeffs.begin(), sky.coeffs.end(), [](float c) { return c == 0; }));
    EXPECT_THROW(prepare_sun(LightSetup{}, 16), Error);
}

TEST(LightPath, BadArgumentsThrow) {
    const ShLight source = light_source(LightSetup{}, 9);
    EXPECT_THROW(rotated_light(source, Mat3d::identity(), 0), Error);
    EXPECT_THROW(rotated_light(source, Mat3d::identity(), 10), Error) << "more than the source";
    ShLight broken = source;
    broken.coeffs.pop_back();
    EXPECT_THROW(rotated_light(broken, Mat3d::identity(), 4), Error);
    EXPECT_THROW(light_source(LightSetup{}, 0), Error);
    EXPECT_THROW(light_source(LightSetup{}, kMaxLightK + 1), Error);
    EXPECT_THROW(prepare_light(LightSetup{}, kMaxLightK + 1), Error);
}

TEST(LightPath, RotationTextIsThreeFiniteNumbers) {
    const Vec3d v = parse_yaw_pitch_roll("30, -10.5,+2e1");
    EXPECT_EQ(v.x, 30.0);
    EXPECT_EQ(v.y, -10.5);
    EXPECT_EQ(v.z, 20.0);
    for (const std::string bad : {"1,2", "1,2,3,4", "1,x,3", "1,nan,3", ""}) {
        try {
            parse_yaw_pitch_roll(bad);
            ADD_FAILURE() << "no error for '" << bad << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
            EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("YAW,PITCH,ROLL"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace shprt
