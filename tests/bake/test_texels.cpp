// Per-texel transfer (bake/texels.hpp): on a two-triangle floor with a box on it, the texel
// bake's irradiance at texel centres matches the direct ground truth (bake/ground_truth.hpp) and
// shows the box's shadow; the vertex bake, interpolated to the same points, cannot.
#include "bake/linear_light.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/ground_truth.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/scene/builtin.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace shprt {
namespace {

using test::linear_light_coeffs;
using test::linear_light_truth;

double irradiance(const float* row, const std::vector<double>& light) {
    double e = 0;
    for (std::size_t i = 0; i < light.size(); ++i) e += double(row[i]) * light[i];
    return e;
}

// Barycentric interpolation of per-vertex values over triangle t of `mesh` at point p (on it).
double interpolate(const Mesh& mesh, std::uint32_t t, Vec3f p, const std::vector<double>& value) {
    const auto& tri = mesh.triangles[t];
    const Vec3d a = cast<double>(mesh.positions[tri[0]]), b = cast<double>(mesh.positions[tri[1]]),
                c = cast<double>(mesh.positions[tri[2]]), q = cast<double>(p);
    const Vec3d n = cross(b - a, c - a);
    const double area = dot(n, n);
    const double la = dot(cross(c - b, q - b), n) / area, lb = dot(cross(a - c, q - c), n) / area;
    return la * value[tri[0]] + lb * value[tri[1]] + (1 - la - lb) * value[tri[2]];
}

TEST(TexelBake, FloorShowsTheBoxShadowLikeTheGroundTruthAndVerticesCannot) {
    const Mesh mesh = make_builtin("quad_box");
    const TexelSamples texels = rasterize_texels(mesh, 48, 48);
    BakeOptions options;
    options.K = 16;
    options.samples = 1024;
    options.threads = 2;
    HostSink sink;
    const TransferInfo info =
        bake(BakeJob{&mesh, texel_receivers(texels), &sink, nullptr, nullptr, nullptr}, options);
    EXPECT_EQ(info.layout.domain, ReceiverDomain::texel);
    ASSERT_EQ(sink.rows().size(), texels.count() * 16);
    const TransferSet vertices = bake(mesh, options);

    // Ground truth at the texel centres: the texels as extra (unconnected) vertices of the mesh.
    Mesh probes = mesh;
    probes.positions.insert(probes.positions.end(), texels.positions.begin(),
                            texels.positions.end());
    probes.normals.insert(probes.normals.end(), texels.normals.begin(), texels.normals.end());
    probes.albedo.insert(probes.albedo.end(), texels.albedo.begin(), texels.albedo.end());
    probes.uvs.clear();
    const GroundTruth truth = linear_light_truth(probes, 2048);

    const std::vector<double> L = linear_light_coeffs(16);
    std::vector<double> vertex_e(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        vertex_e[v] = irradiance(vertices.receiver(v), L);
    double lo = 1e30, hi = 0, texel_err = 0, vertex_err = 0, vlo = 1e30, vhi = 0;
    std::size_t floor = 0;
    for (std::size_t r = 0; r < texels.count(); ++r) {
        if (texels.triangle[r] >= 2) continue;  // the floor only
        ++floor;
        const double gt = truth.irradiance[mesh.vertex_count() + r].x;
        const double e = irradiance(sink.rows().data() + 16 * r, L);
        const double ev = interpolate(mesh, texels.triangle[r], texels.positions[r], vertex_e);
        lo = std::min(lo, gt), hi = std::max(hi, gt);
        vlo = std::min(vlo, ev), vhi = std::max(vhi, ev);
        texel_err = std::max(texel_err, std::abs(e - gt));
        vertex_err = std::max(vertex_err, std::abs(ev - gt));
    }
    ASSERT_GT(floor, 1000u);
    // The shadow is there (the ground truth's darkest floor texel is under half its brightest)…
    EXPECT_LT(lo, 0.5 * hi);
    // …the texels see it, within sampling error…
    EXPECT_LT(texel_err, 0.03 * hi);
    // …and the four floor vertices cannot: they are all far from the box.
    EXPECT_GT(vlo, 0.9 * vhi);
    EXPECT_GT(vertex_err, 0.4 * hi);
}

TEST(TexelBake, MemoryEstimateGrowsWithTexelsAndK) {
    TransferLayout layout;
    layout.K = 16;
    const std::uint64_t small = texel_bake_bytes(1000, 64, 64, layout, 1024, 2);
    const std::uint64_t big = texel_bake_bytes(1000000, 1024, 1024, layout, 1024, 2);
    EXPECT_GE(big - small, std::uint64_t(999000) * 16 * 4);  // at least the coefficients
    layout.K = 64;
    EXPECT_GT(texel_bake_bytes(1000000, 1024, 1024, layout, 1024, 2), big);
}

TEST(TexelBake, DilationFillsTheGutterFromTheNearestChart) {
    TexelAtlas atlas;
    atlas.width = 6;
    atlas.height = 1;
    atlas.texel = {1, 2};  // texels 1 and 2 covered
    const std::vector<std::int64_t> d1 = dilate_texels(atlas, 1);
    EXPECT_EQ(d1, (std::vector<std::int64_t>{0, 0, 1, 1, -1, -1}));
    const std::vector<std::int64_t> d2 = dilate_texels(atlas, 2);
    EXPECT_EQ(d2, (std::vector<std::int64_t>{0, 0, 1, 1, 1, -1}));
}

}  // namespace
}  // namespace shprt
