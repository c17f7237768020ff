// Reading image files: OpenEXR (tinyexr), Radiance RGBE (stb_image, after our own structural
// check of the scanlines, because stb_image 2.27 loops forever on some truncated RLE streams) and
// PNG (stb_image). Writing is shade/save_image.cpp. References: Greg Ward, "Real Pixels" (Graphics
// Gems II, 1991) and the Radiance file-format notes for RGBE and its run-length scanlines; IEC
// 61966-2-1 for sRGB.
#include "shprt/light/image.hpp"

#include "shprt/core/colour.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"

#include <stb_image.h>
#include <tinyexr.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

namespace shprt {
namespace {

std::string read_image_bytes(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    SHPRT_CHECK(std::filesystem::exists(status), io, "cannot open image {}: no such file", path);
    SHPRT_CHECK(std::filesystem::is_regular_file(status), io,
                "cannot open image {}: not a regular file", path);
    std::string bytes = read_file(path);
    SHPRT_CHECK(!bytes.empty(), format, "image {} is empty (0 bytes)", path);
    return bytes;
}

void check_dimensions(const std::string& path, int width, int height) {
    SHPRT_CHECK(width > 0 && height > 0 && width <= kMaxImageSide && height <= kMaxImageSide,
                format, "image {} has invalid size {}x{} (each side must be 1..{})", path, width,
                height, kMaxImageSide);
    SHPRT_CHECK(std::size_t(width) * std::size_t(height) <= kMaxImagePixels, format,
                "image {} is too large: {}x{} is more than {} pixels", path, width, height,
                kMaxImagePixels);
}

// The header's size, checked before decoding: ours, then the caller's.
void check_header_size(const std::string& path, int width, int height,
                       const ImageSizeCheck& check_size) {
    check_dimensions(path, width, height);
    if (check_size) check_size(width, height);
}

void check_finite_row(const std::string& path, int y, int width, const float* rgb) {
    for (std::size_t i = 0; i < 3 * std::size_t(width); ++i) {
        if (!std::isfinite(rgb[i]))
            fail(ErrorCode::format, "image {} has a {} value at pixel ({}, {}) channel {}", path,
                 std::isnan(rgb[i]) ? "NaN" : "infinite", i / 3, y, "RGB"[i % 3]);
    }
}

// ---- Radiance .hdr ---------------------------------------------------------------------------

// Reads one header line (without '\n') starting at `pos`; false at end of data.
bool next_line(const std::string& bytes, std::size_t& pos, std::string& line) {
    if (pos >= bytes.size()) return false;
    const std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) return false;  // a header line must be terminated
    line.assign(bytes, pos, end - pos);
    pos = end + 1;
    return true;
}

// Checks that the RGBE stream is complete and well formed in the layout stb_image decodes
// (-Y H +X W; flat or "new" RLE scanlines), so that stb_image never reads past the end.
// Returns the header's resolution (width, height).
std::pair<int, int> validate_rgbe(const std::string& path, const std::string& bytes,
                                  const ImageSizeCheck& check_size) {
    std::size_t pos = 0;
    std::string line;
    SHPRT_CHECK(next_line(bytes, pos, line) && (line == "#?RADIANCE" || line == "#?RGBE"), format,
                "image {} is not a Radiance .hdr file (no #?RADIANCE signature)", path);
    bool rgbe = false;
    for (;;) {
        SHPRT_CHECK(next_line(bytes, pos, line), format,
                    "image {} is truncated: the header never ends", path);
        if (line.empty()) break;
        if (line == "FORMAT=32-bit_rle_rgbe") rgbe = true;
    }
    SHPRT_CHECK(rgbe, format, "image {}: only FORMAT=32-bit_rle_rgbe .hdr files are supported",
                path);
    SHPRT_CHECK(next_line(bytes, pos, line), format, "image {} is truncated: no resolution line",
                path);
    int width = 0, height = 0;
    char extra = 0;
    SHPRT_CHECK(std::sscanf(line.c_str(), "-Y %d +X %d%c", &height, &width, &extra) == 2, format,
                "image {}: unsupported resolution line '{}' (expected '-Y H +X W')", path, line);
    check_header_size(path, width, height, check_size);

    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::size_t n = bytes.size();
    const std::size_t flat_bytes = std::size_t(4) * std::size_t(width) * std::size_t(height);
    const bool rle_possible = width >= 8 && width < 32768;
    if (!rle_possible || n - pos < 4 || b[pos] != 2 || b[pos + 1] != 2 || (b[pos + 2] & 0x80)) {
        SHPRT_CHECK(n - pos >= flat_bytes, format,
                    "image {} is truncated: {} bytes of pixel data, {}x{} needs {}", path, n - pos,
                    width, height, flat_bytes);
        return {width, height};
    }
    for (int y = 0; y < height; ++y) {
        SHPRT_CHECK(n - pos >= 4, format, "image {} is truncated at scanline {} of {}", path, y,
                    height);
        SHPRT_CHECK(b[pos] == 2 && b[pos + 1] == 2 && !(b[pos + 2] & 0x80), format,
                    "image {}: scanline {} is not run-length encoded like the first", path, y);
        const int len = (b[pos + 2] << 8) | b[pos + 3];
        SHPRT_CHECK(len == width, format, "image {}: scanline {} has length {}, expected {}", path,
                    y, len, width);
        pos += 4;
        for (int k = 0; k < 4; ++k) {
            for (int x = 0; x < width;) {
                SHPRT_CHECK(pos < n, format, "image {} is truncated at scanline {} of {}", path, y,
                            height);
                const int count = b[pos++];
                if (count > 128) {
                    SHPRT_CHECK(pos < n, format, "image {} is truncated at scanline {} of {}", path,
                                y, height);
                    ++pos;
                    x += count - 128;
                } else {
                    SHPRT_CHECK(count > 0, format, "image {}: zero-length run in scanline {}", path,
                                y);
                    SHPRT_CHECK(n - pos >= std::size_t(count), format,
                                "image {} is truncated at scanline {} of {}", path, y, height);
                    pos += std::size_t(count);
                    x += count;
                }
                SHPRT_CHECK(x <= width, format, "image {}: run overflows scanline {}", path, y);
            }
        }
    }
    return {width, height};
}

struct StbFree {
    void operator()(void* p) const { stbi_image_free(p); }
};

Image load_hdr(const std::string& path, const std::string& bytes,
               const ImageSizeCheck& check_size) {
    const auto [width, height] = validate_rgbe(path, bytes, check_size);
    int w = 0, h = 0, comp = 0;
    std::unique_ptr<float, StbFree> data(
        stbi_loadf_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                               static_cast<int>(bytes.size()), &w, &h, &comp, 3));
    SHPRT_CHECK(data != nullptr, format, "cannot decode image {}: {}", path,
                stbi_failure_reason() ? stbi_failure_reason() : "unknown stb_image error");
    // stb_image reads the header by its own rules (a NUL byte ends a line for it, not for the
    // check above): the size the caller was told must be the size decoded.
    SHPRT_CHECK(w == width && h == height, format,
                "image {}: its header's resolution is {}x{}, but it decodes as {}x{} (a malformed "
                "header)",
                path, width, height, w, h);
    check_dimensions(path, w, h);
    Image image = Image::make(w, h);
    std::memcpy(image.rgb.data(), data.get(), image.rgb.size() * sizeof(float));
    return image;
}

// ---- PNG -------------------------------------------------------------------------------------

// CRC-32 of PNG chunks (ISO 3309, polynomial 0xedb88320; the PNG specification's Annex D).
std::uint32_t png_crc32(const unsigned char* p, std::size_t n) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

// A chunk type from the file, non-printable bytes as '?'.
std::string printable_chunk_type(std::string t) {
    for (char& c : t)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    return t;
}

std::uint32_t get_be32(const unsigned char* p) {
    return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
           std::uint32_t(p[3]);
}

// The PNG's size from its IHDR chunk (checked first, as every format's header size is), then its
// chunk structure, before stb_image (which checks no CRC, and stops reading after the last IDAT
// chunk): chunks of length, type, data and a CRC over type and data, each CRC right, up to IEND.
// stb_image's own size refusal ("unknown image type" for an RGB image over 2^30 bytes) is never
// reached: the size line is ours.
void check_png(const std::string& path, const std::string& bytes,
               const ImageSizeCheck& check_size) {
    static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::size_t n = bytes.size();
    SHPRT_CHECK(n >= 8 && std::memcmp(b, kSignature, 8) == 0, format,
                "cannot decode image {}: not a PNG file (no PNG signature)", path);
    SHPRT_CHECK(n >= 8 + 8 + 13 + 4, format, "image {} is truncated: no PNG header chunk (IHDR)",
                path);
    SHPRT_CHECK(get_be32(b + 8) == 13 && std::memcmp(b + 12, "IHDR", 4) == 0, format,
                "cannot decode image {}: the first PNG chunk is '{}', not IHDR", path,
                printable_chunk_type(std::string(reinterpret_cast<const char*>(b + 12), 4)));
    const auto side = [](std::uint32_t v) {
        return static_cast<int>(std::min<std::uint32_t>(v, 0x7fffffffu));
    };
    check_header_size(path, side(get_be32(b + 16)), side(get_be32(b + 20)), check_size);
    std::size_t pos = 8;
    for (int chunk = 0;; ++chunk) {
        SHPRT_CHECK(n - pos >= 12, format, "image {} is truncated: no PNG end chunk (IEND)", path);
        const std::uint32_t length = get_be32(b + pos);
        SHPRT_CHECK(length <= 0x7fffffffu && length <= n - pos - 12, format,
                    "image {} is truncated: PNG chunk {} at byte {} claims {} bytes", path, chunk,
                    pos, length);
        const std::string type(reinterpret_cast<const char*>(b + pos + 4), 4);
        SHPRT_CHECK(
            png_crc32(b + pos + 4, 4 + std::size_t(length)) == get_be32(b + pos + 8 + length),
            format, "image {} is corrupt: PNG chunk '{}' at byte {} fails its CRC", path,
            printable_chunk_type(type), pos);
        pos += 12 + std::size_t(length);
        if (type == "IEND") return;
    }
}

Image load_png(const std::string& path, const std::string& bytes,
               const ImageSizeCheck& check_size) {
    SHPRT_CHECK(bytes.size() <= std::size_t(std::numeric_limits<int>::max()), format,
                "image {} is too large", path);
    check_png(path, bytes, check_size);
    const auto* mem = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int len = static_cast<int>(bytes.size());
    int w = 0, h = 0, comp = 0;
    SHPRT_CHECK(stbi_info_from_memory(mem, len, &w, &h, &comp), format,
                "cannot decode image {}: {}", path,
                stbi_failure_reason() ? stbi_failure_reason() : "not a PNG file");
    // 16-bit PNGs are reduced to 8 bits by stb_image; environment maps worth more precision
    // come as .exr or .hdr.
    std::unique_ptr<stbi_uc, StbFree> data(stbi_load_from_memory(mem, len, &w, &h, &comp, 3));
    SHPRT_CHECK(data != nullptr, format, "cannot decode image {}: {}", path,
                stbi_failure_reason() ? stbi_failure_reason() : "corrupt PNG");
    check_dimensions(path, w, h);
    std::array<float, 256> lut;
    for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(float(i) / 255.0f);
    Image image = Image::make(w, h);
    for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = lut[data.get()[i]];
    return image;
}

// ---- OpenEXR ---------------------------------------------------------------------------------

// tinyexr's one-call LoadEXRFromMemory leaks its header and image on every error path, so the
// steps are done here with the lower-level calls and freed on every path. (Ownership rules of
// tinyexr 1.0.1: ParseEXRHeaderFromMemory allocates even when it fails, so the header is always
// freed; LoadEXRImageFromMemory frees its own allocations when it fails, so the image is freed
// only after success.)
struct ExrHeaderGuard {
    EXRHeader header;
    ExrHeaderGuard() { InitEXRHeader(&header); }
    ~ExrHeaderGuard() { FreeEXRHeader(&header); }
};
struct ExrImageGuard {
    EXRImage image;
    bool loaded = false;
    ExrImageGuard() { InitEXRImage(&image); }
    ~ExrImageGuard() {
        if (loaded) FreeEXRImage(&image);
    }
};

[[noreturn]] void fail_exr(const std::string& path, const char* err, int code) {
    std::string message = err ? err : "unknown tinyexr error";
    while (!message.empty() && (message.back() == '\n' || message.back() == '.'))
        message.pop_back();
    // tinyexr lists each missing header attribute on a line of its own.
    for (std::size_t at; (at = message.find(".\n")) != std::string::npos;)
        message.replace(at, 2, "; ");
    std::replace(message.begin(), message.end(), '\n', ' ');
    if (err) FreeEXRErrorMessage(err);
    fail(ErrorCode::format,
         "cannot decode image {}: {} (tinyexr code {}; truncated or corrupt file)", path, message,
         code);
}

// At most 40 characters of a string from a file, non-printable bytes as '?'.
std::string printable_exr_type(const std::string& t) {
    std::string out = t.substr(0, 40);
    for (char& c : out)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    return out;
}

// Debian's libtinyexr is built with assertions, and ParseEXRHeaderFromMemory asserts (aborting the
// program) on header attributes it does not expect: a "type" other than scanlineimage without
// tiles or tiledimage with them, a "tiles" attribute that is not 9 bytes (fuzz_light_load found
// the first). So the attributes those asserts and unchecked reads look at are checked here first,
// by the same walk tinyexr makes (name\0 type\0 size value, until an empty name). Where the walk
// breaks tinyexr reports an error, but only after it has converted (and asserted on) the
// attributes read so far, so those are checked too.
// Where the walk found the header's end (just past its terminating empty name; 0 if it broke
// off) and the dataWindow attribute's 16 bytes (0 if absent): what read_image_rows needs to cut a
// scanline file into files of a few rows.
struct ExrLayout {
    std::size_t header_end = 0, data_window_at = 0;
};

ExrLayout check_exr_attributes(const std::string& path, const unsigned char* mem, std::size_t size,
                               const EXRVersion& version) {
    ExrLayout layout;
    std::size_t pos = 8;  // magic and version
    bool tiled = false;
    std::vector<std::string> types;
    while (pos < size && mem[pos] != 0) {
        const char* p = reinterpret_cast<const char*>(mem + pos);
        const std::size_t left = size - pos;
        const std::size_t name_len = strnlen(p, left);
        if (name_len == left) break;
        const std::size_t type_len = strnlen(p + name_len + 1, left - name_len - 1);
        const std::size_t head = name_len + 1 + type_len + 1;
        if (type_len == left - name_len - 1 || left - head < 4) break;
        std::uint32_t len = 0;
        std::memcpy(&len, p + head, 4);  // little-endian, as this machine
        if (len > left - head - 4) break;
        const std::string name(p, name_len);
        const unsigned char* data = mem + pos + head + 4;
        static const char* const kRead[] = {"channels",           "compression",
                                            "dataWindow",         "displayWindow",
                                            "lineOrder",          "pixelAspectRatio",
                                            "screenWindowCenter", "screenWindowWidth",
                                            "chunkCount",         "tiles"};
        for (const char* r : kRead)
            SHPRT_CHECK(len > 0 || name != r, format,
                        "cannot decode image {}: OpenEXR attribute '{}' is empty (corrupt file)",
                        path, name);
        if (name == "tiles" && (version.tiled || version.multipart || version.non_image)) {
            SHPRT_CHECK(len == 9, format,
                        "cannot decode image {}: OpenEXR attribute 'tiles' has {} bytes, not 9 "
                        "(corrupt file)",
                        path, len);
            tiled = true;
        }
        if (name == "type" && len > 0 && data[0] != 0)
            types.emplace_back(reinterpret_cast<const char*>(data),
                               strnlen(reinterpret_cast<const char*>(data), len));
        if (name == "dataWindow" && len == 16) layout.data_window_at = pos + head + 4;
        pos += head + 4 + len;
    }
    if (pos < size && mem[pos] == 0) layout.header_end = pos + 1;
    for (const std::string& t : types)
        SHPRT_CHECK((t == "scanlineimage" && !tiled) || (t == "tiledimage" && tiled), format,
                    "cannot decode image {}: OpenEXR part type '{}' does not match its {} layout "
                    "(deep or corrupt file)",
                    path, printable_exr_type(t), tiled ? "tiled" : "scanline");
    return layout;
}

// A parsed OpenEXR header, its size checked (ours, then the caller's) and its channels chosen.
struct ExrFile {
    ExrHeaderGuard h;
    ExrLayout layout;
    int index[3] = {-1, -1, -1};  // the channels read as R, G, B
};

// Which channels are R, G and B: by name, or one channel of any name read as grey.
void choose_exr_channels(const std::string& path, ExrFile& f) {
    const EXRHeader& header = f.h.header;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < header.num_channels; ++c)
        for (int k = 0; k < 3; ++k)
            if (std::strcmp(header.channels[c].name, names[k]) == 0) f.index[k] = c;
    if (header.num_channels == 1) f.index[0] = f.index[1] = f.index[2] = 0;
    SHPRT_CHECK(f.index[0] >= 0 && f.index[1] >= 0 && f.index[2] >= 0, format,
                "image {}: needs R, G and B channels (or a single channel)", path);
    for (int k = 0; k < 3; ++k)
        SHPRT_CHECK(header.requested_pixel_types[f.index[k]] != TINYEXR_PIXELTYPE_UINT, unsupported,
                    "image {}: integer channels are not supported", path);
}

// Parses `mem` (a whole file, or one cut from it by read_exr_rows) into `header`, every channel
// requested as float.
void parse_exr_header(const std::string& path, const unsigned char* mem, std::size_t size,
                      const EXRVersion& version, EXRHeader& header) {
    const char* err = nullptr;
    const int ret = ParseEXRHeaderFromMemory(&header, &version, mem, size, &err);
    if (ret != TINYEXR_SUCCESS) fail_exr(path, err, ret);
    for (int c = 0; c < header.num_channels; ++c)
        if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF)
            header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
}

void open_exr(const std::string& path, const std::string& bytes, const ImageSizeCheck& check_size,
              EXRVersion& version, ExrFile& f) {
    const auto* mem = reinterpret_cast<const unsigned char*>(bytes.data());
    const int ret = ParseEXRVersionFromMemory(&version, mem, bytes.size());
    SHPRT_CHECK(ret == TINYEXR_SUCCESS, format, "image {} is not an OpenEXR file (tinyexr code {})",
                path, ret);
    SHPRT_CHECK(!version.multipart && !version.non_image, unsupported,
                "image {}: multi-part and deep OpenEXR files are not supported", path);
    f.layout = check_exr_attributes(path, mem, bytes.size(), version);
    parse_exr_header(path, mem, bytes.size(), version, f.h.header);
    // The data window decides what LoadEXRImageFromMemory allocates.
    const EXRBox2i& window = f.h.header.data_window;
    const long long header_w = (long long)window.max_x - window.min_x + 1;
    const long long header_h = (long long)window.max_y - window.min_y + 1;
    const auto side = [](long long s) {
        return static_cast<int>(std::clamp<long long>(s, 0, std::numeric_limits<int>::max()));
    };
    check_header_size(path, side(header_w), side(header_h), check_size);
    choose_exr_channels(path, f);
}

// Decodes `mem` with `header` into `im` (which frees it).
void decode_exr(const std::string& path, const unsigned char* mem, std::size_t size,
                const EXRHeader& header, ExrImageGuard& im) {
    // tinyexr frees the image itself when decoding fails, but only the channel planes counted
    // in num_channels, which it sets on success: preset it so the planes are freed too.
    im.image.num_channels = header.num_channels;
    const char* err = nullptr;
    const int ret = LoadEXRImageFromMemory(&im.image, &header, mem, size, &err);
    if (ret != TINYEXR_SUCCESS) fail_exr(path, err, ret);
    im.loaded = true;
}

// The whole of an opened file, decoded.
Image decode_exr_image(const std::string& path, const std::string& bytes, const ExrFile& f) {
    const EXRHeader& header = f.h.header;
    ExrImageGuard im;
    decode_exr(path, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), header,
               im);
    check_dimensions(path, im.image.width, im.image.height);

    const int W = im.image.width, H = im.image.height;
    Image image = Image::make(W, H);
    const auto put = [&](unsigned char** planes, int src, int x, int y) {
        float* dst = image.pixel(x, y);
        for (int k = 0; k < 3; ++k) dst[k] = reinterpret_cast<float**>(planes)[f.index[k]][src];
    };
    if (header.tiled) {
        const int tx = header.tile_size_x, ty = header.tile_size_y;
        for (int t = 0; t < im.image.num_tiles; ++t) {
            const EXRTile& tile = im.image.tiles[t];
            for (int j = 0; j < tile.height; ++j)
                for (int i = 0; i < tile.width; ++i) {
                    const int x = tile.offset_x * tx + i, y = tile.offset_y * ty + j;
                    if (x < W && y < H) put(tile.images, j * tx + i, x, y);
                }
        }
    } else {
        SHPRT_CHECK(im.image.images != nullptr, format, "image {}: no pixel data", path);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) put(im.image.images, y * W + x, x, y);
    }
    return image;
}

Image load_exr(const std::string& path, const std::string& bytes,
               const ImageSizeCheck& check_size) {
    EXRVersion version;
    ExrFile f;
    open_exr(path, bytes, check_size, version, f);
    return decode_exr_image(path, bytes, f);
}

// Rows per chunk of a scanline file by compression (tinyexr's DecodeChunk; OpenEXR's table); 0
// for a compression read_exr_rows leaves whole.
int exr_lines_per_chunk(int compression) {
    switch (compression) {
        case TINYEXR_COMPRESSIONTYPE_NONE:
        case TINYEXR_COMPRESSIONTYPE_RLE:
        case TINYEXR_COMPRESSIONTYPE_ZIPS:
            return 1;
        case TINYEXR_COMPRESSIONTYPE_ZIP:
            return 16;
        case TINYEXR_COMPRESSIONTYPE_PIZ:
            return 32;
        default:
            return 0;
    }
}

// About this many rows are decoded at a time: 64 rows of a 16384-wide map are 12 MiB of floats.
constexpr int kExrRowsPerBlock = 64;

std::int32_t get_i32(const unsigned char* p) {
    std::int32_t v;
    std::memcpy(&v, p, 4);  // little-endian, as this machine (and check_exr_attributes)
    return v;
}

// An OpenEXR file a block of rows at a time. tinyexr 1.0.1 decodes only whole files, so each
// block is cut out as a file of its own: the header with its dataWindow narrowed to the block's
// rows, an offset table for the block's chunks, and the chunks, copied byte for byte; tinyexr
// decodes and checks that file as it would the whole one. Only what can be cut exactly is cut —
// a scanline file in increasing line order whose compression has a known chunk height, whose
// offset table is complete and whose chunks lie in the file, each at the rows it claims; anything
// else (tiled files, a broken table tinyexr would rebuild) is decoded whole.
void read_exr_rows(const std::string& path, const std::string& bytes,
                   const ImageSizeCheck& check_size, const ImageRowSink& row) {
    EXRVersion version;
    ExrFile f;
    open_exr(path, bytes, check_size, version, f);
    const EXRHeader& header = f.h.header;
    const EXRBox2i window = header.data_window;
    const int W = window.max_x - window.min_x + 1, H = window.max_y - window.min_y + 1;
    const auto* mem = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::size_t size = bytes.size(), header_end = f.layout.header_end;
    const int lines = exr_lines_per_chunk(header.compression_type);
    bool cut = !header.tiled && header.line_order == 0 && lines > 0 && header_end > 0 &&
               f.layout.data_window_at > 0;
    const std::size_t chunks = cut ? (std::size_t(H) + lines - 1) / std::size_t(lines) : 0;
    std::vector<std::uint64_t> offset(chunks), length(chunks);
    const std::size_t table_end = header_end + 8 * chunks;
    cut = cut && table_end <= size;
    for (std::size_t c = 0; cut && c < chunks; ++c) {
        std::memcpy(&offset[c], mem + header_end + 8 * c, 8);
        cut = offset[c] >= table_end && offset[c] <= size - 8 &&
              get_i32(mem + offset[c]) == window.min_y + std::int64_t(c) * lines;
        const std::int64_t data = cut ? get_i32(mem + offset[c] + 4) : 0;
        cut = cut && data > 0 && std::uint64_t(data) <= size - offset[c] - 8;
        length[c] = 8 + std::uint64_t(data);
    }
    if (!cut) {
        const Image image = decode_exr_image(path, bytes, f);
        for (int y = 0; y < image.height; ++y) row(y, image.pixel(0, y));
        return;
    }
    const std::size_t per_block = std::max(1, kExrRowsPerBlock / lines);
    std::string block;
    std::vector<float> rgb(3 * std::size_t(W));
    for (std::size_t c0 = 0; c0 < chunks; c0 += per_block) {
        const std::size_t c1 = std::min(chunks, c0 + per_block);
        const int y0 = int(c0) * lines, y1 = std::min(H, int(c1) * lines);
        block.assign(bytes, 0, header_end);
        const std::int32_t window_y[2] = {window.min_y + y0, window.min_y + y1 - 1};
        std::memcpy(block.data() + f.layout.data_window_at + 4, &window_y[0], 4);
        std::memcpy(block.data() + f.layout.data_window_at + 12, &window_y[1], 4);
        block.resize(header_end + 8 * (c1 - c0));
        for (std::size_t c = c0; c < c1; ++c) {
            const std::uint64_t at = block.size();
            std::memcpy(block.data() + header_end + 8 * (c - c0), &at, 8);
            block.append(bytes, offset[c], length[c]);
        }
        const auto* bmem = reinterpret_cast<const unsigned char*>(block.data());
        ExrHeaderGuard bh;
        parse_exr_header(path, bmem, block.size(), version, bh.header);
        ExrImageGuard im;
        decode_exr(path, bmem, block.size(), bh.header, im);
        SHPRT_CHECK(im.image.images != nullptr && im.image.width == W &&
                        im.image.height == y1 - y0 && bh.header.num_channels == header.num_channels,
                    format, "cannot decode image {}: rows {} to {} decode as {}x{}", path, y0,
                    y1 - 1, im.image.width, im.image.height);
        const auto* const* planes = reinterpret_cast<const float* const*>(im.image.images);
        for (int y = y0; y < y1; ++y) {
            const std::size_t first = std::size_t(y - y0) * std::size_t(W);
            for (int x = 0; x < W; ++x)
                for (int k = 0; k < 3; ++k)
                    rgb[3 * std::size_t(x) + k] = planes[f.index[k]][first + x];
            row(y, rgb.data());
        }
    }
}

}  // namespace

Image Image::make(int width, int height) {
    SHPRT_CHECK(width > 0 && height > 0 && width <= kMaxImageSide && height <= kMaxImageSide,
                invalid_argument, "image size {}x{} is invalid (each side must be 1..{})", width,
                height, kMaxImageSide);
    Image image;
    image.width = width;
    image.height = height;
    image.rgb.assign(std::size_t(3) * std::size_t(width) * std::size_t(height), 0.0f);
    return image;
}

void check_image_finite(const std::string& name, const Image& image) {
    for (int y = 0; y < image.height; ++y)
        check_finite_row(name, y, image.width, image.pixel(0, y));
}

void read_image_rows(const std::string& path, const ImageSizeCheck& check_size,
                     const ImageRowSink& row) {
    const std::string ext = lower_extension(path);
    SHPRT_CHECK(ext == ".exr" || ext == ".hdr" || ext == ".png", unsupported,
                "cannot read image {}: unknown extension '{}' (expected .exr, .hdr or .png)", path,
                ext);
    const std::string bytes = read_image_bytes(path);
    if (ext == ".exr") {
        int width = 0;
        read_exr_rows(
            path, bytes,
            [&](int w, int h) {
                width = w;
                if (check_size) check_size(w, h);
            },
            [&](int y, const float* rgb) {
                check_finite_row(path, y, width, rgb);
                row(y, rgb);
            });
        return;
    }
    const Image image =
        ext == ".hdr" ? load_hdr(path, bytes, check_size) : load_png(path, bytes, check_size);
    check_image_finite(path, image);
    for (int y = 0; y < image.height; ++y) row(y, image.pixel(0, y));
}

Image load_image(const std::string& path, const ImageSizeCheck& check_size) {
    const std::string ext = lower_extension(path);
    SHPRT_CHECK(ext == ".exr" || ext == ".hdr" || ext == ".png", unsupported,
                "cannot read image {}: unknown extension '{}' (expected .exr, .hdr or .png)", path,
                ext);
    const std::string bytes = read_image_bytes(path);
    Image image = ext == ".exr"   ? load_exr(path, bytes, check_size)
                  : ext == ".hdr" ? load_hdr(path, bytes, check_size)
                                  : load_png(path, bytes, check_size);
    check_image_finite(path, image);
    return image;
}

}  // namespace shprt
