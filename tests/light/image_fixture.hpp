// Image files for the light tests, written without the library's picture writer (save_image lives
// in render/, a layer above light/, and the reader is tested on its own): .exr through tinyexr as
// 32-bit float (so a round trip is bit-exact), .hdr through stb_image_write (RGBE), .png through
// stb_image_write as plain 8-bit sRGB of the linear values (clamped to [0, 1], no tone map).
#pragma once

#include "shprt/core/colour.hpp"
#include "shprt/core/file.hpp"
#include "shprt/light/image.hpp"

#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace shprt::test_support {

// A w×h image of values uniform in [lo, hi), reproducible from `seed`.
inline Image random_image(int w, int h, unsigned seed, float lo, float hi) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    Image image = Image::make(w, h);
    for (float& v : image.rgb) v = u(rng);
    return image;
}

// RGBE (.hdr) keeps 8 bits of mantissa shared by the three channels: a channel may be off by up to
// 1/128 of the pixel's largest channel.
inline constexpr float kRgbeRelTol = 1.0f / 128.0f;

// Checks that `back` is `image` after an RGBE round trip (sizes equal, every channel within
// kRgbeRelTol of the pixel's largest), and that it lost something (the check is not vacuous).
inline void expect_rgbe_round_trip(const Image& image, const Image& back) {
    ASSERT_EQ(back.width, image.width);
    ASSERT_EQ(back.height, image.height);
    double worst = 0.0;
    for (std::size_t px = 0; px < image.pixel_count(); ++px) {
        const float* a = &image.rgb[3 * px];
        const float* b = &back.rgb[3 * px];
        const float maxc = std::max({a[0], a[1], a[2]});
        for (int c = 0; c < 3; ++c) {
            ASSERT_LE(std::abs(a[c] - b[c]), kRgbeRelTol * maxc) << "pixel " << px;
            worst = std::max(worst, double(std::abs(a[c] - b[c]) / maxc));
        }
    }
    EXPECT_GT(worst, 0.0);  // RGBE is lossy: the check above is not vacuous
}

// Writes `image` to `path` by extension (.exr, .hdr or .png); fails the test otherwise.
inline void write_test_image(const std::string& path, const Image& image) {
    const std::string ext = lower_extension(path);
    if (ext == ".exr") {
        const char* err = nullptr;
        ASSERT_EQ(SaveEXR(image.rgb.data(), image.width, image.height, 3, 0, path.c_str(), &err),
                  TINYEXR_SUCCESS)
            << path << ": " << (err ? err : "");
    } else if (ext == ".hdr") {
        ASSERT_NE(stbi_write_hdr(path.c_str(), image.width, image.height, 3, image.rgb.data()), 0)
            << path;
    } else if (ext == ".png") {
        std::vector<std::uint8_t> bytes(image.rgb.size());
        for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = linear_to_srgb8(image.rgb[i]);
        ASSERT_NE(stbi_write_png(path.c_str(), image.width, image.height, 3, bytes.data(),
                                 image.width * 3),
                  0)
            << path;
    } else {
        FAIL() << "write_test_image: unknown extension of " << path;
    }
}

}  // namespace shprt::test_support
