// Float RGB images, and reading them: environment maps (light specs) are read here. Pictures are
// written by shade/save_image.hpp, a layer up.
//
// Pixels are linear RGB floats (radiance or any linear quantity), row-major, row 0 at the top of
// the picture, three floats per pixel. Reading is chosen by the file's extension:
//
//   .exr  OpenEXR through tinyexr: R, G, B channels (half or float; a single-channel file is read
//         as grey; A is ignored).
//   .hdr  Radiance RGBE through stb_image (8-bit mantissas with a shared exponent: relative
//         precision about 2^-8 of the pixel's largest channel).
//   .png  8-bit sRGB through stb_image, decoded to linear with the exact sRGB curve
//         (core/colour.hpp; 16-bit PNGs are reduced to 8 bits first; alpha is ignored).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace shprt {

// Largest side of an image read or written: far beyond any environment map, small enough that
// width·height·3 floats cannot overflow.
inline constexpr int kMaxImageSide = 1 << 15;
// Largest pixel count of an image read: 2^27 pixels (16384 x 8192, an equirect map far sharper
// than any SH light can use) is 1.5 GiB of float RGB. Checked from the file's header, before a
// pixel is decoded, so a small file claiming a huge image costs nothing.
inline constexpr std::size_t kMaxImagePixels = std::size_t(1) << 27;

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

// Called with an image's width and height as its header gives them, before any pixel is decoded;
// throws to refuse the image (a light refuses a shape it cannot use).
using ImageSizeCheck = std::function<void(int width, int height)>;

// Reads an image by extension (.exr, .hdr, .png; case-insensitive). Throws shprt::Error naming
// the file: ErrorCode::io if it is missing or unreadable; ErrorCode::format if it is truncated,
// malformed, empty, larger than kMaxImageSide on a side or kMaxImagePixels in all (both checked
// from the header, before decoding), or holds a NaN or infinite pixel (the message names the
// first such pixel); ErrorCode::unsupported for any other extension. `check_size`, when given,
// is called with the header's size before decoding as well.
Image load_image(const std::string& path, const ImageSizeCheck& check_size = {});

// Receives one row of an image: y from the top, width·3 floats (valid during the call only).
using ImageRowSink = std::function<void(int y, const float* rgb)>;

// Reads an image as load_image does (the same checks and errors; `check_size` is called before
// the first row), but hands it over a row at a time, top row first, so that a caller that needs
// one row at a time (an SH projection) never holds the whole picture. OpenEXR scanline files in
// increasing line order (NONE, RLE, ZIPS, ZIP or PIZ compression: what writers make) are decoded
// about 64 rows at a time: memory is the file's bytes plus O(width · 64) floats, whatever the
// height. Other OpenEXR files (tiled ones), .hdr and .png are decoded whole first. A NaN or
// infinite pixel throws when its row is reached, after the rows above it were handed over.
void read_image_rows(const std::string& path, const ImageSizeCheck& check_size,
                     const ImageRowSink& row);

// Throws Error(format) "image NAME has a NaN value at pixel (x, y) channel R" (or "infinite") for
// the first non-finite value: the check load_image makes, for images from elsewhere (Python).
void check_image_finite(const std::string& name, const Image& image);

}  // namespace shprt
