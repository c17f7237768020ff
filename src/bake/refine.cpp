// Adaptive refinement of per-vertex transfer (refine.hpp): edge-difference marking under fixed
// test lights, conforming 1-to-2 / 1-to-3 / 1-to-4 splits (Bank, Sherman & Weiser's red
// refinement, with the irregular cases closed by bisection instead of green closure), and bakes
// of the new vertices only on the receivers seam.
#include "shprt/bake/refine.hpp"

#include "shprt/bake/session.hpp"

#include "shprt/core/error.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

namespace shprt {
namespace {

using Edge = std::array<std::uint32_t, 2>;

Edge edge_key(std::uint32_t a, std::uint32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

constexpr double kTwoPiOverThree = 2.0943951023931954923;  // ∫ max(0, cos θ)² dω

}  // namespace

std::vector<std::vector<float>> refine_test_lights(int K) {
    const std::vector<double> zonal = clamped_cosine_zonal(sh_bands_for(K));
    std::vector<std::vector<float>> lights;
    const double s = 1.0 / std::sqrt(3.0);
    const Vec3d dirs[14] = {{1, 0, 0},  {-1, 0, 0},  {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                            {0, 0, -1}, {s, s, s},   {s, s, -s},  {s, -s, s},  {s, -s, -s},
                            {-s, s, s}, {-s, s, -s}, {-s, -s, s}, {-s, -s, -s}};
    for (const Vec3d& d : dirs) {
        std::vector<double> c(std::size_t(K), 0.0);
        rotate_zonal(zonal.data(), K, d, c.data());
        lights.emplace_back(c.begin(), c.end());
    }
    return lights;
}

double transfer_difference(const float* a, const float* b, int K,
                           const std::vector<std::vector<float>>& lights) {
    double worst = 0;
    for (const auto& l : lights) {
        double e = 0;
        for (int i = 0; i < K; ++i) e += (double(a[i]) - double(b[i])) * double(l[i]);
        worst = std::max(worst, std::abs(e));
    }
    return worst / kTwoPiOverThree;
}

std::size_t split_edges(Mesh& mesh, std::vector<Edge> edges,
                        std::vector<std::uint32_t>* triangle_origin) {
    SHPRT_CHECK(!triangle_origin || triangle_origin->size() == mesh.triangle_count(),
                invalid_argument, "split_edges: {} triangle origins for {} triangles",
                triangle_origin ? triangle_origin->size() : 0, mesh.triangle_count());
    std::vector<std::uint32_t> origin_out;
    for (Edge& e : edges) e = edge_key(e[0], e[1]);
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    const std::size_t V = mesh.vertex_count();
    if (mesh.parents.empty()) mesh.parents.assign(V, {Mesh::kNoParent, Mesh::kNoParent});
    // Which edges exist (to reject pairs that are not edges).
    std::map<Edge, std::uint32_t> midpoint;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k)
            midpoint.emplace(edge_key(t[k], t[(k + 1) % 3]), Mesh::kNoParent);
    for (const Edge& e : edges) {
        const auto it = midpoint.find(e);
        SHPRT_CHECK(it != midpoint.end(), invalid_argument,
                    "split_edges: ({}, {}) is not an edge of the mesh", e[0], e[1]);
        const auto m = static_cast<std::uint32_t>(mesh.positions.size());
        it->second = m;
        const auto mid = [](Vec3f p, Vec3f q) { return (p + q) * 0.5f; };
        mesh.positions.push_back(mid(mesh.positions[e[0]], mesh.positions[e[1]]));
        Vec3f n = mesh.normals[e[0]] + mesh.normals[e[1]];
        n = length(n) > 0 ? normalize(n) : mesh.normals[e[0]];
        mesh.normals.push_back(n);
        if (!mesh.albedo.empty()) mesh.albedo.push_back(mid(mesh.albedo[e[0]], mesh.albedo[e[1]]));
        if (!mesh.uvs.empty()) {
            const auto& p = mesh.uvs[e[0]];
            const auto& q = mesh.uvs[e[1]];
            mesh.uvs.push_back({(p[0] + q[0]) * 0.5f, (p[1] + q[1]) * 0.5f});
        }
        if (!mesh.source_vertex.empty()) mesh.source_vertex.push_back(Mesh::kNoParent);
        // The two ends of an edge share a material (the loader never joins vertices across
        // materials): the first end's BRDF.
        if (!mesh.brdf_index.empty()) mesh.brdf_index.push_back(mesh.brdf_index[e[0]]);
        mesh.parents.push_back(e);
    }
    const auto dist2 = [&](std::uint32_t a, std::uint32_t b) {
        const Vec3f d = mesh.positions[a] - mesh.positions[b];
        return dot(d, d);
    };
    std::vector<std::array<std::uint32_t, 3>> out;
    out.reserve(mesh.triangles.size() + 3 * edges.size());
    for (std::size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
        const auto& t = mesh.triangles[ti];
        const std::size_t first_child = out.size();
        std::uint32_t m[3];  // midpoint of edge (t[k], t[k+1]), or kNoParent
        int split = 0;
        for (int k = 0; k < 3; ++k) {
            m[k] = midpoint.at(edge_key(t[k], t[(k + 1) % 3]));
            split += m[k] != Mesh::kNoParent;
        }
        if (split == 0) {
            out.push_back(t);
        } else if (split == 3) {
            out.push_back({t[0], m[0], m[2]});
            out.push_back({m[0], t[1], m[1]});
            out.push_back({m[2], m[1], t[2]});
            out.push_back({m[0], m[1], m[2]});
        } else if (split == 1) {
            int k = 0;
            while (m[k] == Mesh::kNoParent) ++k;
            const std::uint32_t a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
            out.push_back({a, m[k], c});
            out.push_back({m[k], b, c});
        } else {  // two edges: k is the unsplit one, (a, b) = its ends, c the opposite corner
            int k = 0;
            while (m[k] != Mesh::kNoParent) ++k;
            const std::uint32_t a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
            const std::uint32_t mbc = m[(k + 1) % 3], mca = m[(k + 2) % 3];
            out.push_back({mca, mbc, c});
            // The quad (a, b, mbc, mca), cut along its shorter diagonal.
            if (dist2(a, mbc) <= dist2(b, mca)) {
                out.push_back({a, b, mbc});
                out.push_back({a, mbc, mca});
            } else {
                out.push_back({a, b, mca});
                out.push_back({b, mbc, mca});
            }
        }
        if (triangle_origin)
            origin_out.insert(origin_out.end(), out.size() - first_child, (*triangle_origin)[ti]);
    }
    mesh.triangles = std::move(out);
    if (triangle_origin) *triangle_origin = std::move(origin_out);
    return edges.size();
}

RefineResult bake_refined(const Mesh& input, const BakeOptions& options,
                          const RefineOptions& refine) {
    SHPRT_CHECK(refine.tolerance > 0 && std::isfinite(refine.tolerance), invalid_argument,
                "--refine {}: the tolerance must be a positive fraction", refine.tolerance);
    SHPRT_CHECK(refine.max_depth >= 1 && refine.max_depth <= 30, invalid_argument,
                "--max-edge-split-depth {}: must be 1 to 30", refine.max_depth);
    SHPRT_CHECK(!kind_row(options.transfer).whole_domain, unsupported,
                "refinement of {} transfer is not supported (bake shadowed or unshadowed "
                "transfer)",
                to_string(options.transfer));
    validate(options);
    const std::size_t V0 = input.vertex_count();
    const std::size_t budget =
        refine.max_vertices > 0 ? refine.max_vertices : std::max<std::size_t>(16 * V0, V0);
    SHPRT_CHECK(budget >= V0, invalid_argument,
                "--max-vertices {}: fewer than the scene's {} vertices", budget, V0);

    RefineResult r;
    r.input_vertices = V0;
    r.mesh = input;
    Mesh& mesh = r.mesh;
    mesh.parents.assign(V0, {Mesh::kNoParent, Mesh::kNoParent});
    std::vector<int> depth(V0, 0);
    r.triangle_origin.resize(input.triangle_count());
    for (std::size_t t = 0; t < r.triangle_origin.size(); ++t)
        r.triangle_origin[t] = static_cast<std::uint32_t>(t);

    // The occluders never change (new vertices lie on the input's triangles): one bake session,
    // one BVH and one set of tables for every pass.
    std::unique_ptr<Tracer> tracer;
    if (resolve_device(options.device, options.device_index) == Device::cpu)
        tracer = make_embree_tracer(input);
    BakeSession session(BakeJob{&input, vertex_receivers(input), nullptr, nullptr, tracer.get()},
                        options);
    const auto bake_range = [&](std::size_t first, std::size_t count) {
        HostSink sink;
        Receivers rx = vertex_receivers(mesh).range(first, count);
        const TransferInfo info = session.bake(BakeJob{nullptr, rx, &sink, nullptr, nullptr});
        if (first == 0) {
            static_cast<TransferInfo&>(r.transfer) = info;
        } else {
            add_stats(r.transfer.stats, info.stats);
        }
        const std::vector<float>& rows = sink.rows();
        r.transfer.coeffs.insert(r.transfer.coeffs.end(), rows.begin(), rows.end());
    };
    bake_range(0, V0);

    const int K = r.transfer.layout.K;
    const auto lights = refine_test_lights(K);
    for (;;) {
        // Every edge once, in index order, with its difference.
        std::vector<Edge> all;
        all.reserve(mesh.triangles.size() * 3);
        for (const auto& t : mesh.triangles)
            for (int k = 0; k < 3; ++k) all.push_back(edge_key(t[k], t[(k + 1) % 3]));
        std::sort(all.begin(), all.end());
        all.erase(std::unique(all.begin(), all.end()), all.end());
        std::vector<std::pair<double, Edge>> over;
        r.largest_difference = 0;
        r.depth_reached = false;
        std::size_t blocked = 0;  // over the tolerance but too deep to split
        for (const Edge& e : all) {
            const double d = transfer_difference(r.transfer.receiver(e[0]),
                                                 r.transfer.receiver(e[1]), K, lights);
            r.largest_difference = std::max(r.largest_difference, d);
            if (d <= refine.tolerance) continue;
            if (std::max(depth[e[0]], depth[e[1]]) + 1 > refine.max_depth) {
                r.depth_reached = true;
                ++blocked;
                continue;
            }
            // Priority when the budget binds: the difference times the edge's length. The error
            // linear interpolation leaves beside an edge spreads over triangles as wide as the
            // edge is long, so a long edge with a moderate step costs more picture than a short
            // one with a large step (a contact line, which no split makes smooth).
            const double len =
                length(cast<double>(mesh.positions[e[0]]) - cast<double>(mesh.positions[e[1]]));
            over.push_back({d * len, e});
        }
        r.edges_over = over.size() + blocked;
        if (over.empty()) break;
        const std::size_t room = budget - mesh.vertex_count();
        if (room == 0) {
            r.budget_reached = true;
            break;
        }
        if (over.size() > room) {
            // Not every edge fits: the largest priorities first, and only half of what is
            // left per pass, so that later passes can split the worst places again (deeper)
            // instead of spending the whole budget one level deep.
            std::stable_sort(over.begin(), over.end(),
                             [](const auto& a, const auto& b) { return a.first > b.first; });
            over.resize(std::max<std::size_t>(1, room / 2));
        }
        if (over.empty()) break;
        std::vector<Edge> edges;
        for (const auto& o : over) edges.push_back(o.second);
        const std::size_t first = mesh.vertex_count();
        const std::size_t added = split_edges(mesh, edges, &r.triangle_origin);
        for (std::size_t v = first; v < first + added; ++v)
            depth.push_back(std::max(depth[mesh.parents[v][0]], depth[mesh.parents[v][1]]) + 1);
        bake_range(first, added);
        ++r.passes;
    }
    return r;
}

}  // namespace shprt
