// Image files for the light tests, written without the library's picture writer (save_image lives
// in render/, a layer above light/, and the reader is tested on its own): .exr through tinyexr as
// 32-bit float (so a round trip is bit-exact), .hdr through stb_image_write (RGBE), .png through
// stb_image_write as plain 8-bit sRGB of the linear values (clamped to [0, 1], no tone map).
#pragma once

#include "shprt/core/colour.hpp"
#include "shprt/light/image.hpp"

#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace shprt::test_support {

// Writes `image` to `path` by extension (.exr, .hdr or .png); fails the test otherwise.
inline void write_test_image(const std::string& path, const Image& image) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
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
