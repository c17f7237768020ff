// Picture files (save_image.hpp): OpenEXR through tinyexr, Radiance RGBE and PNG through
// stb_image_write; 16-bit PNG data (save_png16) through zlib, after the PNG specification
// (W3C, 2nd edition, 2003: §5 chunk layout and CRC, §11.2.2 IHDR, §9 filter type 0, §10 zlib).
// References: Greg Ward, "Real Pixels" (Graphics Gems II, 1991) for RGBE;
// IEC 61966-2-1 for sRGB; Narkowicz 2016 for the filmic tone map (shade/tonemap.hpp).
#include "shprt/shade/save_image.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/shade/tonemap.hpp"

#include <stb_image_write.h>
#include <tinyexr.h>
#include <zlib.h>

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

// Channels (name, plane of width·height floats) as one ZIP-compressed EXR part; `half` stores
// 16-bit floats. tinyexr writes channels in the order given, and EXR wants them sorted by name.
std::string encode_exr_channels(const std::string& path, int width, int height,
                                std::vector<std::pair<std::string, const float*>> channels,
                                bool half) {
    std::sort(channels.begin(), channels.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const std::size_t n = channels.size();
    std::vector<const float*> plane_ptrs(n);
    std::vector<EXRChannelInfo> info(n);
    std::vector<int> pixel_types(n, TINYEXR_PIXELTYPE_FLOAT);  // type of the data handed over
    std::vector<int> requested(n, half ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT);
    for (std::size_t c = 0; c < n; ++c) {
        std::memset(&info[c], 0, sizeof(info[c]));
        SHPRT_CHECK(channels[c].first.size() < sizeof(info[c].name), invalid_argument,
                    "cannot write image {}: channel name '{}' too long", path, channels[c].first);
        std::strncpy(info[c].name, channels[c].first.c_str(), sizeof(info[c].name) - 1);
        plane_ptrs[c] = channels[c].second;
    }
    EXRImage exr_image;
    InitEXRImage(&exr_image);
    exr_image.num_channels = static_cast<int>(n);
    exr_image.images = reinterpret_cast<unsigned char**>(const_cast<float**>(plane_ptrs.data()));
    exr_image.width = width;
    exr_image.height = height;

    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = static_cast<int>(n);
    header.channels = info.data();
    header.pixel_types = pixel_types.data();
    header.requested_pixel_types = requested.data();
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

std::string encode_exr(const std::string& path, const Image& image) {
    const std::size_t n = image.pixel_count();
    std::vector<float> planes[3];  // R, G, B
    for (int c = 0; c < 3; ++c) {
        planes[c].resize(n);
        for (std::size_t p = 0; p < n; ++p) planes[c][p] = image.rgb[3 * p + c];
    }
    return encode_exr_channels(
        path, image.width, image.height,
        {{"R", planes[0].data()}, {"G", planes[1].data()}, {"B", planes[2].data()}}, false);
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

// One PNG chunk: big-endian length, type, data, CRC-32 of type and data (PNG §5.3).
void append_png_chunk(std::string& out, const char type[4], const std::string& data) {
    const auto be32 = [&out](std::uint32_t x) {
        for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((x >> s) & 0xff));
    };
    be32(static_cast<std::uint32_t>(data.size()));
    const std::size_t start = out.size();
    out.append(type, 4);
    out += data;
    be32(static_cast<std::uint32_t>(
        crc32(0, reinterpret_cast<const Bytef*>(out.data() + start), uInt(out.size() - start))));
}

std::string encode_png16(const std::string& path, int width, int height, int channels,
                         const std::vector<std::uint16_t>& samples) {
    static constexpr int kColourType[5] = {0, 0, 4, 2, 6};  // by channel count
    const std::size_t row = std::size_t(width) * std::size_t(channels);
    std::string raw;  // filter byte 0, then the row's samples big-endian
    raw.reserve((2 * row + 1) * std::size_t(height));
    for (std::size_t y = 0; y < std::size_t(height); ++y) {
        raw.push_back(0);
        for (std::size_t i = 0; i < row; ++i) {
            const std::uint16_t q = samples[y * row + i];
            raw.push_back(static_cast<char>(q >> 8));
            raw.push_back(static_cast<char>(q & 0xff));
        }
    }
    uLongf size = compressBound(uLong(raw.size()));
    std::string idat(size, '\0');
    SHPRT_CHECK(compress2(reinterpret_cast<Bytef*>(idat.data()), &size,
                          reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()),
                          Z_DEFAULT_COMPRESSION) == Z_OK,
                io, "cannot encode image {} as a 16-bit .png", path);
    idat.resize(size);
    std::string ihdr;
    for (const std::uint32_t x : {std::uint32_t(width), std::uint32_t(height)})
        for (int s = 24; s >= 0; s -= 8) ihdr.push_back(static_cast<char>((x >> s) & 0xff));
    // Bit depth 16, the colour type, compression 0, filter method 0, no interlace.
    ihdr += std::string{16, static_cast<char>(kColourType[channels]), 0, 0, 0};
    std::string out("\x89PNG\r\n\x1a\n", 8);
    append_png_chunk(out, "IHDR", ihdr);
    append_png_chunk(out, "IDAT", idat);
    append_png_chunk(out, "IEND", "");
    return out;
}

void write_atomically(const std::string& path, const std::string& bytes) {
    AtomicFile file(path);
    file.write(bytes.data(), bytes.size());
    file.commit();
}

}  // namespace

void check_image_extension(const std::string& path) {
    const std::string ext = lower_extension(path);
    SHPRT_CHECK(ext == ".png" || ext == ".exr" || ext == ".hdr", invalid_argument,
                "output {}: unknown image format (expected .png, .exr or .hdr)", path);
}

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

void save_exr_channels(const std::string& path, int width, int height,
                       const std::vector<ExrChannel>& channels, bool half) {
    SHPRT_CHECK(width > 0 && height > 0 && width <= kMaxImageSide && height <= kMaxImageSide &&
                    !channels.empty(),
                invalid_argument, "cannot write image {}: invalid size {}x{} or no channels", path,
                width, height);
    std::vector<std::pair<std::string, const float*>> list;
    for (const ExrChannel& c : channels) {
        SHPRT_CHECK(c.plane.size() == std::size_t(width) * std::size_t(height), invalid_argument,
                    "cannot write image {}: channel {} has {} values for {}x{}", path, c.name,
                    c.plane.size(), width, height);
        list.push_back({c.name, c.plane.data()});
    }
    write_atomically(path, encode_exr_channels(path, width, height, std::move(list), half));
}

void save_png(const std::string& path, const Rgb8Image& image) {
    SHPRT_CHECK(image.width > 0 && image.height > 0 && image.width <= kMaxImageSide &&
                    image.height <= kMaxImageSide &&
                    image.rgb.size() == std::size_t(image.width) * std::size_t(image.height) * 3,
                invalid_argument, "cannot write image {}: {} bytes for {}x{} RGB pixels", path,
                image.rgb.size(), image.width, image.height);
    write_atomically(path, encode_png(path, image));
}

void save_png16(const std::string& path, int width, int height, int channels,
                const std::vector<std::uint16_t>& samples) {
    SHPRT_CHECK(
        width > 0 && height > 0 && width <= kMaxImageSide && height <= kMaxImageSide &&
            channels >= 1 && channels <= 4 &&
            samples.size() == std::size_t(width) * std::size_t(height) * std::size_t(channels),
        invalid_argument, "cannot write image {}: {} samples for {}x{} pixels of {} channel(s)",
        path, samples.size(), width, height, channels);
    write_atomically(path, encode_png16(path, width, height, channels, samples));
}

}  // namespace shprt
