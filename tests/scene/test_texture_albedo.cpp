// Albedo from colour textures (scene/load.hpp, src/scene/texture_albedo.hpp): an OBJ whose
// material has map_Kd is sampled at its vertices' UVs (v = 0 at the image's bottom), sRGB texels
// made linear before the bilinear filter, times Kd; an unreadable texture warns once and falls
// back to the material's colour; the glTF box of Assimp's own corpus gives the same albedo in its
// three packagings (PNG beside the file, GLB buffer, data URI).
#include "shprt/core/colour.hpp"
#include "shprt/core/log.hpp"
#include "shprt/scene/load.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace shprt {
namespace {

namespace fs = std::filesystem;

class TextureAlbedo : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::path(::testing::TempDir()) / ("shprt_texture_" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
        // 2×2 sRGB texels; row 0 is the image's top.
        const std::array<std::uint8_t, 12> rgb = {200, 100, 50, 10, 20, 30,  // top
                                                  255, 255, 255, 0, 0, 0};   // bottom
        ASSERT_NE(stbi_write_png((m_dir / "tex.png").c_str(), 2, 2, 3, rgb.data(), 6), 0);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    // A quad in y = 0 with corners at texel centres and one corner between two texels.
    std::string write_obj(const std::string& map) {
        std::ofstream(m_dir / "m.mtl") << "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd " << map << "\n";
        std::ofstream(m_dir / "quad.obj")
            << "mtllib m.mtl\n"
               "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
               "vt 0.25 0.75\nvt 0.75 0.75\nvt 0.5 0.25\nvt 0.25 0.25\n"
               "vn 0 1 0\nusemtl m\nf 1/1/1 4/4/1 3/3/1\nf 1/1/1 3/3/1 2/2/1\n";
        return (m_dir / "quad.obj").string();
    }

    fs::path m_dir;
};

float lin(int code) { return srgb_to_linear(float(code) / 255.0f); }

TEST_F(TextureAlbedo, ObjMapKdIsSampledAtTheUvsInLinearSpace) {
    const Mesh mesh = load_scene(write_obj("tex.png"));
    EXPECT_EQ(mesh.albedo_source, "diffuse texture");
    ASSERT_EQ(mesh.albedo.size(), mesh.vertex_count());
    int checked = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const Vec3f p = mesh.positions[v];
        Vec3f want{};
        if (p.x == 0 && p.z == 0) want = {lin(200), lin(100), lin(50)};  // top left
        if (p.x == 1 && p.z == 0) want = {lin(10), lin(20), lin(30)};    // top right
        if (p.x == 0 && p.z == 1) want = {1, 1, 1};                      // bottom left
        // Half way between white and black, filtered in linear space: 0.5 (in sRGB space it
        // would be srgb_to_linear(0.5) = 0.214).
        if (p.x == 1 && p.z == 1) want = {0.5f, 0.5f, 0.5f};
        want = want * 0.5f;  // Kd
        EXPECT_NEAR(mesh.albedo[v].x, want.x, 1e-6) << v;
        EXPECT_NEAR(mesh.albedo[v].y, want.y, 1e-6) << v;
        EXPECT_NEAR(mesh.albedo[v].z, want.z, 1e-6) << v;
        ++checked;
    }
    EXPECT_GE(checked, 4);
}

TEST_F(TextureAlbedo, AnUnreadableTextureWarnsAndUsesTheMaterialColour) {
    std::ofstream(m_dir / "broken.png") << "not a png";
    for (const std::string map : {"missing.png", "broken.png"}) {
        std::string err;
        set_log_sink([&](LogLevel, std::string_view m) { err += std::string(m) + "\n"; });
        const Mesh mesh = load_scene(write_obj(map));
        set_log_sink(nullptr);
        EXPECT_EQ(mesh.albedo_source, "material diffuse colour") << map;
        for (const Vec3f a : mesh.albedo) EXPECT_EQ(a, (Vec3f{0.5f, 0.5f, 0.5f})) << map;
        EXPECT_NE(err.find("colour texture could not be read"), std::string::npos) << err;
    }
}

TEST(TextureAlbedoCorpus, TheGltfBoxHasTheSameAlbedoInItsThreePackagings) {
    const std::string dir = "/usr/share/assimp/models/glTF2/";
    const std::string files[] = {dir + "BoxTextured-glTF/BoxTextured.gltf",
                                 dir + "BoxTextured-glTF-Binary/BoxTextured.glb",
                                 dir + "BoxTextured-glTF-Embedded/BoxTextured.gltf"};
    for (const std::string& f : files)
        if (!fs::exists(f)) GTEST_SKIP() << f << " is missing (scripts/setup installs it)";
    const Mesh first = load_scene(files[0]);
    EXPECT_EQ(first.albedo_source, "diffuse texture");
    // The box's UVs are whole numbers (0 or 1 up to 1.2e-7, the logo repeated on each face), so
    // every vertex samples the image's corner: with repeat wrapping, the mean of the four corner
    // texels, in linear space (baseColorFactor is 1).
    int w = 0, h = 0, n = 0;
    stbi_uc* png = stbi_load((dir + "BoxTextured-glTF/CesiumLogoFlat.png").c_str(), &w, &h, &n, 3);
    ASSERT_NE(png, nullptr);
    Vec3f corner{0, 0, 0};
    for (const int x : {0, w - 1})
        for (const int y : {0, h - 1}) {
            const stbi_uc* t = png + 3 * (std::size_t(y) * std::size_t(w) + std::size_t(x));
            corner = corner + Vec3f{lin(t[0]), lin(t[1]), lin(t[2])} * 0.25f;
        }
    stbi_image_free(png);
    for (const Vec3f a : first.albedo) {
        EXPECT_NEAR(a.x, corner.x, 1e-5);
        EXPECT_NEAR(a.y, corner.y, 1e-5);
        EXPECT_NEAR(a.z, corner.z, 1e-5);
    }
    for (const std::string& f : {files[1], files[2]}) {
        const Mesh other = load_scene(f);
        EXPECT_EQ(other.albedo_source, "diffuse texture") << f;
        EXPECT_EQ(other.albedo, first.albedo) << f;
    }
}

}  // namespace
}  // namespace shprt
