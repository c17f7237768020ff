// Float RGB images: environment maps read here, pictures written by the renderer.
//
// Pixels are linear RGB floats (radiance or any linear quantity), row-major, row 0 at the top of
// the picture, three floats per pixel. Reading and writing are chosen by the file's extension:
//
//   .exr  OpenEXR through tinyexr. Read: R, G, B channels (half or float; a single-channel file
//         is read as grey; A is ignored). Written: 32-bit float R, G, B, ZIP-compressed, so a
//         round trip is bit-exact.
//   .hdr  Radiance RGBE through stb_image / stb_image_write (8-bit mantissas with a shared
//         exponent: relative precision about 2^-8 of the pixel's largest channel).
//   .png  8-bit sRGB through stb_image. Read: decoded to linear with the exact sRGB curve
//         (16-bit PNGs are reduced to 8 bits first; alpha is ignored). Written: display-referred —
//         multiplied by `exposure`, tone mapped with the ACES filmic fit and encoded with the sRGB
//         curve (see light/tonemap.hpp).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace shprt {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  // width·height·3 floats, row-major, row 0 at the top

    // A width × height image filled with zeros. Throws Error(invalid_argument) unless both
    // sizes are positive and the pixel count fits memory arithmetic.
    static Image make(int width, int height);

    bool empty() const { return width <= 0 || height <= 0; }
    std::size_t pixel_count() const {
        return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    }
    // Pointer to the three floats of pixel (x, y); x from the left, y from the top. Unchecked.
    float* pixel(int x, int y) {
        return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x);
    }
    const float* pixel(int x, int y) const {
        return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x);
    }
};

// Reads an image by extension (.exr, .hdr, .png; case-insensitive). Throws shprt::Error naming
// the file: ErrorCode::io if it is missing or unreadable; ErrorCode::format if it is truncated,
// malformed, empty, or holds a NaN or infinite pixel (the message names the first such pixel);
// ErrorCode::unsupported for any other extension.
Image load_image(const std::string& path);

// Writes an image by extension (.exr, .hdr, .png; case-insensitive) through AtomicFile, so the
// target is either the complete new file or untouched. `exposure` is a linear multiplier used
// for .png only (display output); .exr and .hdr store the radiometric values unchanged.
// Throws Error(invalid_argument) for an empty image, a wrong pixel-buffer size or a
// non-positive exposure, Error(unsupported) for an unknown extension, Error(io) if writing fails.
void save_image(const std::string& path, const Image& image, float exposure = 1.0f);

}  // namespace shprt
