// Adaptive refinement (bake/refine.hpp): the splits keep the mesh conforming and the input's
// vertex indices; refinement on a shadow edge lowers the error of the interpolated irradiance
// against the direct ground truth; the budget stops it.
#include "bake/linear_light.hpp"
#include "shprt/bake/ground_truth.hpp"
#include "shprt/bake/refine.hpp"
#include "shprt/core/error.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace shprt {
namespace {

// A coarse floor (1 m cells over [-2, 2]²) with a 1 m box on it: few vertices near the shadow.
Mesh coarse_box_scene() {
    MeshBuilder b;
    const Vec3f grey{0.8f, 0.8f, 0.8f};
    b.add_rect(Axis::y, 0.0, +1, {-2, 2, -2, 2}, 1.0, grey);
    b.add_box({-0.5, 0.0, -0.5}, {0.5, 1.0, 0.5}, 1.0, grey, kBoxNoBottom);
    return b.take_mesh("test:coarse_box");
}

// Every edge is used by at most two triangles, no vertex lies inside another triangle's edge
// (a T-junction), and the area is the input's.
void expect_conforming(const Mesh& mesh, double area) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    for (const auto& [edge, n] : uses) {
        EXPECT_LE(n, 2) << edge.first << "-" << edge.second;
        const Vec3d a = cast<double>(mesh.positions[edge.first]);
        const Vec3d b = cast<double>(mesh.positions[edge.second]);
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            if (v == edge.first || v == edge.second) continue;
            const Vec3d p = cast<double>(mesh.positions[v]);
            const Vec3d ab = b - a;
            const double t = dot(p - a, ab) / dot(ab, ab);
            if (t <= 1e-6 || t >= 1 - 1e-6) continue;
            const Vec3d off = p - (a + ab * t);
            // A vertex on the open edge with the same normal would be a T-junction (the box's
            // own vertices on the floor's lines have other normals and are not connected).
            if (length(off) < 1e-6 && dot(mesh.normals[v], mesh.normals[edge.first]) > 0.99f)
                ADD_FAILURE() << "T-junction: vertex " << v << " on edge " << edge.first << "-"
                              << edge.second;
        }
    }
    EXPECT_NEAR(mesh_surface_area(mesh), area, 1e-4 * area);
}

TEST(Refine, SplitsStayConformingAndKeepIndices) {
    Mesh input = coarse_box_scene();
    input.brdfs = {Brdf{BrdfModel::phong, 8}, Brdf{BrdfModel::ggx, 0.5}};
    for (std::size_t v = 0; v < input.vertex_count(); ++v)
        input.brdf_index.push_back(v % 3 == 2 ? Mesh::kNoBrdf : std::uint32_t(v % 3));
    const double area = mesh_surface_area(input);
    Mesh mesh = input;
    for (int round = 0; round < 4; ++round) {
        // A scattered, deterministic choice of edges: some triangles get one, two or three.
        std::vector<std::array<std::uint32_t, 2>> edges;
        for (const auto& t : mesh.triangles)
            for (int k = 0; k < 3; ++k)
                if ((t[k] * 7 + t[(k + 1) % 3] * 3 + round) % 4 == 0)
                    edges.push_back({t[k], t[(k + 1) % 3]});
        const std::size_t before = mesh.vertex_count();
        const std::size_t added = split_edges(mesh, edges);
        EXPECT_GT(added, 0u);
        EXPECT_EQ(mesh.vertex_count(), before + added);
        expect_conforming(mesh, area);
    }
    for (std::size_t v = 0; v < input.vertex_count(); ++v) {
        EXPECT_EQ(mesh.positions[v], input.positions[v]);
        EXPECT_EQ(mesh.parents[v][0], Mesh::kNoParent);
    }
    for (std::size_t v = input.vertex_count(); v < mesh.vertex_count(); ++v) {
        const auto [a, b] = mesh.parents[v];
        ASSERT_LT(a, v);
        ASSERT_LT(b, v);
        const Vec3f mid = (mesh.positions[a] + mesh.positions[b]) * 0.5f;
        EXPECT_EQ(mesh.positions[v], mid);
        EXPECT_EQ(mesh.brdf_index[v], mesh.brdf_index[a]);  // the material of its edge's first end
    }
    EXPECT_EQ(mesh.brdf_index.size(), mesh.vertex_count());
    EXPECT_THROW(split_edges(mesh, {{0, std::uint32_t(mesh.vertex_count() - 1)}}), Error);
}

// Irradiance interpolated over the +Y floor triangles of `mesh` at (x, 0, z).
double floor_value(const Mesh& mesh, const std::vector<double>& e, double x, double z) {
    for (const auto& t : mesh.triangles) {
        const Vec3f a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
        if (a.y != 0 || b.y != 0 || c.y != 0 || mesh.normals[t[0]].y < 0.5f) continue;
        const double det = (b.x - a.x) * (c.z - a.z) - (c.x - a.x) * (b.z - a.z);
        const double lb = ((x - a.x) * (c.z - a.z) - (c.x - a.x) * (z - a.z)) / det;
        const double lc = ((b.x - a.x) * (z - a.z) - (x - a.x) * (b.z - a.z)) / det;
        const double la = 1 - lb - lc;
        if (la < -1e-9 || lb < -1e-9 || lc < -1e-9) continue;
        return la * e[t[0]] + lb * e[t[1]] + lc * e[t[2]];
    }
    ADD_FAILURE() << "no floor triangle at " << x << ", " << z;
    return 0;
}

std::vector<double> vertex_irradiance(const TransferSet& t) {
    const std::vector<double> L = test::linear_light_coeffs(t.layout.K);
    std::vector<double> e(t.receiver_count());
    for (std::size_t v = 0; v < e.size(); ++v)
        for (int i = 0; i < t.layout.K; ++i) e[v] += double(t.receiver(v)[i]) * L[i];
    return e;
}

TEST(Refine, RefinementOnAShadowEdgeLowersTheErrorAgainstTheGroundTruth) {
    const Mesh input = coarse_box_scene();
    BakeOptions options;
    options.K = 16;
    options.samples = 512;
    options.threads = 2;
    RefineOptions refine;
    refine.tolerance = 0.03;
    refine.max_depth = 4;
    const RefineResult r = bake_refined(input, options, refine);
    EXPECT_GT(r.mesh.vertex_count(), input.vertex_count());
    EXPECT_EQ(r.transfer.receiver_count(), r.mesh.vertex_count());
    EXPECT_GE(r.passes, 1);
    expect_conforming(r.mesh, mesh_surface_area(input));
    const TransferSet coarse = bake(input, options);
    // Input rows are the plain bake's: the same vertices, options and seed.
    for (std::size_t i = 0; i < coarse.coeffs.size(); ++i)
        ASSERT_EQ(coarse.coeffs[i], r.transfer.coeffs[i]);

    // Probes on the floor around the box, ground truth there.
    Mesh probes = input;
    std::vector<std::pair<double, double>> xz;
    for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 24; ++j) {
            const double x = -1.9 + 3.8 * (i + 0.5) / 24, z = -1.9 + 3.8 * (j + 0.5) / 24;
            if (std::abs(x) < 0.55 && std::abs(z) < 0.55) continue;  // under the box
            xz.push_back({x, z});
            probes.positions.push_back({float(x), 0.0f, float(z)});
            probes.normals.push_back({0, 1, 0});
            probes.albedo.push_back({0.8f, 0.8f, 0.8f});
        }
    const GroundTruth truth = test::linear_light_truth(probes, 1024);
    const std::vector<double> e_coarse = vertex_irradiance(coarse),
                              e_fine = vertex_irradiance(r.transfer);
    double err_coarse = 0, err_fine = 0;
    for (std::size_t p = 0; p < xz.size(); ++p) {
        const double gt = truth.irradiance[input.vertex_count() + p].x;
        err_coarse += std::pow(floor_value(input, e_coarse, xz[p].first, xz[p].second) - gt, 2);
        err_fine += std::pow(floor_value(r.mesh, e_fine, xz[p].first, xz[p].second) - gt, 2);
    }
    err_coarse = std::sqrt(err_coarse / double(xz.size()));
    err_fine = std::sqrt(err_fine / double(xz.size()));
    EXPECT_LT(err_fine, 0.5 * err_coarse) << "coarse " << err_coarse << ", refined " << err_fine;
}

TEST(Refine, TheVertexBudgetStopsIt) {
    const Mesh input = coarse_box_scene();
    BakeOptions options;
    options.K = 9;
    options.samples = 256;
    RefineOptions refine;
    refine.tolerance = 0.001;
    refine.max_vertices = input.vertex_count() + 10;
    const RefineResult r = bake_refined(input, options, refine);
    EXPECT_TRUE(r.budget_reached);
    EXPECT_EQ(r.mesh.vertex_count(), refine.max_vertices);
    EXPECT_GT(r.edges_over, 0u);
    refine.max_vertices = input.vertex_count() - 1;
    EXPECT_THROW(bake_refined(input, options, refine), Error);
    refine = {};
    refine.tolerance = 0;
    EXPECT_THROW(bake_refined(input, options, refine), Error);
}

// With the budget binding, the first pass splits the edges with the largest difference × length
// (refine.hpp): its parents are exactly the top edges of that order, computed here from the input
// bake (bake_refined's first pass bakes the same vertices with the same options).
TEST(Refine, ABindingBudgetSplitsTheLargestDifferenceTimesLengthFirst) {
    // Long floor edges (2 m cells) around a finely cut box (0.25 m cells): the two orders differ.
    MeshBuilder b;
    const Vec3f grey{0.8f, 0.8f, 0.8f};
    b.add_rect(Axis::y, 0.0, +1, {-2, 2, -2, 2}, 2.0, grey);
    b.add_box({0.4, 0.0, 0.4}, {1.2, 0.8, 1.2}, 0.25, grey, kBoxNoBottom);
    const Mesh input = b.take_mesh("test:long_and_short_edges");
    BakeOptions options;
    options.K = 9;
    options.samples = 256;
    const TransferSet t = bake(input, options);
    const auto lights = refine_test_lights(options.K);
    std::map<std::pair<std::uint32_t, std::uint32_t>, double> priority;
    for (const auto& tri : input.triangles)
        for (int k = 0; k < 3; ++k) {
            const auto e = std::minmax(tri[k], tri[(k + 1) % 3]);
            const double d =
                transfer_difference(t.receiver(e.first), t.receiver(e.second), options.K, lights);
            const double len = length(cast<double>(input.positions[e.first]) -
                                      cast<double>(input.positions[e.second]));
            priority[e] = d * len;
        }
    std::vector<double> sorted;
    for (const auto& [e, p] : priority) sorted.push_back(p);
    std::sort(sorted.rbegin(), sorted.rend());
    RefineOptions refine;
    refine.tolerance = 0.001;
    refine.max_vertices = input.vertex_count() + 8;  // the first pass takes half: 4 edges
    const RefineResult r = bake_refined(input, options, refine);
    ASSERT_GE(r.mesh.vertex_count(), input.vertex_count() + 4);
    for (std::size_t v = input.vertex_count(); v < input.vertex_count() + 4; ++v) {
        const auto e = std::minmax(r.mesh.parents[v][0], r.mesh.parents[v][1]);
        ASSERT_TRUE(priority.count(e));
        EXPECT_GE(priority[e], sorted[3]) << "vertex " << v;
    }
    EXPECT_GT(sorted[3], sorted[8]);  // the order separates the first four from the rest
}

}  // namespace
}  // namespace shprt
