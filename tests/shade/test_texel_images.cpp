// The texel coefficients as standard images (shade/texel_shade.hpp,
// write_texel_coefficient_images): read back with stb_image (16-bit PNG) and tinyexr (RGBA EXR),
// decoded with the sidecar's offsets and scales, every pixel equals the dilated coefficient
// plane — PNG within the quantisation bound scale/131070, EXR exactly; the file names, the
// padding past K, and a failed export leaving no file.
#include "shade_test_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/shade/texel_shade.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>
#include <tinyexr.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

// A texel transfer on a 13 × 9 atlas with scattered texels (gutters between them), K = 9 (the
// last image holds one coefficient), three channels; coefficient i of channel c spans a range
// from 1e-3 to 10 around an offset, one coefficient is constant (scale 0).
TransferSet synthetic_texels(TransferEncoding encoding) {
    TransferSet t;
    t.kind = TransferKind::shadowed;
    t.layout = {ReceiverDomain::texel, 3, 9, TransferShape::vector, encoding};
    t.samples = 64;
    t.texels.width = 13;
    t.texels.height = 9;
    for (std::uint32_t p = 0; p < 13 * 9; ++p)
        if (p % 5 == 1 || p % 7 == 3) t.texels.texel.push_back(p);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    t.coeffs.resize(t.layout.floats(t.texels.texel.size()));
    for (std::size_t r = 0; r < t.texels.texel.size(); ++r)
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 9; ++i) {
                const float range = i == 5 ? 0.0f : std::pow(10.0f, float(i % 5) - 3.0f);
                t.receiver(r, c)[i] = 0.3f * float(i - 4) + float(c) + range * u(rng);
            }
    return t;
}

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(read_file(path)); }

// The coefficient the image's pixel p, channel j, must decode to: the dilated plane's value.
float expected(const TransferSet& t, const std::vector<std::int64_t>& source, std::size_t p, int c,
               int i) {
    if (source[p] >= 0) return t.receiver(std::size_t(source[p]), c)[i];
    float lo = std::numeric_limits<float>::max(), hi = -lo;
    for (std::size_t r = 0; r < t.receiver_count(); ++r)
        lo = std::min(lo, t.receiver(r, c)[i]), hi = std::max(hi, t.receiver(r, c)[i]);
    return std::clamp(0.0f, lo, hi);
}

// Reads every image of the sidecar and checks each decoded pixel against the plane; `decode`
// returns the pixel's 4 normalized values (PNG: q/65535; EXR: the floats).
template <typename Read>
void check_images(const TransferSet& t, const std::string& sidecar, bool png, Read read) {
    const nlohmann::json j = read_json(sidecar);
    EXPECT_EQ(j["format"], "shprt-texel-images");
    EXPECT_EQ(j["K"], 9);
    EXPECT_EQ(j["channels"], 3);
    EXPECT_EQ(j["width"], 13);
    EXPECT_EQ(j["height"], 9);
    EXPECT_EQ(j["sh"]["index"], "i = l*(l+1) + m");
    ASSERT_EQ(j["images"].size(), 9u);  // ceil(9/4) per channel
    const std::vector<std::int64_t> source = dilate_texels(t.texels, kTexelGutter);
    double worst_ratio = 0;  // largest error / bound over the PNG pixels
    for (const auto& image : j["images"]) {
        const int c = int(std::string("RGB").find(image["channel"].get<std::string>()[0]));
        const int first = image["first"], count = image["count"];
        EXPECT_EQ(count, std::min(4, 9 - first));
        const std::string file = (fs::path(sidecar).parent_path() / image["file"]).string();
        const std::vector<float> v = read(file);  // 13·9·4 normalized values
        ASSERT_EQ(v.size(), 13u * 9u * 4u) << file;
        for (int k = 0; k < 4; ++k) {
            const float offset = image["offset"][k], scale = image["scale"][k];
            if (!png) EXPECT_TRUE(offset == 0 && scale == 1) << file;
            for (std::size_t p = 0; p < 13 * 9; ++p) {
                const double got = offset + double(scale) * v[4 * p + k];
                if (k >= count) {
                    EXPECT_EQ(got, 0.0) << file << " pads past K with 0";
                    continue;
                }
                const double want = expected(t, source, p, c, first + k);
                if (!png) {
                    EXPECT_EQ(got, want) << file << " pixel " << p;  // EXR float32: exact
                    continue;
                }
                // The quantisation bound, and float rounding of offset and scale.
                const double bound = scale / 131070.0 + 1e-6 * (std::abs(offset) + scale);
                EXPECT_LE(std::abs(got - want), bound) << file << " pixel " << p << " k " << k;
                if (scale > 0) worst_ratio = std::max(worst_ratio, std::abs(got - want) / bound);
            }
        }
    }
    if (png) {
        EXPECT_GT(worst_ratio, 0.3) << "the bound is tight: errors reach a third of it";
        std::printf("largest PNG error: %.3f of the bound\n", worst_ratio);
    }
}

TEST(TexelImages, Png16DecodesWithinTheQuantisationBound) {
    test::TempDir dir;
    const TransferSet t = synthetic_texels(TransferEncoding::f16);
    const std::vector<std::string> files =
        write_texel_coefficient_images(dir.file("planes.png"), t);
    ASSERT_EQ(files.size(), 10u);
    EXPECT_EQ(files[0], dir.file("planes.json"));
    EXPECT_EQ(files[1], dir.file("planes_R000.png"));
    EXPECT_EQ(files[9], dir.file("planes_B002.png"));
    EXPECT_EQ(files, texel_coefficient_image_paths(dir.file("planes.png"), t.layout));
    for (const std::string& f : files) EXPECT_TRUE(fs::exists(f)) << f;
    check_images(t, files[0], true, [](const std::string& file) {
        const std::string bytes = read_file(file);
        int w = 0, h = 0, n = 0;
        EXPECT_TRUE(stbi_is_16_bit_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                               int(bytes.size())));
        stbi_us* q = stbi_load_16_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                              int(bytes.size()), &w, &h, &n, 4);
        EXPECT_TRUE(q && w == 13 && h == 9 && n == 4) << file;
        std::vector<float> v;
        if (q) {
            for (int i = 0; i < w * h * 4; ++i) v.push_back(float(q[i]) / 65535.0f);
            stbi_image_free(q);
        }
        return v;
    });
}

TEST(TexelImages, RgbaExrHoldsTheCoefficientsExactly) {
    test::TempDir dir;
    const TransferSet t = synthetic_texels(TransferEncoding::f32);
    const std::vector<std::string> files =
        write_texel_coefficient_images(dir.file("planes.exr"), t);
    EXPECT_EQ(files[4], dir.file("planes_G000.exr"));
    check_images(t, files[0], false, [](const std::string& file) {
        float* rgba = nullptr;
        int w = 0, h = 0;
        const char* err = nullptr;
        EXPECT_EQ(LoadEXR(&rgba, &w, &h, file.c_str(), &err), TINYEXR_SUCCESS) << file;
        std::vector<float> v(rgba, rgba + (rgba ? 4 * w * h : 0));
        std::free(rgba);
        return v;
    });
}

TEST(TexelImages, BadInputLeavesNoFile) {
    test::TempDir dir;
    TransferSet t = synthetic_texels(TransferEncoding::f32);
    EXPECT_THROW(write_texel_coefficient_images(dir.file("planes.tga"), t), Error);
    t.coeffs.back() = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(write_texel_coefficient_images(dir.file("planes.png"), t), Error);
    t.coeffs.back() = 0;
    EXPECT_TRUE(fs::is_empty(dir.path()));
    // A write that fails part-way (the last image's name is taken by a directory) removes the
    // images it wrote.
    fs::create_directory(dir.file("planes_B002.png"));
    EXPECT_THROW(write_texel_coefficient_images(dir.file("planes.png"), t), Error);
    EXPECT_FALSE(fs::exists(dir.file("planes_R000.png")));
    EXPECT_FALSE(fs::exists(dir.file("planes.json")));
}

}  // namespace
}  // namespace shprt
