// UV atlas of a mesh without one (scene/uv_atlas.hpp): normal-cone charts, orthographic
// projection, shelf packing.
#include "shprt/scene/uv_atlas.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace shprt {
namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(a) << 32) | b;
}

struct ChartBox {
    double lo_u = 1e300, lo_v = 1e300, hi_u = -1e300, hi_v = -1e300;
    double x = 0, y = 0;  // packed position of (lo_u, lo_v), metres
    double width() const { return hi_u - lo_u; }
    double height() const { return hi_v - lo_v; }
};

// Shelf packing of `boxes` (order: tallest first) into a square of side `side` metres with `gap`
// metres between boxes and gap/2 to the border; returns the height used.
double pack(std::vector<ChartBox>& boxes, const std::vector<std::size_t>& order, double side,
            double gap) {
    double x = gap / 2, y = gap / 2, shelf = 0;
    for (std::size_t i : order) {
        ChartBox& b = boxes[i];
        if (x > gap / 2 && x + b.width() + gap / 2 > side) {
            y += shelf + gap;
            x = gap / 2;
            shelf = 0;
        }
        b.x = x, b.y = y;
        x += b.width() + gap;
        shelf = std::max(shelf, b.height());
    }
    return y + shelf + gap / 2;
}

}  // namespace

UvAtlasInfo make_uv_atlas(Mesh& mesh, const UvAtlasOptions& options) {
    const std::size_t V = mesh.vertex_count(), T = mesh.triangle_count();
    SHPRT_CHECK(T > 0, invalid_argument, "{}: no triangles to lay out in UV space", mesh.source);
    SHPRT_CHECK(options.resolution >= 1 && options.gutter_texels >= 0 &&
                    options.max_angle_deg > 0 && options.max_angle_deg < 90,
                invalid_argument, "UV atlas: resolution {}, gutter {}, angle {} out of range",
                options.resolution, options.gutter_texels, options.max_angle_deg);
    for (const auto& t : mesh.triangles)
        SHPRT_CHECK(t[0] < V && t[1] < V && t[2] < V, invalid_argument,
                    "{}: triangle index out of range ({} vertices)", mesh.source, V);

    // Face normals, and the triangles around each edge.
    std::vector<Vec3d> normal(T);
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> around;
    for (std::size_t t = 0; t < T; ++t) {
        const auto& tri = mesh.triangles[t];
        const Vec3d a = cast<double>(mesh.positions[tri[0]]);
        const Vec3d n = cross(cast<double>(mesh.positions[tri[1]]) - a,
                              cast<double>(mesh.positions[tri[2]]) - a);
        normal[t] = length(n) > 0 ? normalize(n) : Vec3d{0, 1, 0};
        for (int k = 0; k < 3; ++k)
            around[edge_key(tri[k], tri[(k + 1) % 3])].push_back(std::uint32_t(t));
    }

    // Charts: breadth-first growth within the normal cone of the seed.
    UvAtlasInfo info;
    info.chart.assign(T, kNone);
    std::vector<Vec3d> axis;
    const double min_cos = std::cos(options.max_angle_deg * kPi / 180.0);
    std::vector<std::uint32_t> queue;
    for (std::size_t seed = 0; seed < T; ++seed) {
        if (info.chart[seed] != kNone) continue;
        const auto c = std::uint32_t(axis.size());
        axis.push_back(normal[seed]);
        info.chart[seed] = c;
        queue.assign(1, std::uint32_t(seed));
        for (std::size_t q = 0; q < queue.size(); ++q) {
            const auto& tri = mesh.triangles[queue[q]];
            for (int k = 0; k < 3; ++k)
                for (std::uint32_t u : around[edge_key(tri[k], tri[(k + 1) % 3])])
                    if (info.chart[u] == kNone && dot(normal[u], axis[c]) >= min_cos) {
                        info.chart[u] = c;
                        queue.push_back(u);
                    }
        }
    }
    info.charts = axis.size();

    // One vertex per (vertex, chart): the first chart keeps the index, the others get copies.
    std::vector<std::uint32_t> owner(V, kNone);
    std::unordered_map<std::uint64_t, std::uint32_t> copy;
    const auto append_copy = [&](std::uint32_t v) {
        const auto n = std::uint32_t(mesh.positions.size());
        mesh.positions.push_back(mesh.positions[v]);
        mesh.normals.push_back(mesh.normals[v]);
        if (!mesh.albedo.empty()) mesh.albedo.push_back(mesh.albedo[v]);
        if (!mesh.source_vertex.empty()) mesh.source_vertex.push_back(mesh.source_vertex[v]);
        if (!mesh.parents.empty()) mesh.parents.push_back(mesh.parents[v]);
        if (!mesh.brdf_index.empty()) mesh.brdf_index.push_back(mesh.brdf_index[v]);
        return n;
    };
    for (std::size_t t = 0; t < T; ++t) {
        const std::uint32_t c = info.chart[t];
        for (std::uint32_t& v : mesh.triangles[t]) {
            if (owner[v] == kNone) owner[v] = c;
            if (owner[v] == c) continue;
            const std::uint64_t key = (std::uint64_t(v) << 32) | c;
            auto it = copy.find(key);
            if (it == copy.end()) it = copy.emplace(key, append_copy(v)).first;
            v = it->second;
        }
    }
    info.added_vertices = mesh.positions.size() - V;

    // Each chart projected along its axis (metres), then packed.
    const std::size_t N = mesh.vertex_count();
    std::vector<std::uint32_t> chart_of(N, kNone);
    for (std::size_t t = 0; t < T; ++t)
        for (std::uint32_t v : mesh.triangles[t]) chart_of[v] = info.chart[t];
    std::vector<std::array<double, 2>> local(N, {0.0, 0.0});
    std::vector<ChartBox> boxes(info.charts);
    for (std::size_t v = 0; v < N; ++v) {
        const std::uint32_t c = chart_of[v];
        if (c == kNone) continue;  // used by no triangle
        const Vec3d d = axis[c];
        const Vec3d e1 = normalize(cross(std::abs(d.y) < 0.9 ? Vec3d{0, 1, 0} : Vec3d{1, 0, 0}, d));
        const Vec3d e2 = cross(d, e1);
        const Vec3d p = cast<double>(mesh.positions[v]);
        local[v] = {dot(p, e1), dot(p, e2)};
        ChartBox& b = boxes[c];
        b.lo_u = std::min(b.lo_u, local[v][0]), b.hi_u = std::max(b.hi_u, local[v][0]);
        b.lo_v = std::min(b.lo_v, local[v][1]), b.hi_v = std::max(b.hi_v, local[v][1]);
    }
    std::vector<std::size_t> order(info.charts);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return boxes[a].height() > boxes[b].height();
    });
    double area = 0, widest = 0;
    for (const ChartBox& b : boxes)
        area += b.width() * b.height(), widest = std::max({widest, b.width(), b.height()});
    // The gap is a number of texels of the final side: grow the side until everything fits.
    const double gap_share = options.gutter_texels / options.resolution;
    double side = std::max(std::sqrt(area), widest) * (1 + 2 * gap_share) + 1e-9;
    for (;;) {
        const double gap = gap_share * side;
        if (widest + gap <= side && pack(boxes, order, side, gap) <= side) break;
        side *= 1.02;
    }
    mesh.uvs.assign(N, {0.0f, 0.0f});
    for (std::size_t v = 0; v < N; ++v) {
        const std::uint32_t c = chart_of[v];
        if (c == kNone) continue;
        const ChartBox& b = boxes[c];
        mesh.uvs[v] = {float((b.x + local[v][0] - b.lo_u) / side),
                       float((b.y + local[v][1] - b.lo_v) / side)};
    }
    info.texels_per_metre = options.resolution / side;
    return info;
}

}  // namespace shprt
