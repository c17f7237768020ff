// The conformal UV atlas (scene/uv_atlas.hpp, ChartLayout::conformal: `shprt bake --unwrap`,
// `shprt scene unwrap`) on meshes built like real assets — a bumpy sphere standing in for the
// bunny (no bunny is in the repository or in Debian's Assimp corpus) with an interpenetrating
// open-backed panel, duplicated (overlapping) triangles, a non-manifold fin, a triangle without
// area and a part with split (unwelded) vertices — and on meshes of Assimp's own corpus (skipped
// when assimp-testmodels is not installed). Checked: no overlapping texels (the rasteriser's own
// check), the stretch bound and the reported stretch, one scale (texels per metre), the mesh kept
// (positions, triangle order), the gutters filled by dilation from their own chart only, and bad
// input refused with one message.
#include "shprt/core/error.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/scene/uv_atlas.hpp"
#include "shprt/transfer/transfer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

constexpr double kPiD = 3.14159265358979323846;

std::uint32_t add_vertex(Mesh& m, Vec3f p, Vec3f n) {
    m.positions.push_back(p);
    m.normals.push_back(n);
    return std::uint32_t(m.positions.size() - 1);
}

// A latitude–longitude sphere of radius 1 ± 0.15 bumps (rings × 2·rings quads, one vertex per
// pole), centred at the origin.
void add_bumpy_sphere(Mesh& m, int rings) {
    const auto first = std::uint32_t(m.positions.size());
    const auto point = [](double theta, double phi) {
        const double r = 1 + 0.15 * std::sin(5 * theta) * std::cos(3 * phi);
        const Vec3f d{float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                      float(std::sin(theta) * std::sin(phi))};
        return std::pair{Vec3f{float(r * d.x), float(r * d.y), float(r * d.z)}, d};
    };
    const int segments = 2 * rings;
    const auto [top, up] = point(0, 0);
    add_vertex(m, top, up);
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const auto [p, n] = point(kPiD * i / rings, 2 * kPiD * j / segments);
            add_vertex(m, p, n);
        }
    const auto [bottom, down] = point(kPiD, 0);
    const std::uint32_t south = add_vertex(m, bottom, down);
    const auto at = [&](int i, int j) {
        return first + 1 + std::uint32_t((i - 1) * segments + (j % segments));
    };
    for (int j = 0; j < segments; ++j) {
        m.triangles.push_back({first, at(1, j + 1), at(1, j)});
        m.triangles.push_back({south, at(rings - 1, j), at(rings - 1, j + 1)});
    }
    for (int i = 1; i < rings - 1; ++i)
        for (int j = 0; j < segments; ++j) {
            m.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
            m.triangles.push_back({at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
        }
}

// An n × n grid of quads at height y = h(x, z) (a wavy panel, one-sided), either with shared
// vertices or with three of its own per triangle (as STL files and flat-shaded exports have).
void add_panel(Mesh& m, int n, float size, Vec3f origin, bool split_vertices) {
    const auto p = [&](int i, int j) {
        const float x = origin.x + size * float(i) / float(n);
        const float z = origin.z + size * float(j) / float(n);
        return Vec3f{x, origin.y + 0.1f * std::sin(3 * x) * std::cos(2 * z), z};
    };
    const Vec3f up{0, 1, 0};
    const auto first = std::uint32_t(m.positions.size());
    if (!split_vertices)
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n; ++j) add_vertex(m, p(i, j), up);
    const auto at = [&](int i, int j) { return first + std::uint32_t(i * (n + 1) + j); };
    const auto tri = [&](int i0, int j0, int i1, int j1, int i2, int j2) {
        if (!split_vertices) return m.triangles.push_back({at(i0, j0), at(i1, j1), at(i2, j2)});
        m.triangles.push_back({add_vertex(m, p(i0, j0), up), add_vertex(m, p(i1, j1), up),
                               add_vertex(m, p(i2, j2), up)});
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            tri(i, j, i, j + 1, i + 1, j);
            tri(i + 1, j, i, j + 1, i + 1, j + 1);
        }
}

// The bumpy sphere with the defects real assets have (see the top of the file).
Mesh messy_mesh() {
    Mesh m;
    m.source = "messy";
    add_bumpy_sphere(m, 16);
    const std::size_t sphere = m.triangle_count();
    add_panel(m, 12, 3.0f, {-1.5f, 0.2f, -1.5f}, false);  // through the sphere, open back
    for (std::size_t t = 40; t < 60; ++t) m.triangles.push_back(m.triangles[t]);  // duplicates
    // A fin on one of the sphere's edges: three triangles on that edge (non-manifold).
    const auto& e = m.triangles[sphere / 2];
    const std::uint32_t tip = add_vertex(m, {3, 3, 3}, {1, 0, 0});
    m.triangles.push_back({e[0], e[1], tip});
    // A triangle without area, on three collinear points of its own.
    const std::uint32_t a = add_vertex(m, {4, 0, 0}, {0, 1, 0});
    const std::uint32_t b = add_vertex(m, {5, 0, 0}, {0, 1, 0});
    const std::uint32_t c = add_vertex(m, {6, 0, 0}, {0, 1, 0});
    m.triangles.push_back({a, b, c});
    add_panel(m, 6, 1.0f, {4.0f, -1.0f, 0.0f}, true);  // split vertices
    return m;
}

double uv_area2(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const auto& a = m.uvs[t[0]];
    const auto& b = m.uvs[t[1]];
    const auto& c = m.uvs[t[2]];
    return double(b[0] - a[0]) * double(c[1] - a[1]) - double(c[0] - a[0]) * double(b[1] - a[1]);
}

double world_area(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const Vec3d a = cast<double>(m.positions[t[0]]);
    return 0.5 *
           length(cross(cast<double>(m.positions[t[1]]) - a, cast<double>(m.positions[t[2]]) - a));
}

// The options `shprt bake --unwrap --resolution R` uses (R = 0: set a density instead).
UvAtlasOptions unwrap_options(int resolution) {
    UvAtlasOptions options;
    options.layout = ChartLayout::conformal;
    options.max_angle_deg = kUnwrapMaxAngle;
    if (resolution > 0) options.resolution = resolution;
    return options;
}

// What every conformal atlas must be, whatever the mesh.
void expect_sound_atlas(const Mesh& before, const Mesh& after, const UvAtlasInfo& info,
                        const UvAtlasOptions& options) {
    SCOPED_TRACE(before.source);
    ASSERT_EQ(after.triangle_count(), before.triangle_count());
    ASSERT_EQ(after.uvs.size(), after.vertex_count());
    ASSERT_EQ(info.chart.size(), after.triangle_count());
    EXPECT_EQ(after.vertex_count(), before.vertex_count() + info.added_vertices);
    EXPECT_TRUE(info.overlaps_checked);
    // The mesh is kept: every corner at the same place, the original vertices first.
    for (std::size_t t = 0; t < after.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const Vec3f p = after.positions[after.triangles[t][k]];
            const Vec3f q = before.positions[before.triangles[t][k]];
            ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << "triangle " << t;
        }
    for (const auto& uv : after.uvs)
        for (float x : uv) ASSERT_TRUE(x >= 0.0f && x <= 1.0f) << x;
    // No overlapping texels: the rasteriser refuses a texel centre strictly inside two triangles.
    const int side = info.resolution;
    EXPECT_NO_THROW(rasterize_texels(after, side, side));
    EXPECT_TRUE(find_uv_overlaps(after, side, side).empty());
    // Stretch: reported, within the bound, and uniform scale: each triangle's UV area is its
    // surface area at `texels_per_metre`, within the stretch.
    EXPECT_GE(info.max_stretch, 1.0);
    EXPECT_LE(info.max_stretch, options.max_stretch);
    EXPECT_GE(info.mean_stretch, 1.0);
    EXPECT_LE(info.mean_stretch, info.max_stretch);
    const double s = info.texels_per_metre / side;  // UV units per metre
    const double bound = options.max_stretch * options.max_stretch * 1.0001;
    std::size_t without_area = 0;
    for (const auto& t : after.triangles) {
        const double world = world_area(after, t);
        double longest = 0;  // the atlas's test for "no area": |n| ≤ 1e-9 · longest edge²
        for (int k = 0; k < 3; ++k) {
            const Vec3d d =
                cast<double>(after.positions[t[(k + 1) % 3]]) - cast<double>(after.positions[t[k]]);
            longest = std::max(longest, dot(d, d));
        }
        if (!(2 * world > 1e-9 * longest)) {
            ++without_area;
            continue;
        }
        const double ratio = 0.5 * uv_area2(after, t) / (world * s * s);
        ASSERT_GT(ratio, 1 / bound);
        ASSERT_LT(ratio, bound);
    }
    EXPECT_EQ(without_area, info.degenerate_triangles);
    EXPECT_GT(info.chart_share, 0.15);  // 180 charts, 4-texel gutters at 256²: 19 %
    EXPECT_LE(info.chart_share, 1.0);
}

TEST(Unwrap, AMessyMeshGetsAnAtlasWithoutOverlaps) {
    const Mesh before = messy_mesh();
    Mesh mesh = before;
    const UvAtlasOptions options = unwrap_options(256);
    const UvAtlasInfo info = make_uv_atlas(mesh, options);
    expect_sound_atlas(before, mesh, info, options);
    EXPECT_EQ(info.degenerate_triangles, 1u);
    EXPECT_EQ(info.resolution, 256);
    EXPECT_LE(info.mean_stretch, 1.1);
    // Deterministic.
    Mesh again = before;
    make_uv_atlas(again, options);
    EXPECT_EQ(again.uvs, mesh.uvs);
    EXPECT_EQ(again.triangles, mesh.triangles);
}

TEST(Unwrap, SplitVerticesAreWeldedForCharts) {
    // A flat panel stored with three vertices per triangle is one chart, not 72.
    Mesh mesh;
    add_panel(mesh, 6, 1.0f, {0, 0, 0}, true);
    const UvAtlasOptions options = unwrap_options(64);
    const UvAtlasInfo info = make_uv_atlas(mesh, options);
    EXPECT_EQ(info.charts, 1u);
    EXPECT_EQ(info.added_vertices, 0u);
    EXPECT_NO_THROW(rasterize_texels(mesh, 64, 64));
}

TEST(Unwrap, TexelDensityChoosesTheResolution) {
    const Mesh before = messy_mesh();
    Mesh mesh = before;
    UvAtlasOptions options = unwrap_options(0);
    options.texels_per_metre = 40;
    const UvAtlasInfo info = make_uv_atlas(mesh, options);
    EXPECT_EQ(info.texels_per_metre, 40.0);
    EXPECT_GT(info.resolution, 64);
    EXPECT_LT(info.resolution, 1024);
    expect_sound_atlas(before, mesh, info, options);
    // Twice the density: about twice the side (the gutters are texels, so not exactly).
    Mesh finer = before;
    options.texels_per_metre = 80;
    const UvAtlasInfo twice = make_uv_atlas(finer, options);
    EXPECT_NEAR(double(twice.resolution) / info.resolution, 2.0, 0.15);
    // Too dense for the largest image: refused, with the density that fits.
    options.texels_per_metre = 1e5;
    Mesh dense = before;
    try {
        make_uv_atlas(dense, options);
        ADD_FAILURE() << "no error for 1e5 texels per metre";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("texels per metre at most"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("messy"), std::string::npos) << e.what();
    }
}

TEST(Unwrap, GuttersAreDilatedFromTheirOwnChart) {
    Mesh mesh = messy_mesh();
    const UvAtlasOptions options = unwrap_options(256);
    const UvAtlasInfo info = make_uv_atlas(mesh, options);
    const TexelSamples texels = rasterize_texels(mesh, 256, 256);
    TexelAtlas atlas;
    atlas.width = atlas.height = 256;
    atlas.texel = texels.texel;
    const std::vector<std::int64_t> source = dilate_texels(atlas, int(options.gutter_texels));
    // Bilinear filtering inside a chart reads the 8 neighbours of its texels: each is filled, and
    // from the same chart (a seam's gutter is dilated, and never from a neighbouring chart).
    std::vector<bool> covered(256 * 256, false);
    for (std::uint32_t i : texels.texel) covered[i] = true;
    std::size_t filled = 0;
    for (std::size_t r = 0; r < texels.count(); ++r) {
        const int x = int(texels.texel[r] % 256), y = int(texels.texel[r] / 256);
        const std::uint32_t chart = info.chart[texels.triangle[r]];
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= 256 || ny >= 256) continue;
                const std::int64_t s = source[std::size_t(ny) * 256 + std::size_t(nx)];
                ASSERT_GE(s, 0) << "texel (" << nx << ", " << ny << ") is empty";
                ASSERT_EQ(info.chart[texels.triangle[std::size_t(s)]], chart)
                    << "texel (" << nx << ", " << ny << ") takes another chart's value";
                filled += !covered[std::size_t(ny) * 256 + std::size_t(nx)];
            }
    }
    EXPECT_GT(filled, 0u);
}

TEST(Unwrap, BadInputIsRefused) {
    UvAtlasOptions options = unwrap_options(256);
    Mesh empty;
    empty.source = "empty.obj";
    EXPECT_THROW(make_uv_atlas(empty, options), Error);
    Mesh nan = messy_mesh();
    nan.positions[3].y = std::nanf("");
    EXPECT_THROW(make_uv_atlas(nan, options), Error);
    Mesh bad_index = messy_mesh();
    bad_index.triangles[0][1] = std::uint32_t(bad_index.vertex_count());
    EXPECT_THROW(make_uv_atlas(bad_index, options), Error);
    Mesh fine = messy_mesh();
    options.max_stretch = 1;
    EXPECT_THROW(make_uv_atlas(fine, options), Error);
}

// Meshes of Assimp's corpus: a character (Wuson, OFF), an STL sphere with a hole (every triangle
// with its own vertices), the Collada duck, the OBJ spider (many small parts).
class UnwrapCorpus : public ::testing::TestWithParam<const char*> {};

TEST_P(UnwrapCorpus, HasAnAtlasWithoutOverlaps) {
    const std::string path = std::string("/usr/share/assimp/models/") + GetParam();
    if (!std::filesystem::exists(path))
        GTEST_SKIP() << path << " is missing (scripts/setup installs assimp-testmodels)";
    const Mesh before = load_scene(path);
    Mesh mesh = before;
    const UvAtlasOptions options = unwrap_options(256);
    const UvAtlasInfo info = make_uv_atlas(mesh, options);
    expect_sound_atlas(before, mesh, info, options);
    EXPECT_LE(info.mean_stretch, 1.25) << describe(info);
    std::printf("%s: %s\n", GetParam(), describe(info).c_str());
}

INSTANTIATE_TEST_SUITE_P(Assimp, UnwrapCorpus,
                         ::testing::Values("OFF/Wuson.off", "STL/sphereWithHole.stl",
                                           "Collada/duck.dae", "OBJ/spider.obj"),
                         [](const ::testing::TestParamInfo<const char*>& param) {
                             std::string name = param.param;
                             name = name.substr(name.find('/') + 1);
                             name = name.substr(0, name.find('.'));
                             return name;
                         });

}  // namespace
}  // namespace shprt
