// Reading image files: .exr bit-exact, .hdr within RGBE precision, .png decoded with the exact
// sRGB curve, orientation, and bad files (missing, empty, truncated at every cut, garbage, NaN/Inf
// pixels, wrong extension) → shprt::Error naming the file, never a crash or a hang. The files are
// written by tinyexr and stb_image_write directly (image_fixture.hpp), not by save_image (render/,
// tested in tests/shade/test_save_image.cpp).
#include "shprt/light/image.hpp"
#include "shprt/light/light.hpp"

#include "light/image_fixture.hpp"
#include "shprt/core/colour.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"

#include <gtest/gtest.h>
#include <tinyexr.h>

#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

// RGBE keeps an 8-bit mantissa shared by the three channels; stb truncates, so each channel is
// off by less than one mantissa step of the largest channel, ≤ max/128.

class ImageFiles : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("shprt_test_image_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    fs::path m_dir;
};

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Expects load_image(path) to throw shprt::Error whose message names `path`.
void expect_error_naming(const std::string& path, ErrorCode code) {
    try {
        load_image(path);
        ADD_FAILURE() << "no error for " << path;
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), code) << e.what();
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

TEST_F(ImageFiles, ExrReadsFloatPixelsBitExactly) {
    Image image = test_support::random_image(37, 19, 1, -2.0f, 50.0f);
    image.rgb[0] = 1e-30f;  // denormal-adjacent and large values survive as float32
    image.rgb[1] = 6.0e4f;
    image.rgb[5] = 1.0e20f;
    test_support::write_test_image(path("a.EXR"), image);  // the extension in any case
    const Image back = load_image(path("a.EXR"));
    ASSERT_EQ(back.width, image.width);
    ASSERT_EQ(back.height, image.height);
    ASSERT_EQ(back.rgb.size(), image.rgb.size());
    EXPECT_EQ(std::memcmp(back.rgb.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
}

TEST_F(ImageFiles, HdrReadsWithinRgbePrecision) {
    for (int w : {5, 40}) {  // widths below 8 are written flat, 8..32767 run-length encoded
        Image image = test_support::random_image(w, 13, 2, 0.0f, 100.0f);
        for (std::size_t i = 0; i < image.rgb.size(); i += 7) image.rgb[i] *= 1e-3f;
        const std::string p = path(w < 8 ? "flat.hdr" : "rle.hdr");
        test_support::write_test_image(p, image);
        test_support::expect_rgbe_round_trip(image, load_image(p));
    }
}

TEST_F(ImageFiles, PngDecodesEveryCodeWithTheSrgbCurve) {
    // Every 8-bit code (as a linear value the fixture encodes back to exactly that code).
    Image image = Image::make(16, 16);
    for (std::size_t i = 0; i < image.rgb.size(); ++i)
        image.rgb[i] = srgb_to_linear(float((i * 7 + i / 3) & 0xff) / 255.0f);
    test_support::write_test_image(path("codes.png"), image);
    const Image back = load_image(path("codes.png"));
    ASSERT_EQ(back.width, 16);
    ASSERT_EQ(back.height, 16);
    EXPECT_EQ(back.rgb, image.rgb);
}

TEST_F(ImageFiles, RowZeroIsTheTop) {
    // A PNG written with one bright pixel at (x, y) = (3, 1) reads back there.
    Image image = Image::make(5, 4);
    image.pixel(3, 1)[1] = 1.0f;
    test_support::write_test_image(path("dot.png"), image);
    const Image back = load_image(path("dot.png"));
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x)
            EXPECT_EQ(back.pixel(x, y)[1] > 0.5f, x == 3 && y == 1) << x << "," << y;
}

TEST_F(ImageFiles, MissingEmptyAndGarbageFilesThrow) {
    expect_error_naming(path("missing.exr"), ErrorCode::io);
    expect_error_naming(path("missing.hdr"), ErrorCode::io);
    fs::create_directories(path("dir.hdr"));
    expect_error_naming(path("dir.hdr"), ErrorCode::io);
    for (const char* name : {"empty.exr", "empty.hdr", "empty.png"}) {
        write_bytes(path(name), "");
        expect_error_naming(path(name), ErrorCode::format);
    }
    for (const char* name : {"junk.exr", "junk.hdr", "junk.png"}) {
        write_bytes(path(name), std::string(300, 'x'));
        expect_error_naming(path(name), ErrorCode::format);
    }
    write_bytes(path("a.jpg"), "whatever");
    expect_error_naming(path("a.jpg"), ErrorCode::unsupported);
}

// Found by fuzz_light_load: a header whose lines hold a NUL byte, which ends a line for
// stb_image but not for the header check, so the two read different resolution lines (3x4
// against 1x3). A light then projected 3-pixel rows from a 1-pixel image (a heap overflow under
// ASan). It is refused in one line, as a light too.
TEST_F(ImageFiles, HdrWhoseHeaderStbReadsOtherwiseIsRefused) {
    const std::string header = std::string("#?RADIANCE\n# .h\nFORMAT=32-bit_rle_rgbe\nEX\xff\n") +
                               std::string(1, '\0') + "#?RADI\n-Y 3 +X 1\n\x02\x02" +
                               std::string(1, '\0') +
                               "ANCE\n#=y .h\nFORMAT=32-bit_rle_rgbe\nEXOS000000\n\n-Y 4 +X 3\n";
    write_bytes(path("nul.hdr"), header + std::string(48, '\x40'));
    expect_error_naming(path("nul.hdr"), ErrorCode::format);
    try {
        parse_light("equirect:" + path("nul.hdr"), 9);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("decodes as"), std::string::npos) << e.what();
    }
}

TEST_F(ImageFiles, TruncatedFilesThrowAtEveryCut) {
    const Image image = test_support::random_image(16, 4, 4, 0.0f, 10.0f);
    for (const char* name : {"t.exr", "t.hdr", "t.png"}) {
        test_support::write_test_image(path(name), image);
        const std::string bytes = read_file(path(name));
        ASSERT_GT(bytes.size(), 64u);
        // Every cut of the pixel data, and a sample of cuts in the header.
        int checked = 0;
        for (std::size_t cut = 1; cut < bytes.size(); cut += (cut < 64 ? 7 : 1)) {
            // A fresh name per cut: overwriting one file thousands of times is slow on some
            // file systems.
            const std::string p = path("cut" + std::to_string(cut) + "_" + name);
            write_bytes(p, bytes.substr(0, cut));
            try {
                load_image(p);
                ADD_FAILURE() << name << " cut at " << cut << " of " << bytes.size() << " loaded";
            } catch (const Error& e) {
                ASSERT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
            }
            fs::remove(p);
            ++checked;
        }
        EXPECT_GT(checked, 50);
    }
}

TEST_F(ImageFiles, HdrWithWrongLayoutOrZeroRunThrows) {
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
    write_bytes(path("flip.hdr"), header + "+Y 2 +X 2\n" + std::string(16, '\x40'));
    expect_error_naming(path("flip.hdr"), ErrorCode::format);
    write_bytes(path("nofmt.hdr"), "#?RADIANCE\n\n-Y 1 +X 1\n" + std::string(4, '\x40'));
    expect_error_naming(path("nofmt.hdr"), ErrorCode::format);
    // An RLE scanline whose dump count is 0 would make a naive decoder spin forever.
    std::string rle = header + "-Y 1 +X 8\n";
    rle += std::string("\x02\x02\x00\x08", 4);
    rle += std::string(1, '\0');
    write_bytes(path("zero.hdr"), rle + std::string(40, '\x01'));
    expect_error_naming(path("zero.hdr"), ErrorCode::format);
    write_bytes(path("zero_size.hdr"), header + "-Y 0 +X 4\n");
    expect_error_naming(path("zero_size.hdr"), ErrorCode::format);
}

TEST_F(ImageFiles, NonFinitePixelsInExrThrow) {
    // Written with tinyexr directly: one NaN or infinity at a known pixel.
    for (float bad :
         {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        std::vector<float> rgb(4 * 3 * 3, 1.0f);
        rgb[3 * 7 + 2] = bad;  // pixel (3, 1) of a 4×3 image, channel B
        const std::string p = path(std::isnan(bad) ? "nan.exr" : "inf.exr");
        const char* err = nullptr;
        ASSERT_EQ(SaveEXR(rgb.data(), 4, 3, 3, 0, p.c_str(), &err), TINYEXR_SUCCESS);
        try {
            load_image(p);
            ADD_FAILURE() << "non-finite pixel accepted";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(e.code(), ErrorCode::format);
            EXPECT_NE(what.find(p), std::string::npos) << what;
            EXPECT_NE(what.find("(3, 1)"), std::string::npos) << what;
        }
    }
}

// A PNG that claims `width` x `height` pixels in its header, with a corrupt IDAT and a correct
// IEND: only a reader that decodes pixels notices the IDAT. (stb_image does not check CRCs.)
// Grey (colour type 0): stb_image refuses an RGB header of more than 2^30 bytes itself, but a
// grey one of 20000 x 20000 it decodes, and to RGB floats that is 4.8 GB.
std::string png_claiming(std::uint32_t width, std::uint32_t height) {
    const auto be32 = [](std::uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    std::string png = "\x89PNG\r\n\x1a\n";
    png +=
        be32(13) + "IHDR" + be32(width) + be32(height) + std::string("\x08\0\0\0\0", 5) + be32(0);
    png += be32(4) + "IDAT" + "junk" + be32(0);
    png += std::string("\0\0\0\0IEND\xAE\x42\x60\x82", 12);
    return png;
}

// A header that claims a huge image is refused from the header, before any pixel is decoded: a
// 20000 x 20000 PNG of a few hundred bytes would otherwise take 5.7 GB.
TEST_F(ImageFiles, HugeImagesAreRefusedFromTheHeader) {
    const std::string png = path("huge.png");
    std::ofstream(png, std::ios::binary) << png_claiming(20000, 20000);
    const std::string hdr = path("huge.hdr");
    std::ofstream(hdr, std::ios::binary)
        << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 20000 +X 20000\n";
    for (const std::string& p : {png, hdr}) {
        try {
            load_image(p);
            ADD_FAILURE() << "huge image accepted: " << p;
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(e.code(), ErrorCode::format) << what;
            EXPECT_NE(what.find(p), std::string::npos) << what;
            EXPECT_NE(what.find("too large: 20000x20000"), std::string::npos) << what;
        }
    }
}

// An RGB PNG over the caps (20000 x 20000 x 3 bytes is over 2^30, where stb_image refuses it
// itself with "unknown image type") is refused with the size line too.
TEST_F(ImageFiles, AnRgbPngOverTheCapsGivesTheSizeLine) {
    std::string png = png_claiming(20000, 20000);
    png[8 + 8 + 9] = 2;  // colour type 2: RGB
    const std::string p = path("rgb.png");
    write_bytes(p, png);
    try {
        load_image(p);
        ADD_FAILURE() << "huge RGB PNG accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is too large: 20000x20000"), std::string::npos)
            << e.what();
    }
}

// stb_image checks no CRC: a PNG chunk whose CRC is wrong (here the pixel data's own) decodes
// there as if whole. The chunks' CRCs are checked first.
TEST_F(ImageFiles, APngChunkWithABadCrcIsRefused) {
    const Image image = test_support::random_image(6, 3, 2, 0.0f, 1.0f);
    test_support::write_test_image(path("good.png"), image);
    std::string bytes = read_file(path("good.png"));
    EXPECT_NO_THROW(load_image(path("good.png")));
    const std::size_t idat = bytes.find("IDAT");
    ASSERT_NE(idat, std::string::npos);
    const std::uint32_t length = (std::uint32_t(std::uint8_t(bytes[idat - 4])) << 24) |
                                 (std::uint32_t(std::uint8_t(bytes[idat - 3])) << 16) |
                                 (std::uint32_t(std::uint8_t(bytes[idat - 2])) << 8) |
                                 std::uint32_t(std::uint8_t(bytes[idat - 1]));
    bytes[idat + 4 + length] ^= 0x01;  // the first byte of IDAT's CRC
    write_bytes(path("crc.png"), bytes);
    try {
        load_image(path("crc.png"));
        ADD_FAILURE() << "a PNG with a bad CRC was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::format);
        EXPECT_NE(std::string(e.what()).find(path("crc.png") +
                                             " is corrupt: PNG chunk 'IDAT' at "
                                             "byte " +
                                             std::to_string(idat - 4) + " fails its CRC"),
                  std::string::npos)
            << e.what();
    }
}

// The caller's size check runs on the header's size, before decoding: the corrupt pixel data of
// this PNG is never reached.
TEST_F(ImageFiles, TheCallersSizeCheckRunsBeforeDecoding) {
    const std::string png = path("claims.png");
    std::ofstream(png, std::ios::binary) << png_claiming(30, 20);
    int seen_w = 0, seen_h = 0;
    try {
        load_image(png, [&](int w, int h) {
            seen_w = w;
            seen_h = h;
            fail(ErrorCode::format, "refused {}x{}", w, h);
        });
        ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "refused 30x20");
    }
    EXPECT_EQ(seen_w, 30);
    EXPECT_EQ(seen_h, 20);
    // Without the check, decoding finds the corrupt data.
    EXPECT_THROW(load_image(png), Error);
}

// EXR variants that save_image does not write, made with tinyexr directly: half floats, a single
// grey channel, and a tiled file whose edge tiles are partial.
TEST_F(ImageFiles, ExrVariantsLoad) {
    const int W = 20, H = 12;
    const Image image = test_support::random_image(W, H, 6, 0.0f, 4.0f);
    const char* err = nullptr;

    const std::string half = path("half.exr");
    ASSERT_EQ(SaveEXR(image.rgb.data(), W, H, 3, 1, half.c_str(), &err), TINYEXR_SUCCESS);
    const Image h = load_image(half);
    for (std::size_t i = 0; i < image.rgb.size(); ++i)  // half: 11-bit mantissa
        ASSERT_NEAR(h.rgb[i], image.rgb[i], image.rgb[i] * (1.0f / 1024.0f) + 1e-7f);

    std::vector<float> grey(std::size_t(W) * H);
    for (std::size_t p = 0; p < grey.size(); ++p) grey[p] = image.rgb[3 * p];
    const std::string single = path("grey.exr");
    ASSERT_EQ(SaveEXR(grey.data(), W, H, 1, 0, single.c_str(), &err), TINYEXR_SUCCESS);
    const Image g = load_image(single);
    for (std::size_t p = 0; p < grey.size(); ++p)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(g.rgb[3 * p + c], grey[p]);

    // Tiled, 8×8 tiles: 3×2 tiles, the last column 4 wide and the last row 4 high.
    const int T = 8, tiles_x = 3, tiles_y = 2;
    std::vector<std::vector<float>> planes(tiles_x * tiles_y * 3, std::vector<float>(T * T, 0.0f));
    std::vector<std::array<unsigned char*, 3>> tile_ptrs(tiles_x * tiles_y);
    std::vector<EXRTile> tiles(tiles_x * tiles_y);
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx) {
            const int t = ty * tiles_x + tx;
            EXRTile& tile = tiles[t];
            tile.offset_x = tx;
            tile.offset_y = ty;
            tile.level_x = tile.level_y = 0;
            tile.width = std::min(T, W - tx * T);
            tile.height = std::min(T, H - ty * T);
            for (int c = 0; c < 3; ++c) {  // file channel order B, G, R
                std::vector<float>& plane = planes[3 * t + c];
                for (int j = 0; j < tile.height; ++j)
                    for (int i = 0; i < tile.width; ++i)
                        plane[j * T + i] = image.pixel(tx * T + i, ty * T + j)[2 - c];
                tile_ptrs[t][c] = reinterpret_cast<unsigned char*>(plane.data());
            }
            tile.images = tile_ptrs[t].data();
        }
    EXRImage exr;
    InitEXRImage(&exr);
    exr.num_channels = 3;
    exr.width = W;
    exr.height = H;
    exr.tiles = tiles.data();
    exr.num_tiles = tiles_x * tiles_y;
    EXRHeader header;
    InitEXRHeader(&header);
    EXRChannelInfo channels[3] = {};
    int types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
    int requested[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
    channels[0].name[0] = 'B';
    channels[1].name[0] = 'G';
    channels[2].name[0] = 'R';
    header.num_channels = 3;
    header.channels = channels;
    header.pixel_types = types;
    header.requested_pixel_types = requested;
    header.tiled = 1;
    header.tile_size_x = header.tile_size_y = T;
    header.tile_level_mode = TINYEXR_TILE_ONE_LEVEL;
    header.tile_rounding_mode = TINYEXR_TILE_ROUND_DOWN;
    header.data_window.min_x = header.data_window.min_y = 0;  // tiled saving needs the windows
    header.data_window.max_x = W - 1;
    header.data_window.max_y = H - 1;
    header.display_window = header.data_window;
    const std::string tiled = path("tiled.exr");
    ASSERT_EQ(SaveEXRImageToFile(&exr, &header, tiled.c_str(), &err), TINYEXR_SUCCESS)
        << (err ? err : "");
    const Image t = load_image(tiled);
    ASSERT_EQ(t.width, W);
    ASSERT_EQ(t.height, H);
    EXPECT_EQ(t.rgb, image.rgb);
}

}  // namespace
}  // namespace shprt

namespace shprt {
namespace {

// Debian's libtinyexr asserts (aborting the program) on a header whose "type" does not match its
// layout or whose "tiles" is not 9 bytes, even when it then reports the header as corrupt. Found
// by fuzz_light_load (tests/data/light/exr_type_assert.exr is its input; in the fuzz corpus as
// light_load/exr-type-assert): these must be errors, not the end of the program.
std::string exr_with(const std::string& name, const std::string& type, const std::string& value,
                     std::uint8_t version_flags = 0) {
    std::string out("\x76\x2f\x31\x01", 4);
    out += std::string{char(2), char(version_flags), char(0), char(0)};
    out += name + '\0' + type + '\0';
    const auto len = static_cast<std::uint32_t>(value.size());
    out.append(reinterpret_cast<const char*>(&len), 4);  // little-endian machine
    out += value;
    out += '\0';  // end of the header
    return out;
}

TEST_F(ImageFiles, ExrHeadersThatTinyexrAssertsOnAreErrors) {
    expect_error_naming(std::string(SHPRT_TEST_DATA_DIR) + "/light/exr_type_assert.exr",
                        ErrorCode::format);
    write_bytes(path("tiled_type.exr"), exr_with("type", "string", "tiledimage"));
    expect_error_naming(path("tiled_type.exr"), ErrorCode::format);
    write_bytes(path("odd_type.exr"), exr_with("type", "string", "flat"));
    expect_error_naming(path("odd_type.exr"), ErrorCode::format);
    // A tiled file (version bit 9) whose "tiles" attribute is 4 bytes.
    write_bytes(path("tiles.exr"), exr_with("tiles", "tiledesc", "abcd", 0x02));
    expect_error_naming(path("tiles.exr"), ErrorCode::format);
    write_bytes(path("empty.exr"), exr_with("compression", "string", ""));
    expect_error_naming(path("empty.exr"), ErrorCode::format);
}

}  // namespace
}  // namespace shprt
