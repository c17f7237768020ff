// The picture writer (shade/save_image.hpp): round trips through load_image (.exr bit-exact,
// .hdr within RGBE precision, .png through the display chain), orientation, display bytes written
// unchanged, the tone map's properties, and bad input refused without leaving a file.
#include "light/image_fixture.hpp"
#include "shade_test_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/light/image.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/tonemap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

TEST(SaveImage, ExrRoundTripIsBitExact) {
    test::TempDir dir;
    Image image = test_support::random_image(37, 19, 1, -2.0f, 50.0f);
    image.rgb[0] = 1e-30f;  // denormal-adjacent and large values survive as float32
    image.rgb[1] = 6.0e4f;
    image.rgb[5] = 1.0e20f;
    save_image(dir.file("a.EXR"), image);  // the extension in any case
    const Image back = load_image(dir.file("a.EXR"));
    ASSERT_EQ(back.width, image.width);
    ASSERT_EQ(back.height, image.height);
    ASSERT_EQ(back.rgb.size(), image.rgb.size());
    EXPECT_EQ(std::memcmp(back.rgb.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
}

TEST(SaveImage, HdrRoundTripWithinRgbePrecision) {
    test::TempDir dir;
    for (int w : {5, 40}) {  // widths below 8 are written flat, 8..32767 run-length encoded
        Image image = test_support::random_image(w, 13, 2, 0.0f, 100.0f);
        for (std::size_t i = 0; i < image.rgb.size(); i += 7) image.rgb[i] *= 1e-3f;
        const std::string p = dir.file(w < 8 ? "flat.hdr" : "rle.hdr");
        save_image(p, image);
        test_support::expect_rgbe_round_trip(image, load_image(p));
    }
}

TEST(SaveImage, HdrNegativeValuesAreStoredAsZero) {
    test::TempDir dir;
    Image image = Image::make(8, 2);
    image.rgb.assign(image.rgb.size(), 0.5f);
    image.rgb[4] = -3.0f;
    save_image(dir.file("neg.hdr"), image);
    const Image back = load_image(dir.file("neg.hdr"));
    EXPECT_EQ(back.rgb[4], 0.0f);
    EXPECT_NEAR(back.rgb[3], 0.5f, test_support::kRgbeRelTol);
}

TEST(SaveImage, PngRoundTripThroughDisplayChain) {
    test::TempDir dir;
    Image image = test_support::random_image(23, 11, 3, 0.0f, 8.0f);
    image.rgb[0] = 0.0f;
    image.rgb[1] = 1000.0f;  // saturates to white
    const float exposure = 0.7f;
    save_image(dir.file("a.png"), image, exposure);
    const Image back = load_image(dir.file("a.png"));
    ASSERT_EQ(back.width, image.width);
    ASSERT_EQ(back.height, image.height);
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        // Exactly the 8-bit code the writer chose, decoded with the sRGB curve...
        const float expected = srgb_to_linear(display_encode8(image.rgb[i], exposure) / 255.0f);
        ASSERT_EQ(back.rgb[i], expected) << "value " << i;
        // ...which is the ACES-mapped value within half an 8-bit sRGB step.
        const float s_true = linear_to_srgb(tonemap_aces(image.rgb[i] * exposure));
        ASSERT_LE(std::abs(linear_to_srgb(back.rgb[i]) - s_true), 0.5f / 255.0f + 1e-6f);
    }
    EXPECT_EQ(back.rgb[0], 0.0f);
    EXPECT_EQ(back.rgb[1], 1.0f);
}

TEST(SaveImage, RowZeroIsTheTop) {
    test::TempDir dir;
    // A PNG written with one bright pixel at (x, y) = (3, 1) reads back there.
    Image image = Image::make(5, 4);
    image.pixel(3, 1)[1] = 100.0f;
    save_image(dir.file("dot.png"), image);
    const Image back = load_image(dir.file("dot.png"));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x)
            EXPECT_EQ(back.pixel(x, y)[1] > 0.5f, x == 3 && y == 1) << x << "," << y;
}

TEST(SaveImage, DisplayBytesAreWrittenUnchangedBySavePng) {
    test::TempDir dir;
    // Every 8-bit code, in every channel, at a known pixel.
    Rgb8Image bytes{16, 16, std::vector<std::uint8_t>(16 * 16 * 3)};
    for (std::size_t i = 0; i < bytes.rgb.size(); ++i)
        bytes.rgb[i] = static_cast<std::uint8_t>((i * 7 + i / 3) & 0xff);
    save_png(dir.file("bytes.png"), bytes);
    const Image back = load_image(dir.file("bytes.png"));
    ASSERT_EQ(back.width, 16);
    ASSERT_EQ(back.height, 16);
    for (std::size_t i = 0; i < bytes.rgb.size(); ++i)
        ASSERT_EQ(back.rgb[i], srgb_to_linear(bytes.rgb[i] / 255.0f)) << i;
    // save_image's PNG is save_png of the display-encoded bytes: the same file.
    Image linear = test_support::random_image(9, 5, 4, 0.0f, 3.0f);
    Rgb8Image encoded{9, 5, std::vector<std::uint8_t>(linear.rgb.size())};
    for (std::size_t i = 0; i < linear.rgb.size(); ++i)
        encoded.rgb[i] = display_encode8(linear.rgb[i], 1.3f);
    save_image(dir.file("linear.png"), linear, 1.3f);
    save_png(dir.file("encoded.png"), encoded);
    EXPECT_EQ(read_file(dir.file("linear.png")), read_file(dir.file("encoded.png")));
    EXPECT_THROW(save_png(dir.file("empty.png"), Rgb8Image{}), Error);
    EXPECT_THROW(save_png(dir.file("short.png"), Rgb8Image{2, 2, std::vector<std::uint8_t>(11)}),
                 Error);
}

TEST(ToneMap, AcesFitProperties) {
    EXPECT_EQ(tonemap_aces(0.0f), 0.0f);
    EXPECT_EQ(tonemap_aces(-1.0f), 0.0f);
    EXPECT_EQ(tonemap_aces(std::numeric_limits<float>::quiet_NaN()), 0.0f);
    EXPECT_NEAR(tonemap_aces(1.0f), 2.54f / 3.16f, 1e-6f);  // the fit's value at 1
    float prev = 0.0f;
    for (float x = 0.01f; x < 100.0f; x *= 1.1f) {
        const float y = tonemap_aces(x);
        EXPECT_GE(y, prev);
        EXPECT_LE(y, 1.0f);
        prev = y;
    }
    EXPECT_EQ(display_encode8(0.0f, 1.0f), 0);
    EXPECT_EQ(display_encode8(1e6f, 1.0f), 255);
}

TEST(SaveImage, BadInputThrowsAndLeavesNoFile) {
    test::TempDir dir;
    Image image = Image::make(2, 2);
    EXPECT_THROW(save_image(dir.file("a.bmp"), image), Error);
    EXPECT_THROW(save_image(dir.file("a.png"), Image{}), Error);
    EXPECT_THROW(save_image(dir.file("a.png"), image, 0.0f), Error);
    Image short_buffer = image;
    short_buffer.rgb.pop_back();
    EXPECT_THROW(save_image(dir.file("a.exr"), short_buffer), Error);
    image.rgb[2] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(save_image(dir.file("a.exr"), image), Error);
    EXPECT_FALSE(fs::exists(dir.file("a.exr")));
    image.rgb[2] = 0.0f;
    EXPECT_THROW(save_image(dir.file("no/such/dir/a.exr"), image), Error);
    EXPECT_TRUE(fs::is_empty(dir.path()));
    // A failed save leaves an existing file untouched.
    save_image(dir.file("keep.exr"), image);
    const std::string before = read_file(dir.file("keep.exr"));
    image.rgb[0] = std::numeric_limits<float>::infinity();
    EXPECT_THROW(save_image(dir.file("keep.exr"), image), Error);
    EXPECT_EQ(read_file(dir.file("keep.exr")), before);
}

}  // namespace
}  // namespace shprt
