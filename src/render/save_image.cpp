// Picture files (save_image.hpp): OpenEXR through tinyexr, Radiance RGBE and PNG through
// stb_image_write. References: Greg Ward, "Real Pixels" (Graphics Gems II, 1991) for RGBE;
// IEC 61966-2-1 for sRGB; Narkowicz 2016 for the filmic tone map (render/tonemap.hpp).
#include "shprt/render/save_image.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/render/tonemap.hpp"

#include <stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>

namespace shprt {
namespace {

void append_bytes(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
}

std::string encode_exr(const std::string& path, const Image& image) {
    // EXR stores channels in alphabetical order; tinyexr writes them in the order given.
    const std::size_t n = image.pixel_count();
    std::vector<float> planes[3];  // B, G, R
    for (int c = 0; c < 3; ++c) {
        planes[c].resize(n);
        for (std::size_t p = 0; p < n; ++p) planes[c][p] = image.rgb[3 * p + (2 - c)];
    }
    float* plane_ptrs[3] = {planes[0].data(), planes[1].data(), planes[2].data()};

    EXRImage exr_image;
    InitEXRImage(&exr_image);
    exr_image.num_channels = 3;
    exr_image.images = reinterpret_cast<unsigned char**>(plane_ptrs);
    exr_image.width = image.width;
    exr_image.height = image.height;

    EXRHeader header;
    InitEXRHeader(&header);
    EXRChannelInfo channels[3];
    std::memset(channels, 0, sizeof(channels));
    const char* names[3] = {"B", "G", "R"};
    int pixel_types[3], requested[3];
    for (int c = 0; c < 3; ++c) {
        std::strncpy(channels[c].name, names[c], sizeof(channels[c].name) - 1);
        pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;  // type of the data we hand over
        requested[c] = TINYEXR_PIXELTYPE_FLOAT;    // type stored in the file: full float
    }
    header.num_channels = 3;
    header.channels = channels;
    header.pixel_types = pixel_types;
    header.requested_pixel_types = requested;
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

    unsigned char* memory = nullptr;
    const char* err = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&exr_image, &header, &memory, &err);
    std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
    if (size == 0 || memory == nullptr) {
        const std::string message = err ? err : "unknown tinyexr error";
        if (err) FreeEXRErrorMessage(err);
        fail(ErrorCode::io, "cannot encode image {}: {}", path, message);
    }
    return std::string(reinterpret_cast<const char*>(memory), size);
}

std::string encode_hdr(const std::string& path, const Image& image) {
    // RGBE has no sign: negative values are stored as 0.
    std::vector<float> clamped(image.rgb.size());
    for (std::size_t i = 0; i < clamped.size(); ++i) clamped[i] = std::max(image.rgb[i], 0.0f);
    std::string out;
    SHPRT_CHECK(stbi_write_hdr_to_func(append_bytes, &out, image.width, image.height, 3,
                                       clamped.data()) != 0,
                io, "cannot encode image {} as .hdr", path);
    return out;
}

std::string encode_png(const std::string& path, const Rgb8Image& image) {
    std::string out;
    SHPRT_CHECK(stbi_write_png_to_func(append_bytes, &out, image.width, image.height, 3,
                                       image.rgb.data(), image.width * 3) != 0,
                io, "cannot encode image {} as .png", path);
    return out;
}

void write_atomically(const std::string& path, const std::string& bytes) {
    AtomicFile file(path);
    file.write(bytes.data(), bytes.size());
    file.commit();
}

}  // namespace

void save_image(const std::string& path, const Image& image, float exposure) {
    const std::string ext = lower_extension(path);
    SHPRT_CHECK(ext == ".exr" || ext == ".hdr" || ext == ".png", unsupported,
                "cannot write image {}: unknown extension '{}' (expected .exr, .hdr or .png)", path,
                ext);
    SHPRT_CHECK(!image.empty() && image.width <= kMaxImageSide && image.height <= kMaxImageSide,
                invalid_argument, "cannot write image {}: invalid size {}x{}", path, image.width,
                image.height);
    SHPRT_CHECK(image.rgb.size() == 3 * image.pixel_count(), invalid_argument,
                "cannot write image {}: {} floats for {}x{} RGB pixels (expected {})", path,
                image.rgb.size(), image.width, image.height, 3 * image.pixel_count());
    SHPRT_CHECK(std::isfinite(exposure) && exposure > 0.0f, invalid_argument,
                "cannot write image {}: exposure {} must be positive", path, exposure);
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        const std::size_t p = i / 3;
        SHPRT_CHECK(std::isfinite(image.rgb[i]), invalid_argument,
                    "cannot write image {}: pixel ({}, {}) is not finite", path,
                    p % std::size_t(image.width), p / std::size_t(image.width));
    }
    if (ext == ".exr") return write_atomically(path, encode_exr(path, image));
    if (ext == ".hdr") return write_atomically(path, encode_hdr(path, image));
    Rgb8Image display{image.width, image.height, std::vector<std::uint8_t>(image.rgb.size())};
    for (std::size_t i = 0; i < display.rgb.size(); ++i)
        display.rgb[i] = display_encode8(image.rgb[i], exposure);
    write_atomically(path, encode_png(path, display));
}

void save_png(const std::string& path, const Rgb8Image& image) {
    SHPRT_CHECK(image.width > 0 && image.height > 0 && image.width <= kMaxImageSide &&
                    image.height <= kMaxImageSide &&
                    image.rgb.size() == std::size_t(image.width) * std::size_t(image.height) * 3,
                invalid_argument, "cannot write image {}: {} bytes for {}x{} RGB pixels", path,
                image.rgb.size(), image.width, image.height);
    write_atomically(path, encode_png(path, image));
}

}  // namespace shprt
