// Writing pictures: the one path from a rendered image to a file. `shprt render` and the viewer's
// --screenshot both call render_image (render/renderer.hpp) and then save_image, so they write the
// same bytes for the same options.
//
// Pixels are linear RGB floats (light/image.hpp's Image: row 0 at the top, three floats per
// pixel). The format is chosen by the file's extension:
//
//   .exr  OpenEXR through tinyexr: 32-bit float R, G, B, ZIP-compressed, so a round trip through
//         load_image is bit-exact.
//   .hdr  Radiance RGBE through stb_image_write (8-bit mantissas with a shared exponent: relative
//         precision about 2^-8 of the pixel's largest channel; negative values are stored as 0).
//   .png  8-bit sRGB through stb_image_write, display-referred: multiplied by `exposure`, tone
//         mapped with the ACES filmic fit and encoded with the sRGB curve (shade/tonemap.hpp).
//
// Reading images (environment maps) is light/image.hpp's load_image.
#pragma once

#include "shprt/light/image.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

// Writes `image` by extension (.exr, .hdr, .png; case-insensitive) through AtomicFile, so the
// target is either the complete new file or untouched. `exposure` is a linear multiplier used
// for .png only (display output); .exr and .hdr store the radiometric values unchanged.
// Throws Error(invalid_argument) for an empty image, a wrong pixel-buffer size, a non-finite
// pixel or a non-positive exposure, Error(unsupported) for an unknown extension, Error(io) if
// writing fails.
void save_image(const std::string& path, const Image& image, float exposure = 1.0f);
// Before the work: Error(invalid_argument) "output PATH: unknown image format (expected .png,
// .exr or .hdr)" unless `path` ends in one save_image writes (any case).
void check_image_extension(const std::string& path);

// One named channel of an EXR image: width·height floats, rows top first. Names follow EXR's
// "layer.channel" convention ("sh03.R", "Y").
struct ExrChannel {
    std::string name;
    std::vector<float> plane;
};

// Writes `channels` (any number, any finite or non-finite values: NaN marks "no data") as one
// ZIP-compressed OpenEXR image through tinyexr and AtomicFile; `half` stores 16-bit floats
// (else 32-bit). Throws Error(invalid_argument) for a bad size or plane, Error(io).
void save_exr_channels(const std::string& path, int width, int height,
                       const std::vector<ExrChannel>& channels, bool half = false);

// A picture already encoded for display: 8-bit sRGB, three bytes per pixel, rows top first (what
// a window's framebuffer holds).
struct Rgb8Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // width·height·3 bytes
};

// Writes display bytes as an 8-bit RGB PNG, unchanged, through AtomicFile: the same encoder as
// save_image's .png output, without its tone map. Throws Error(invalid_argument) for an empty or
// inconsistent image and Error(io) naming the path if writing fails.
void save_png(const std::string& path, const Rgb8Image& image);

// Data, not a picture: width·height pixels of `channels` (1 to 4: grey, grey + alpha, RGB, RGBA)
// 16-bit samples each, rows top first, written unchanged as a 16-bit PNG (colour type 0, 4, 2 or
// 6, no gamma or colour-space chunk) through AtomicFile. stb_image_write has no 16-bit PNG; this
// is the PNG specification's minimum (IHDR, one zlib-compressed IDAT, IEND, filter 0 on every
// row). Throws Error(invalid_argument) for a bad size or channel count, Error(io).
void save_png16(const std::string& path, int width, int height, int channels,
                const std::vector<std::uint16_t>& samples);

}  // namespace shprt
