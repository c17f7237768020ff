// Bounce sources (bounce_sources.hpp): the grid points the light leaving a hit is interpolated
// from, their validity and the fill of the invalid ones.
#include "shprt/bake/bounce_sources.hpp"

#include "shprt/bake/interreflect.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shprt {

namespace {

double longest_edge(const Mesh& mesh, const std::array<std::uint32_t, 3>& t) {
    const Vec3d a = cast<double>(mesh.positions[t[0]]);
    const Vec3d b = cast<double>(mesh.positions[t[1]]);
    const Vec3d c = cast<double>(mesh.positions[t[2]]);
    return std::max({length(b - a), length(c - b), length(a - c)});
}

// The point's unit normal: the vertex normals interpolated, else the face's, else +Y.
Vec3f grid_normal(const Mesh& mesh, const std::array<std::uint32_t, 3>& t, double u, double v) {
    const Vec3d n = cast<double>(mesh.normals[t[0]]) * (1.0 - u - v) +
                    cast<double>(mesh.normals[t[1]]) * u + cast<double>(mesh.normals[t[2]]) * v;
    if (length(n) > 1e-6) return cast<float>(normalize(n));
    const Vec3d p0 = cast<double>(mesh.positions[t[0]]);
    const Vec3d f =
        cross(cast<double>(mesh.positions[t[1]]) - p0, cast<double>(mesh.positions[t[2]]) - p0);
    if (length(f) > 0) return cast<float>(normalize(f));
    return Vec3f{0.0f, 1.0f, 0.0f};
}

// Calls cell(a, b, c) with the three point indices of every cell of every triangle's grid.
template <class Fn>
void for_each_cell(const Mesh& mesh, const BounceSources& s, Fn&& cell) {
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* tri = mesh.triangles[t].data();
        const std::uint32_t n = s.grid[t];
        const std::uint32_t base = s.base[t];
        const auto at = [&](std::uint32_t i, std::uint32_t j) {
            return grid_point_index(tri, base, n, i, j);
        };
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i + j < n; ++i) {
                cell(at(i, j), at(i + 1, j), at(i, j + 1));
                if (i + j + 1 < n) cell(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }
}

}  // namespace

TransportMeshView BounceSources::view(const Mesh& mesh) const {
    TransportMeshView v = transport_mesh_view(mesh);
    v.grid = grid.data();
    v.base = base.data();
    v.back_offset = two_sided ? static_cast<std::uint32_t>(front) : 0u;
    return v;
}

float default_source_spacing(const Mesh& mesh) {
    const Bounds b = mesh_bounds(mesh);
    const double diagonal = length(cast<double>(b.hi) - cast<double>(b.lo));
    return diagonal > 0 && std::isfinite(diagonal) ? float(diagonal / kDefaultSourceCells) : 1.0f;
}

namespace {

// Cells per edge of a triangle whose longest edge is `edge` at `spacing` (at most 2^15: a sliver
// longer than that many cells is cut no finer).
std::uint32_t cells_per_edge(double edge, float spacing) {
    const double cells = std::isfinite(spacing) ? std::ceil(edge / double(spacing)) : 1.0;
    return static_cast<std::uint32_t>(std::clamp(cells, 1.0, 32768.0));
}

}  // namespace

std::size_t bounce_source_count(const Mesh& mesh, float spacing, bool two_sided) {
    std::uint64_t points = mesh.vertex_count();
    for (const auto& t : mesh.triangles)
        points += grid_own_points(cells_per_edge(longest_edge(mesh, t), spacing));
    return std::size_t(points * (two_sided ? 2 : 1));
}

BounceSources make_bounce_sources(const Mesh& mesh, float spacing, bool two_sided) {
    SHPRT_CHECK(mesh.normals.size() == mesh.vertex_count(), invalid_argument,
                "bounce sources need a normal per vertex ({} vertices, {} normals)",
                mesh.vertex_count(), mesh.normals.size());
    SHPRT_CHECK(spacing > 0.0f, invalid_argument,
                "the bounce sources' spacing must be positive (got {})", spacing);
    BounceSources s;
    const std::size_t V = mesh.vertex_count(), T = mesh.triangle_count();
    s.vertices = V;
    s.two_sided = two_sided;
    s.spacing = spacing;
    s.grid.resize(T);
    s.base.resize(T);
    std::vector<float> cell(T);
    std::uint64_t points = V;
    constexpr std::uint64_t kMaxPoints = std::numeric_limits<std::int32_t>::max();
    for (std::size_t t = 0; t < T; ++t) {
        const double edge = longest_edge(mesh, mesh.triangles[t]);
        const std::uint32_t n = cells_per_edge(edge, spacing);
        s.grid[t] = n;
        s.base[t] = static_cast<std::uint32_t>(std::min<std::uint64_t>(points, kMaxPoints));
        cell[t] = float(edge / n);
        points += grid_own_points(n);
        SHPRT_CHECK(points * (two_sided ? 2 : 1) <= kMaxPoints, out_of_memory,
                    "{}: more than 2^31 - 1 bounce sources at a spacing of {} m (use a larger "
                    "--source-spacing)",
                    mesh.source, spacing);
    }
    s.front = std::size_t(points);
    s.positions.resize(s.front);
    s.normals.resize(s.front);
    s.reach.assign(s.front, 0.0f);
    for (std::size_t v = 0; v < V; ++v) {
        s.positions[v] = mesh.positions[v];
        s.normals[v] = mesh.normals[v];
    }
    for (std::size_t t = 0; t < T; ++t) {
        const auto& tri = mesh.triangles[t];
        const std::uint32_t n = s.grid[t];
        for (int k = 0; k < 3; ++k) s.reach[tri[k]] = std::max(s.reach[tri[k]], 2.0f * cell[t]);
        if (n == 1) continue;
        const Vec3d a = cast<double>(mesh.positions[tri[0]]);
        const Vec3d e1 = cast<double>(mesh.positions[tri[1]]) - a;
        const Vec3d e2 = cast<double>(mesh.positions[tri[2]]) - a;
        for (std::uint32_t j = 0; j <= n; ++j)
            for (std::uint32_t i = 0; i + j <= n; ++i) {
                const std::uint32_t q = grid_point_index(tri.data(), s.base[t], n, i, j);
                if (q < V) continue;  // a corner: the mesh's vertex
                const double u = double(i) / n, v = double(j) / n;
                s.positions[q] = cast<float>(a + e1 * u + e2 * v);
                s.normals[q] = grid_normal(mesh, tri, u, v);
                s.reach[q] = 2.0f * cell[t];
            }
    }
    if (two_sided) {
        s.positions.reserve(2 * s.front);
        s.normals.reserve(2 * s.front);
        for (std::size_t q = 0; q < s.front; ++q) {
            s.positions.push_back(s.positions[q]);
            s.normals.push_back(-s.normals[q]);
            s.reach.push_back(s.reach[q]);
        }
    }
    return s;
}

bool source_is_valid(std::uint32_t rays, std::uint32_t back, std::uint32_t near_back) {
    return float(near_back) <= kSourceNearBackShare * float(rays) &&
           float(back) <= kSourceBackShare * float(rays);
}

SourceFill plan_source_fill(const Mesh& mesh, const BounceSources& sources,
                            const std::vector<std::uint8_t>& valid) {
    const std::size_t N = sources.size();
    SHPRT_CHECK(valid.size() == N, invalid_argument,
                "the fill needs one validity flag per source ({} for {})", valid.size(), N);
    SourceFill fill;
    for (const std::uint8_t v : valid) fill.invalid += v ? 0 : 1;
    if (fill.invalid == 0) return fill;

    // The neighbours (points that share a cell) of the front points, as sorted unique pairs; a
    // back copy's are the front's plus the offset.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for_each_cell(mesh, sources, [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            if (x == y) continue;
            pairs.emplace_back(x, y);
            pairs.emplace_back(y, x);
        }
    });
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    const std::size_t front = sources.front;
    std::vector<std::uint32_t> start(front + 1, 0);
    for (const auto& p : pairs) ++start[p.first + 1];
    for (std::size_t q = 0; q < front; ++q) start[q + 1] += start[q];

    std::vector<std::uint8_t> has(valid);  // 1: valid or filled by an earlier round
    for (int ring = 0; ring < kSourceFillRings; ++ring) {
        SourceFill::Round round;
        round.start.push_back(0);
        for (std::size_t q = 0; q < N; ++q) {
            if (has[q]) continue;
            const std::size_t f = q % front, offset = q - f;
            for (std::uint32_t e = start[f]; e < start[f + 1]; ++e) {
                const std::uint32_t nb = pairs[e].second + std::uint32_t(offset);
                if (has[nb]) round.neighbour.push_back(nb);
            }
            if (round.neighbour.size() == round.start.back()) continue;
            round.point.push_back(std::uint32_t(q));
            round.start.push_back(std::uint32_t(round.neighbour.size()));
        }
        if (round.point.empty()) break;
        for (const std::uint32_t q : round.point) has[q] = 1;
        fill.rounds.push_back(std::move(round));
    }
    for (std::size_t q = 0; q < N; ++q)
        if (!has[q]) fill.zeroed.push_back(std::uint32_t(q));
    return fill;
}

void SourceFill::apply(float* rows, std::size_t row_floats, int threads) const {
    constexpr std::size_t kGrain = 256;
    for (const Round& r : rounds) {
        const std::size_t tasks = (r.point.size() + kGrain - 1) / kGrain;
        parallel_each(threads, tasks, [&](std::size_t task) {
            const std::size_t end = std::min(r.point.size(), (task + 1) * kGrain);
            for (std::size_t k = task * kGrain; k < end; ++k) {
                float* out = rows + std::size_t(r.point[k]) * row_floats;
                std::fill_n(out, row_floats, 0.0f);
                const float share = 1.0f / float(r.start[k + 1] - r.start[k]);
                for (std::uint32_t e = r.start[k]; e < r.start[k + 1]; ++e) {
                    const float* in = rows + std::size_t(r.neighbour[e]) * row_floats;
                    for (std::size_t i = 0; i < row_floats; ++i) out[i] += share * in[i];
                }
            }
        });
    }
    for (const std::uint32_t q : zeroed)
        std::fill_n(rows + std::size_t(q) * row_floats, row_floats, 0.0f);
}

}  // namespace shprt
