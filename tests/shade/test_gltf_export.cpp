// glTF export (shade/gltf_export.hpp): the .glb parsed back here — container, accessors, every
// attribute's values in vertex order (float32 exactly, int16 within its stated bound), COLOR_0
// against shade_vertices, the extras block's convention and light — and bad input leaving no file.
// The Khronos validator's verdict on real exports is the CTest test web_gltf_validator.
#include "shade_test_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/shade/gltf_export.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/shade/sun_shade.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>

namespace shprt {
namespace {

using Json = nlohmann::json;

struct Glb {
    Json json;
    std::string bin;

    // The elements of accessor `index` as doubles (normalized SHORT decoded as glTF says).
    std::vector<double> accessor(int index) const {
        const Json& a = json["accessors"][index];
        const Json& view = json["bufferViews"][a["bufferView"].get<int>()];
        const std::size_t offset = view["byteOffset"].get<std::size_t>();
        const std::size_t count = a["count"].get<std::size_t>();
        const std::string type = a["type"];
        const std::size_t n = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
        const int component = a["componentType"];
        const bool normalized = a.value("normalized", false);
        std::vector<double> out(count * n);
        for (std::size_t i = 0; i < count * n; ++i) {
            const char* p = bin.data() + offset;
            if (component == 5126) {
                float f;
                std::memcpy(&f, p + 4 * i, 4);
                out[i] = f;
            } else if (component == 5125) {
                std::uint32_t u;
                std::memcpy(&u, p + 4 * i, 4);
                out[i] = u;
            } else if (component == 5122) {
                std::int16_t s;
                std::memcpy(&s, p + 2 * i, 2);
                out[i] = normalized ? std::max(s / 32767.0, -1.0) : s;
            } else {
                ADD_FAILURE() << "unexpected component type " << component;
            }
        }
        EXPECT_LE(offset + count * n * (component == 5122 ? 2 : 4),
                  offset + view["byteLength"].get<std::size_t>());
        return out;
    }
    const Json& primitive() const { return json["meshes"][0]["primitives"][0]; }
    std::vector<double> attribute(const std::string& name) const {
        return accessor(primitive()["attributes"][name].get<int>());
    }
};

std::uint32_t u32(const std::string& s, std::size_t at) {
    std::uint32_t x;
    std::memcpy(&x, s.data() + at, 4);
    return x;
}

Glb read_glb(const std::string& path) {
    const std::string bytes = read_file(path);
    Glb glb;
    EXPECT_GE(bytes.size(), 28u);
    EXPECT_EQ(bytes.substr(0, 4), "glTF");
    EXPECT_EQ(u32(bytes, 4), 2u);
    EXPECT_EQ(u32(bytes, 8), bytes.size());
    const std::uint32_t json_len = u32(bytes, 12);
    EXPECT_EQ(json_len % 4, 0u);
    EXPECT_EQ(bytes.substr(16, 4), "JSON");
    glb.json = Json::parse(bytes.substr(20, json_len));
    const std::size_t bin_at = 20 + json_len;
    const std::uint32_t bin_len = u32(bytes, bin_at);
    EXPECT_EQ(bytes.substr(bin_at + 4, 4), std::string("BIN\0", 4));
    EXPECT_EQ(bin_at + 8 + bin_len, bytes.size());
    EXPECT_EQ(glb.json["buffers"][0]["byteLength"].get<std::size_t>(), bin_len);
    glb.bin = bytes.substr(bin_at + 8, bin_len);
    return glb;
}

struct Scene {
    Mesh mesh = make_builtin("sphere");
    TransferSet transfer;
};

Scene scene(int K, int channels = 1) {
    Scene s;
    const double scale[3] = {1.0, 0.5, 0.25};
    s.transfer = test::analytic_transfer(s.mesh, K, channels, scale);
    for (std::size_t v = 0; v < s.mesh.vertex_count(); ++v)
        s.mesh.albedo[v] = {0.2f + 0.6f * float(v % 7) / 7, 0.5f, 0.8f};
    return s;
}

GltfExportOptions options_with(std::vector<std::string> lights, int K = 0, bool half = false) {
    GltfExportOptions o;
    o.light.specs = std::move(lights);
    o.K = K;
    o.half = half;
    return o;
}

TEST(GltfExport, AttributesAreTheMeshAndTheTransferInVertexOrder) {
    test::TempDir dir;
    const Scene s = scene(13, 3);  // K not a multiple of 4: the last VEC4 is padded with zeros
    write_glb(dir.file("a.glb"), s.mesh, s.transfer, options_with({"sun:0.3,0.9,0.2,20"}));
    const Glb glb = read_glb(dir.file("a.glb"));
    EXPECT_EQ(glb.json["asset"]["version"], "2.0");
    const std::size_t V = s.mesh.vertex_count();
    const auto position = glb.attribute("POSITION"), normal = glb.attribute("NORMAL"),
               albedo = glb.attribute("_SHPRT_ALBEDO");
    for (std::size_t v = 0; v < V; ++v)
        for (int j = 0; j < 3; ++j) {
            ASSERT_EQ(position[3 * v + j], (&s.mesh.positions[v].x)[j]);
            ASSERT_EQ(normal[3 * v + j], (&s.mesh.normals[v].x)[j]);
            ASSERT_EQ(albedo[3 * v + j], (&s.mesh.albedo[v].x)[j]);
        }
    const Json& extras = glb.primitive()["extras"]["shprt"];
    EXPECT_EQ(extras["K"], 13);
    EXPECT_EQ(extras["channels"], 3);
    EXPECT_EQ(extras["attributes"]["per_channel"], 4);
    EXPECT_EQ(extras["encoding"], "float32");
    EXPECT_EQ(extras["sh"]["condon_shortley_phase"], true);
    for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 4; ++a) {
            const auto t = glb.attribute("_SHPRT_T" + std::to_string(c * 4 + a));
            ASSERT_EQ(t.size(), 4 * V);
            for (std::size_t v = 0; v < V; ++v)
                for (int j = 0; j < 4; ++j) {
                    const int i = 4 * a + j;
                    ASSERT_EQ(t[4 * v + j], i < 13 ? s.transfer.receiver(v, c)[i] : 0.0f)
                        << "vertex " << v << " channel " << c << " coefficient " << i;
                }
        }
    EXPECT_FALSE(glb.primitive()["attributes"].contains("_SHPRT_T12"));
    const auto indices = glb.accessor(glb.primitive()["indices"].get<int>());
    ASSERT_EQ(indices.size(), 3 * s.mesh.triangle_count());
    for (std::size_t t = 0; t < s.mesh.triangle_count(); ++t)
        for (int j = 0; j < 3; ++j) ASSERT_EQ(indices[3 * t + j], s.mesh.triangles[t][j]);
}

TEST(GltfExport, Color0IsTheShadedRadianceAndTheLightIsInTheExtras) {
    test::TempDir dir;
    const Scene s = scene(16);
    GltfExportOptions o = options_with({"sun:0.3,0.9,0.2,20", "gradient"}, 9);
    o.light.yaw_pitch_roll_deg = {30, 10, 0};
    write_glb(dir.file("a.glb"), s.mesh, s.transfer, o);
    const Glb glb = read_glb(dir.file("a.glb"));

    const ShLight light = prepare_light(o.light, 9);  // what `shprt shade --coeffs 9` uses
    ShadeOptions so;
    so.K_used = 9;
    const ShadeResult want = shade_vertices(s.mesh, s.transfer, light, so);
    const auto colour = glb.attribute("COLOR_0");
    for (std::size_t v = 0; v < s.mesh.vertex_count(); ++v)
        for (int j = 0; j < 3; ++j)
            ASSERT_EQ(colour[3 * v + j], std::clamp((&want.radiance[v].x)[j], 0.0f, 1.0f)) << v;

    const Json& extras = glb.primitive()["extras"]["shprt"];
    EXPECT_EQ(extras["K"], 9);
    EXPECT_EQ(extras["bands"], 3);
    EXPECT_EQ(extras["attributes"]["per_channel"], 3);
    // The light: full bands, rotated; its first K coefficients are the shading light's.
    EXPECT_EQ(extras["light"]["K"], 9);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 9; ++i)
            EXPECT_EQ(extras["light"]["coeffs"][c][i].get<float>(), light.channel(c)[i]);
    EXPECT_EQ(extras["light"]["specs"][1], "gradient");
    EXPECT_EQ(extras["light"]["rotate_yaw_pitch_roll_deg"][0], 30.0);
    EXPECT_TRUE(extras["camera"]["eye"].is_array());
    EXPECT_EQ(glb.json["materials"][0]["extensions"].count("KHR_materials_unlit"), 1u);
}

// --sun: a KHR_lights_punctual directional light whose node turns −Z into the direction of travel
// (−s, after --rotate), intensity and colour from the disc's irradiance; the SH light in the
// extras is the sky alone (the sun counted once), and COLOR_0 is shade_with_sun's radiance.
TEST(GltfExport, SunIsAPunctualLightAndNotInTheShLight) {
    test::TempDir dir;
    const Scene s = scene(16);
    GltfExportOptions o = options_with({"gradient"});
    o.light.sun = make_sun({0.3, 0.9, -0.2}, 3.0, {2e4, 1.8e4, 1.5e4});
    o.light.yaw_pitch_roll_deg = {40, 0, 0};
    o.exposure = 0.3f;
    write_glb(dir.file("a.glb"), s.mesh, s.transfer, o);
    const Glb glb = read_glb(dir.file("a.glb"));

    const PreparedSun sun = prepare_sun(o.light, 16);  // its direction turned by --rotate
    const Json& lights = glb.json["extensions"]["KHR_lights_punctual"]["lights"];
    ASSERT_EQ(lights.size(), 1u);
    EXPECT_EQ(lights[0]["type"], "directional");
    const Vec3d E = sun_irradiance(sun.sun);
    EXPECT_NEAR(lights[0]["intensity"].get<double>(), E.x, 1e-9 * E.x);
    EXPECT_NEAR(lights[0]["color"][2].get<double>(), E.z / E.x, 1e-12);
    const Json& node = glb.json["nodes"][1];
    EXPECT_EQ(node["extensions"]["KHR_lights_punctual"]["light"], 0);
    EXPECT_EQ(glb.json["scenes"][0]["nodes"][1], 1);
    EXPECT_EQ(glb.json["extensionsUsed"][1], "KHR_lights_punctual");
    const Json& q = node["rotation"];  // (x, y, z, w)
    const Mat3d R = matrix_from_quat(
        {q[3].get<double>(), q[0].get<double>(), q[1].get<double>(), q[2].get<double>()});
    const Vec3d shines = R * Vec3d{0, 0, -1};
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(shines[j], -sun.sun.direction[j], 1e-12) << j;
    EXPECT_GT(std::abs(sun.sun.direction.x - 0.3 / std::sqrt(0.94)), 0.1) << "--rotate turned it";

    const ShLight sky = prepare_light(o.light, 16);  // the gradient alone
    const Json& extras = glb.primitive()["extras"]["shprt"];
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 16; ++i)
            EXPECT_EQ(extras["light"]["coeffs"][c][i].get<float>(), sky.channel(c)[i]);
    EXPECT_EQ(extras["sun"]["radius_deg"], 3.0);
    ShadeOptions so;
    so.K_used = 16;
    const SunShadeResult want = shade_with_sun(s.mesh, s.transfer, sky, sun, so, {});
    const auto colour = glb.attribute("COLOR_0");
    std::size_t sunlit = 0;
    for (std::size_t v = 0; v < s.mesh.vertex_count(); ++v) {
        sunlit += want.sun_direct[v].x > 0;
        for (int j = 0; j < 3; ++j)
            ASSERT_EQ(colour[3 * v + j],
                      std::clamp((&want.radiance[v].x)[j] * o.exposure, 0.0f, 1.0f))
                << v;
    }
    EXPECT_GT(sunlit, s.mesh.vertex_count() / 4);
}

TEST(GltfExport, Color0IsExposedAndClampedToTheUnitRangeGltfAllows) {
    test::TempDir dir;
    const Scene s = scene(9);
    GltfExportOptions o = options_with({"constant:3,3,3"});
    o.exposure = 0.5f;
    write_glb(dir.file("a.glb"), s.mesh, s.transfer, o);
    const Glb glb = read_glb(dir.file("a.glb"));
    const ShadeResult want =
        shade_vertices(s.mesh, s.transfer, prepare_light(o.light, 9), ShadeOptions{});
    const auto colour = glb.attribute("COLOR_0");
    std::size_t clipped = 0;
    for (std::size_t v = 0; v < s.mesh.vertex_count(); ++v) {
        const Vec3f L = want.radiance[v] * 0.5f;
        for (int j = 0; j < 3; ++j)
            ASSERT_EQ(colour[3 * v + j], std::clamp((&L.x)[j], 0.0f, 1.0f)) << v;
        if (std::max({L.x, L.y, L.z}) > 1.0f) ++clipped;
    }
    EXPECT_GT(clipped, 0u);  // the case is exercised: albedo 0.8 × 3 / 2 > 1
    const Json& r = glb.primitive()["extras"]["shprt"]["radiometry"];
    EXPECT_EQ(r["color_0_exposure"], 0.5);
    EXPECT_EQ(r["color_0_clipped_vertices"], clipped);
}

TEST(GltfExport, HalfIsNormalizedInt16WithinItsStatedBound) {
    test::TempDir dir;
    const Scene s = scene(16, 3);
    write_glb(dir.file("h.glb"), s.mesh, s.transfer, options_with({"builtin"}, 0, true));
    const Glb glb = read_glb(dir.file("h.glb"));
    const Json& extras = glb.primitive()["extras"]["shprt"];
    EXPECT_EQ(extras["encoding"], "int16_normalized");
    double worst = 0;
    for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 4; ++a) {
            const Json& acc =
                glb.json["accessors"]
                        [glb.primitive()["attributes"]["_SHPRT_T" + std::to_string(c * 4 + a)]
                             .get<int>()];
            EXPECT_EQ(acc["componentType"], 5122);
            EXPECT_EQ(acc["normalized"], true);
            const auto t = glb.attribute("_SHPRT_T" + std::to_string(c * 4 + a));
            for (std::size_t v = 0; v < s.mesh.vertex_count(); ++v)
                for (int j = 0; j < 4; ++j) {
                    const int i = 4 * a + j;
                    const double scale = extras["scale"][c][i];
                    const double got = t[4 * v + j] * scale;
                    const double want = s.transfer.receiver(v, c)[i];
                    // Rounding to 1/32767 of the scale: half a step, plus float slack.
                    ASSERT_LE(std::abs(got - want), scale / 65534 * 1.001 + 1e-9)
                        << v << " " << c << " " << i;
                    worst = std::max(worst, std::abs(got - want) / scale);
                }
        }
    EXPECT_GT(worst, 0.0);  // it did quantize
    // Half the bytes of float32 for the transfer.
    write_glb(dir.file("f.glb"), s.mesh, s.transfer, options_with({"builtin"}));
    EXPECT_LT(std::filesystem::file_size(dir.file("h.glb")),
              0.7 * double(std::filesystem::file_size(dir.file("f.glb"))));
}

// --attributes standard: the channels·K coefficients in order, two per TEXCOORD_0..7, then four
// per COLOR_1..; the convention block on the primitive, the mesh and the node (Blender reads the
// last two).
TEST(GltfExport, StandardAttributesHoldTheCoefficientsInOrder) {
    test::TempDir dir;
    const Scene s = scene(9, 3);  // 27 floats: 8 TEXCOORD pairs (16), then 3 COLOR_n (12, 1 padded)
    GltfExportOptions o = options_with({"builtin"});
    o.attributes = GltfAttributes::standard;
    write_glb(dir.file("s.glb"), s.mesh, s.transfer, o);
    const Glb glb = read_glb(dir.file("s.glb"));
    const std::size_t V = s.mesh.vertex_count();
    const Json& names = glb.primitive()["extras"]["shprt"]["attributes"]["standard"];
    ASSERT_EQ(names.size(), 11u);
    EXPECT_EQ(names[0], "TEXCOORD_0");
    EXPECT_EQ(names[7], "TEXCOORD_7");
    EXPECT_EQ(names[8], "COLOR_1");
    EXPECT_EQ(names[10], "COLOR_3");
    std::vector<std::vector<double>> sets;
    for (const auto& name : names) sets.push_back(glb.attribute(name.get<std::string>()));
    for (std::size_t v = 0; v < V; ++v) {
        int f = 0;
        for (const auto& set : sets) {
            const std::size_t width = set.size() / V;
            ASSERT_TRUE(width == 2 || width == 4);
            for (std::size_t j = 0; j < width; ++j, ++f) {
                const float want = f < 27 ? s.transfer.receiver(v, f / 9)[f % 9] : 0.0f;
                ASSERT_EQ(set[v * width + j], want) << "vertex " << v << " float " << f;
            }
        }
        ASSERT_EQ(f, 28);
    }
    for (const auto& [name, index] : glb.primitive()["attributes"].items())
        EXPECT_EQ(name.rfind("_SHPRT_T", 0), std::string::npos) << name;
    EXPECT_EQ(glb.json["meshes"][0]["extras"], glb.primitive()["extras"]);
    EXPECT_EQ(glb.json["nodes"][0]["extras"], glb.primitive()["extras"]);
    // 16-bit coefficients are signed: TEXCOORD_n and COLOR_n cannot hold them.
    o.half = true;
    EXPECT_THROW(write_glb(dir.file("h.glb"), s.mesh, s.transfer, o), Error);
    // More than the standard attributes' room (16 + 4·64 floats).
    const Scene big = scene(100, 3);
    o.half = false;
    EXPECT_THROW(write_glb(dir.file("b.glb"), big.mesh, big.transfer, o), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.file("h.glb")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("b.glb")));
}

TEST(GltfExport, BadInputThrowsAndLeavesNoFile) {
    test::TempDir dir;
    const std::string out = dir.file("bad.glb");
    Scene s = scene(16);
    EXPECT_THROW(write_glb(out, s.mesh, s.transfer, options_with({}, 25)), Error);
    EXPECT_THROW(write_glb(out, s.mesh, s.transfer, options_with({}, -1)), Error);
    GltfExportOptions dark = options_with({});
    dark.exposure = 0;
    EXPECT_THROW(write_glb(out, s.mesh, s.transfer, dark), Error);
    EXPECT_THROW(write_glb(out, s.mesh, s.transfer, options_with({"nosuchlight"})), Error);
    EXPECT_THROW(write_glb(out, s.mesh, s.transfer, options_with({"constant:1e38"})), Error);
    Scene nan = scene(16);
    nan.transfer.coeffs[5 * 16 + 3] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(write_glb(out, nan.mesh, nan.transfer, options_with({})), Error);
    Scene no_albedo = scene(16);
    no_albedo.mesh.albedo.clear();
    EXPECT_THROW(write_glb(out, no_albedo.mesh, no_albedo.transfer, options_with({})), Error);
    Scene matrix = scene(4);
    matrix.transfer.layout.shape = TransferShape::matrix;
    matrix.transfer.coeffs.resize(matrix.transfer.layout.floats(matrix.mesh.vertex_count()));
    EXPECT_THROW(write_glb(out, matrix.mesh, matrix.transfer, options_with({})), Error);
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // no temporaries either
}

}  // namespace
}  // namespace shprt
