// Texel samples of a UV atlas (scene/texel_raster.hpp): coverage, interpolation, conservative
// coverage of thin triangles, and the errors for meshes without UVs or with overlapping UVs.
#include "shprt/core/error.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/texel_raster.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace shprt {
namespace {

// One triangle facing +Y with the given UVs at (0,0,0), (1,0,0), (0,0,1).
Mesh uv_triangle(std::array<float, 2> a, std::array<float, 2> b, std::array<float, 2> c) {
    Mesh m;
    m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
    m.normals.assign(3, {0, 1, 0});
    m.albedo.assign(3, {0.5f, 0.5f, 0.5f});
    m.uvs = {a, b, c};
    m.triangles = {{0, 1, 2}};
    m.source = "test";
    return m;
}

TEST(TexelRaster, QuadBoxFloorTexelsLieWhereTheirUvsSay) {
    const Mesh mesh = make_builtin("quad_box");
    const int W = 64, H = 48;
    const TexelSamples s = rasterize_texels(mesh, W, H);
    ASSERT_GT(s.count(), 0u);
    EXPECT_EQ(s.positions.size(), s.count());
    // Charts: the floor 0.7² and five 0.2² tiles: 69 % of the image, a little more with the
    // conservative border texels, never less.
    const double covered = double(s.count()) / double(W * H);
    EXPECT_GE(covered, 0.69);
    EXPECT_LE(covered, 0.69 + 0.12);
    std::size_t floor = 0;
    for (std::size_t r = 0; r < s.count(); ++r) {
        EXPECT_LT(r == 0 ? 0u : s.texel[r - 1], r == 0 ? 1u : s.texel[r]);  // ascending
        EXPECT_NEAR(length(s.normals[r]), 1.0f, 1e-5f);
        if (s.triangle[r] >= 2) continue;  // the floor is triangles 0 and 1
        ++floor;
        // Floor UVs: u = (z + 2) / 4 · 0.7 (its first edge runs along +z), v = (x + 2) / 4 · 0.7.
        const double u = (double(s.texel[r] % W) + 0.5) / W;
        const double v = 1.0 - (double(s.texel[r] / W) + 0.5) / H;
        if (u > 0.7 || v > 0.7) continue;  // a border texel, clamped onto the triangle
        EXPECT_NEAR(s.positions[r].z, u / 0.7 * 4 - 2, 1e-4) << r;
        EXPECT_NEAR(s.positions[r].x, v / 0.7 * 4 - 2, 1e-4) << r;
        EXPECT_EQ(s.positions[r].y, 0.0f);
    }
    EXPECT_GT(floor, std::size_t(0.45 * W * H));
}

TEST(TexelRaster, ThinTrianglesGetTexelsConservatively) {
    // A sliver a tenth of a texel wide that covers no texel centre.
    const Mesh m = uv_triangle({0.1f, 0.5f}, {0.9f, 0.5f}, {0.9f, 0.5f + 0.1f / 16});
    const TexelSamples s = rasterize_texels(m, 16, 16);
    EXPECT_GE(s.count(), 12u);            // about the 13 texels it crosses
    for (const Vec3f& p : s.positions) {  // clamped onto the triangle
        EXPECT_GE(p.x, -1e-6f);
        EXPECT_GE(p.z, -1e-6f);
        EXPECT_LE(p.x + p.z, 1.0f + 1e-5f);
    }
}

TEST(TexelRaster, MeshWithoutUvsIsAnError) {
    Mesh m = make_builtin("plane");
    try {
        rasterize_texels(m, 8, 8);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        EXPECT_NE(std::string(e.what()).find("no texture coordinates"), std::string::npos);
    }
}

TEST(TexelRaster, OverlappingUvsAreAnError) {
    Mesh m = make_builtin("quad_box");
    // The box's top face mapped onto the floor's chart.
    for (std::uint32_t v = 4; v < 8; ++v) m.uvs[v] = {m.uvs[v][0] - 0.5f, m.uvs[v][1] + 0.1f};
    try {
        rasterize_texels(m, 32, 32);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        EXPECT_NE(std::string(e.what()).find("overlap in UV space"), std::string::npos);
    }
    // Shared edges are not overlaps: the unchanged atlas passes.
    EXPECT_NO_THROW(rasterize_texels(make_builtin("quad_box"), 32, 32));
}

TEST(TexelRaster, BadResolutionIsAnError) {
    const Mesh m = make_builtin("quad_box");
    EXPECT_THROW(rasterize_texels(m, 0, 8), Error);
    EXPECT_THROW(rasterize_texels(m, 8, kMaxTexelSide + 1), Error);
}

}  // namespace
}  // namespace shprt
