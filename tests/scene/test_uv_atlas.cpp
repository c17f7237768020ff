// The generated UV atlas (scene/uv_atlas.hpp) on the coarse room: charts never overlap (the texel
// rasteriser's own check at 1024², and chart boxes at least the gutter apart), every triangle has
// UV area at the atlas's one scale (planar faces undistorted, smooth ones foreshortened at most by
// the cone angle), the split keeps the builder's vertices and triangles, and it is deterministic.
#include "shprt/core/error.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/scene/uv_atlas.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace shprt {
namespace {

double uv_area(const Mesh& m, std::size_t t) {
    const auto& a = m.uvs[m.triangles[t][0]];
    const auto& b = m.uvs[m.triangles[t][1]];
    const auto& c = m.uvs[m.triangles[t][2]];
    return 0.5 * std::abs(double(b[0] - a[0]) * double(c[1] - a[1]) -
                          double(c[0] - a[0]) * double(b[1] - a[1]));
}

double world_area(const Mesh& m, std::size_t t) {
    const Vec3d a = cast<double>(m.positions[m.triangles[t][0]]);
    return 0.5 * length(cross(cast<double>(m.positions[m.triangles[t][1]]) - a,
                              cast<double>(m.positions[m.triangles[t][2]]) - a));
}

TEST(UvAtlas, TheCoarseRoomHasAnAtlasWithoutOverlaps) {
    const Mesh room = generate_room({2000, false});
    ASSERT_EQ(room.uvs.size(), room.vertex_count());
    for (const auto& uv : room.uvs)
        for (float x : uv) ASSERT_TRUE(x >= 0.0f && x <= 1.0f) << x;
    // The rasteriser refuses a texel centre strictly inside two triangles.
    const TexelSamples texels = rasterize_texels(room, 1024, 1024);
    EXPECT_GT(texels.count(), 1024u * 1024u / 4);  // a quarter of the atlas at least is used
    // Every triangle is covered: it has UV area, and the texel under its UV centroid is a
    // covered texel of one of its chart's triangles (owners are per texel: a sliver shares).
    std::vector<std::int64_t> owner(1024 * 1024, -1);
    for (std::size_t r = 0; r < texels.count(); ++r) owner[texels.texel[r]] = texels.triangle[r];
    std::size_t uncovered = 0;
    for (std::size_t t = 0; t < room.triangle_count(); ++t) {
        ASSERT_GT(uv_area(room, t), 0.0) << "triangle " << t;
        double u = 0, v = 0;
        for (std::uint32_t i : room.triangles[t])
            u += room.uvs[i][0] / 3.0, v += room.uvs[i][1] / 3.0;
        const auto x = std::size_t(u * 1024), y = std::size_t((1 - v) * 1024);
        const std::int64_t o =
            owner[std::min<std::size_t>(y, 1023) * 1024 + std::min<std::size_t>(x, 1023)];
        uncovered += o < 0;
    }
    EXPECT_EQ(uncovered, 0u);
}

TEST(UvAtlas, ChartsAreAGutterApartAtOneScale) {
    Mesh room = generate_room({2000, false});
    const std::size_t V = room.vertex_count(), T = room.triangle_count();
    const Mesh before = room;
    UvAtlasOptions options;
    const UvAtlasInfo info = make_uv_atlas(room, options);
    // Already split by generate_room: a second atlas adds no vertices and keeps the triangles.
    EXPECT_EQ(info.added_vertices, 0u);
    EXPECT_EQ(room.vertex_count(), V);
    EXPECT_EQ(room.triangles, before.triangles);
    ASSERT_EQ(info.chart.size(), T);
    // UV area = world area × scale² × cos(angle to the chart's axis) ∈ [cos 45°, 1].
    const double s = info.texels_per_metre / options.resolution;
    for (std::size_t t = 0; t < T; ++t) {
        const double ratio = uv_area(room, t) / (world_area(room, t) * s * s);
        ASSERT_LE(ratio, 1 + 1e-3) << "triangle " << t;
        ASSERT_GE(ratio, std::cos(options.max_angle_deg * 3.14159265358979 / 180) - 1e-3)
            << "triangle " << t;
    }
    // Chart boxes: at least the gutter apart (in texels at the resolution) on one axis.
    struct Box {
        double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
    };
    std::vector<Box> boxes(info.charts);
    for (std::size_t t = 0; t < T; ++t)
        for (std::uint32_t v : room.triangles[t])
            for (int k = 0; k < 2; ++k) {
                Box& b = boxes[info.chart[t]];
                b.lo[k] = std::min(b.lo[k], double(room.uvs[v][k]) * options.resolution);
                b.hi[k] = std::max(b.hi[k], double(room.uvs[v][k]) * options.resolution);
            }
    for (std::size_t i = 0; i < boxes.size(); ++i)
        for (std::size_t j = i + 1; j < boxes.size(); ++j) {
            double gap = -1e9;
            for (int k = 0; k < 2; ++k)
                gap = std::max(
                    {gap, boxes[j].lo[k] - boxes[i].hi[k], boxes[i].lo[k] - boxes[j].hi[k]});
            ASSERT_GE(gap, options.gutter_texels - 1e-3) << "charts " << i << " and " << j;
        }
}

TEST(UvAtlas, SplitsSharedVerticesKeepingTheOriginals) {
    // A sphere: one smooth piece, cut into charts; its vertices keep their indices and places.
    MeshBuilder b;
    b.add_icosphere({0, 0, 0}, 1.0, 2, {0.5f, 0.5f, 0.5f});
    Mesh sphere = b.take_mesh("sphere");
    sphere.brdfs = {Brdf{BrdfModel::ggx, 0.5}};
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v)
        sphere.brdf_index.push_back(v % 2 == 0 ? 0u : Mesh::kNoBrdf);
    const Mesh before = sphere;
    const UvAtlasInfo info = make_uv_atlas(sphere);
    EXPECT_GT(info.charts, 2u);
    EXPECT_GT(info.added_vertices, 0u);
    ASSERT_EQ(sphere.vertex_count(), before.vertex_count() + info.added_vertices);
    for (std::size_t v = 0; v < before.vertex_count(); ++v)
        ASSERT_EQ(sphere.positions[v], before.positions[v]);
    for (std::size_t t = 0; t < sphere.triangle_count(); ++t) {
        for (int k = 0; k < 3; ++k) {
            ASSERT_EQ(sphere.positions[sphere.triangles[t][k]],
                      before.positions[before.triangles[t][k]]);
            // A split vertex keeps its original's material BRDF.
            ASSERT_EQ(sphere.brdf_index[sphere.triangles[t][k]],
                      before.brdf_index[before.triangles[t][k]]);
        }
    }
    EXPECT_NO_THROW(rasterize_texels(sphere, 512, 512));
    // Deterministic.
    Mesh again = before;
    make_uv_atlas(again);
    EXPECT_EQ(again.uvs, sphere.uvs);
    EXPECT_EQ(again.triangles, sphere.triangles);
    Mesh empty;
    EXPECT_THROW(make_uv_atlas(empty), Error);
    UvAtlasOptions bad;
    bad.max_angle_deg = 90;
    EXPECT_THROW(make_uv_atlas(again, bad), Error);
}

}  // namespace
}  // namespace shprt
