// UV atlas of a mesh without one (scene/uv_atlas.hpp): normal-cone charts, laid out by
// orthographic projection (the generated room) or by least-squares conformal maps (B. Lévy,
// S. Petitjean, N. Ray, J. Maillot, "Least Squares Conformal Maps for Automatic Texture Atlas
// Generation", SIGGRAPH 2002), split on flips, stretch and self-overlap, shelf packing at one
// scale. Stretch as in P. Sander, J. Snyder, S. Gortler, H. Hoppe, "Texture Mapping Progressive
// Meshes", SIGGRAPH 2001 (its L∞ norm, symmetrised: max(σ₁, 1/σ₂)).
#include "shprt/scene/uv_atlas.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "uv_pack.hpp"

#include <fmt/format.h>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <utility>

namespace shprt {
namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A triangle with |n| ≤ this × its longest edge² has no area for the atlas (sin of its largest
// angle below ~1e-9): a chart of its own.
constexpr double kDegenerate = 1e-9;

using detail::ChartBox;
using detail::pack_atlas;
using detail::pack_texels;
using detail::Uv;
using detail::uv_area2;

double length2(const Vec3d& a) { return dot(a, a); }

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(a) << 32) | b;
}

// Stretch max(σ₁, 1/σ₂) of the linear map from triangle (p0, p1, p2) to (q0, q1, q2); infinity
// when the UV triangle is flipped or has no area.
double triangle_stretch(const Vec3d& p0, const Vec3d& p1, const Vec3d& p2, const Uv& q0,
                        const Uv& q1, const Uv& q2) {
    const Vec3d d1 = p1 - p0, d2 = p2 - p0;
    const double l1 = length(d1);
    const Vec3d n = cross(d1, d2);
    const double area2 = length(n);
    const double det_q = uv_area2(q0, q1, q2);
    if (!(area2 > 0) || !(l1 > 0) || !(det_q > 0)) return kInf;
    // The triangle in its own frame: P = [(l1, 0), (a, b)] (columns), det P = l1·b = |n|.
    const double a = dot(d2, d1) / l1, b = area2 / l1;
    // J = Q·P⁻¹ with P⁻¹ = [[1/l1, −a/(l1·b)], [0, 1/b]].
    const double q10 = q1[0] - q0[0], q11 = q1[1] - q0[1], q20 = q2[0] - q0[0], q21 = q2[1] - q0[1];
    const double j00 = q10 / l1, j10 = q11 / l1;
    const double j01 = (q20 - a * j00) / b, j11 = (q21 - a * j10) / b;
    const double e = j00 * j00 + j10 * j10, f = j00 * j01 + j10 * j11, g = j01 * j01 + j11 * j11;
    const double root = std::sqrt((e - g) * (e - g) + 4 * f * f);
    const double s1 = std::sqrt(std::max(0.0, (e + g + root) / 2));
    const double s2 = std::sqrt(std::max(0.0, (e + g - root) / 2));
    if (!(s2 > 0)) return kInf;
    return std::max(s1, 1 / s2);
}

// One vertex per (vertex, chart) of `mesh`, `chart` per triangle: the first chart (by triangle
// order) keeps a vertex's index, each other chart gets a copy appended (position, normal and the
// per-vertex arrays present) and its triangles renumbered to it. Returns, per vertex, the one it
// is a copy of (itself for the originals).
std::vector<std::uint32_t> split_vertices(Mesh& mesh, const std::vector<std::uint32_t>& chart) {
    const std::size_t V = mesh.vertex_count();
    std::vector<std::uint32_t> owner(V, kNone), origin(V);
    std::iota(origin.begin(), origin.end(), std::uint32_t{0});
    std::unordered_map<std::uint64_t, std::uint32_t> copy;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t c = chart[t];
        for (std::uint32_t& v : mesh.triangles[t]) {
            if (owner[v] == kNone) owner[v] = c;
            if (owner[v] == c) continue;
            const std::uint64_t key = (std::uint64_t(v) << 32) | c;
            auto it = copy.find(key);
            if (it == copy.end()) {
                it = copy.emplace(key, std::uint32_t(mesh.positions.size())).first;
                mesh.positions.push_back(mesh.positions[v]);
                mesh.normals.push_back(mesh.normals[v]);
                if (!mesh.albedo.empty()) mesh.albedo.push_back(mesh.albedo[v]);
                if (!mesh.source_vertex.empty())
                    mesh.source_vertex.push_back(mesh.source_vertex[v]);
                if (!mesh.parents.empty()) mesh.parents.push_back(mesh.parents[v]);
                if (!mesh.brdf_index.empty()) mesh.brdf_index.push_back(mesh.brdf_index[v]);
                origin.push_back(v);
            }
            v = it->second;
        }
    }
    return origin;
}

// Stretch and the charts' share of the square, from each triangle's UVs in metres at the atlas's
// scale (`uv`, in double: float UVs round a millimetre triangle of a large atlas to nothing).
void measure(const Mesh& mesh, const std::vector<std::array<Uv, 3>>& uv, UvAtlasInfo& info) {
    const double side = info.resolution / info.texels_per_metre;  // metres per unit of UV
    double worst = 1, sum = 0, weight = 0, uv_area = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const auto& tri = mesh.triangles[t];
        const auto& q = uv[t];
        std::array<Vec3d, 3> p{};
        for (int k = 0; k < 3; ++k) p[std::size_t(k)] = cast<double>(mesh.positions[tri[k]]);
        const double area = 0.5 * length(cross(p[1] - p[0], p[2] - p[0]));
        const double longest =
            std::max({length2(p[1] - p[0]), length2(p[2] - p[1]), length2(p[0] - p[2])});
        uv_area += 0.5 * std::abs(uv_area2(q[0], q[1], q[2]));
        if (!(2 * area > kDegenerate * longest)) continue;
        const double st = triangle_stretch(p[0], p[1], p[2], q[0], q[1], q[2]);
        worst = std::max(worst, st);
        if (std::isfinite(st)) sum += st * area, weight += area;
    }
    info.max_stretch = worst;
    info.mean_stretch = weight > 0 ? sum / weight : 1;
    info.chart_share = uv_area / (side * side);
}

// --- conformal charts ------------------------------------------------------------------------

// The mesh as the conformal layout sees it: welded vertices (same position bits), face normals,
// areas, and each triangle's neighbour across each edge (kNone at a boundary, a non-manifold
// edge, or an edge its neighbour runs the same way: opposite orientation).
struct Surface {
    std::vector<std::uint32_t> welded;  // per vertex: its welded id
    std::vector<std::uint32_t> rep;     // per welded id: its first vertex
    std::vector<Vec3d> normal;          // per triangle, unit ({0, 0, 0} when degenerate)
    std::vector<double> area;           // per triangle, m²
    std::vector<std::uint8_t> degenerate;
    std::vector<std::array<std::uint32_t, 3>> next;  // neighbour across edge (k, k+1)
};

Surface surface_of(const Mesh& mesh) {
    const std::size_t V = mesh.vertex_count(), T = mesh.triangle_count();
    Surface s;
    s.welded.resize(V);
    struct Key {
        std::uint32_t x, y, z;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            return std::size_t((std::uint64_t(k.x) * 0x9E3779B97F4A7C15ull) ^
                               (std::uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full) ^
                               (std::uint64_t(k.z) * 0x165667B19E3779F9ull));
        }
    };
    const auto bits = [](float f) {
        if (f == 0.0f) f = 0.0f;  // −0 = +0
        std::uint32_t u;
        std::memcpy(&u, &f, 4);
        return u;
    };
    std::unordered_map<Key, std::uint32_t, KeyHash> ids;
    ids.reserve(V);
    for (std::size_t v = 0; v < V; ++v) {
        const Vec3f& p = mesh.positions[v];
        const auto [it, added] =
            ids.emplace(Key{bits(p.x), bits(p.y), bits(p.z)}, std::uint32_t(s.rep.size()));
        if (added) s.rep.push_back(std::uint32_t(v));
        s.welded[v] = it->second;
    }
    s.normal.resize(T);
    s.area.resize(T);
    s.degenerate.resize(T);
    // Directed welded edges: (from, to) → the triangles and corner k with that edge.
    std::unordered_map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::uint8_t>>> edges;
    edges.reserve(3 * T);
    for (std::size_t t = 0; t < T; ++t) {
        const auto& tri = mesh.triangles[t];
        const Vec3d a = cast<double>(mesh.positions[tri[0]]);
        const Vec3d b = cast<double>(mesh.positions[tri[1]]);
        const Vec3d c = cast<double>(mesh.positions[tri[2]]);
        const Vec3d n = cross(b - a, c - a);
        const double longest = std::max({length2(b - a), length2(c - b), length2(a - c)});
        const double len = length(n);
        s.degenerate[t] = !(len > kDegenerate * longest);
        s.normal[t] = s.degenerate[t] ? Vec3d{0, 0, 0} : n / len;
        s.area[t] = 0.5 * len;
        for (int k = 0; k < 3; ++k)
            edges[edge_key(s.welded[tri[k]], s.welded[tri[(k + 1) % 3]])].push_back(
                {std::uint32_t(t), std::uint8_t(k)});
    }
    s.next.assign(T, {kNone, kNone, kNone});
    for (const auto& [key, list] : edges) {
        if (list.size() != 2) continue;  // a boundary or a non-manifold edge
        const auto [t0, k0] = list[0];
        const auto [t1, k1] = list[1];
        if (t0 == t1 || s.degenerate[t0] || s.degenerate[t1]) continue;
        const auto& a = mesh.triangles[t0];
        const auto& b = mesh.triangles[t1];
        // Consistent orientation: the edge runs the other way in the neighbour.
        if (s.welded[a[k0]] != s.welded[b[(k1 + 1) % 3]]) continue;
        s.next[t0][k0] = t1;
        s.next[t1][k1] = t0;
    }
    return s;
}

// A chart: its triangles, and its layout (per welded vertex, metres; filled by layout()).
struct Chart {
    std::vector<std::uint32_t> triangles;
    std::vector<std::uint32_t> vertices;  // welded ids
    std::vector<Uv> uv;                   // per entry of `vertices`
};

// The triangle last reached breadth-first from `from` (over Surface::next inside
// the set `member` marks with `tag`).
std::uint32_t farthest(const Surface& s, std::uint32_t from,
                       const std::vector<std::uint32_t>& member, std::uint32_t tag,
                       std::vector<std::uint32_t>& seen, std::uint32_t& stamp) {
    ++stamp;
    std::vector<std::uint32_t> queue{from};
    seen[from] = stamp;
    for (std::size_t q = 0; q < queue.size(); ++q)
        for (std::uint32_t u : s.next[queue[q]])
            if (u != kNone && member[u] == tag && seen[u] != stamp) {
                seen[u] = stamp;
                queue.push_back(u);
            }
    return queue.back();
}

// Splits `chart` in two, grown breadth-first from seeds a and b at once (a's side first at each
// step); a triangle neither reaches (none: charts are connected) goes to a's.
std::pair<Chart, Chart> split(const Surface& s, const Chart& chart, std::uint32_t a,
                              std::uint32_t b, std::vector<std::uint32_t>& member,
                              std::uint32_t tag) {
    // member[t] == tag: in the chart, unclaimed; tag + 1: a's; tag + 2: b's.
    std::vector<std::uint32_t> queue{a, b};
    member[a] = tag + 1, member[b] = tag + 2;
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const std::uint32_t side = member[queue[q]];
        for (std::uint32_t u : s.next[queue[q]])
            if (u != kNone && member[u] == tag) {
                member[u] = side;
                queue.push_back(u);
            }
    }
    std::pair<Chart, Chart> out;
    for (std::uint32_t t : chart.triangles)
        (member[t] == tag + 2 ? out.second : out.first).triangles.push_back(t);
    return out;
}

// The chart's triangles' vertices in the frame of triangle t's plane (for a lone triangle, and as
// the fallback layout: projection along the chart's mean normal).
void project_chart(const Mesh& mesh, const Surface& s, Chart& chart) {
    Vec3d axis{0, 0, 0};
    for (std::uint32_t t : chart.triangles) axis = axis + s.normal[t] * s.area[t];
    axis = length(axis) > 0 ? normalize(axis) : Vec3d{0, 0, 1};
    const Vec3d e1 =
        normalize(cross(std::abs(axis.y) < 0.9 ? Vec3d{0, 1, 0} : Vec3d{1, 0, 0}, axis));
    const Vec3d e2 = cross(axis, e1);
    chart.uv.resize(chart.vertices.size());
    for (std::size_t i = 0; i < chart.vertices.size(); ++i) {
        const Vec3d p = cast<double>(mesh.positions[s.rep[chart.vertices[i]]]);
        chart.uv[i] = {dot(p, e1), dot(p, e2)};
    }
}

// Least-squares conformal map of `chart` (connected, triangles with area): fills vertices and uv.
// `slot` maps welded ids to entries of chart.vertices (kNone elsewhere; restored on return).
void conformal_layout(const Mesh& mesh, const Surface& s, Chart& chart,
                      std::vector<std::uint32_t>& slot) {
    chart.vertices.clear();
    for (std::uint32_t t : chart.triangles)
        for (std::uint32_t v : mesh.triangles[t]) {
            const std::uint32_t w = s.welded[v];
            if (slot[w] == kNone) {
                slot[w] = std::uint32_t(chart.vertices.size());
                chart.vertices.push_back(w);
            }
        }
    const std::size_t n = chart.vertices.size();
    const auto position = [&](std::size_t i) {
        return cast<double>(mesh.positions[s.rep[chart.vertices[i]]]);
    };
    bool solved = false;
    if (chart.triangles.size() == 1) {
        project_chart(mesh, s, chart);  // a lone triangle: its own plane, exactly
        solved = true;
    } else {
        // Pins: a vertex far from the first, and the vertex farthest from it.
        const auto far_from = [&](std::size_t from) {
            std::size_t best = from;
            double d = -1;
            for (std::size_t i = 0; i < n; ++i)
                if (const double e = length2(position(i) - position(from)); e > d) d = e, best = i;
            return best;
        };
        const std::size_t pa = far_from(0), pb = far_from(pa);
        const double span = length(position(pb) - position(pa));
        // Unknowns: u then v of each free vertex. Note 1: per triangle, in its own orthonormal
        // frame, the gradients of the hat functions are g_k = rot90(e_k) / 2A with e_k the edge
        // opposite corner k; the Cauchy–Riemann residuals u_x − v_y and u_y + v_x, weighted by
        // √A, are the rows (the conformal energy of Lévy et al. §3).
        std::vector<std::int32_t> col(n, -1);
        std::int32_t free = 0;
        for (std::size_t i = 0; i < n; ++i)
            if (i != pa && i != pb) col[i] = free++;
        std::vector<Uv> pinned(n, {0.0, 0.0});
        pinned[pb] = {span, 0.0};
        const std::size_t rows = 2 * chart.triangles.size();
        std::vector<Eigen::Triplet<double>> entries;
        entries.reserve(6 * rows);
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(Eigen::Index(rows));
        for (std::size_t r = 0; r < chart.triangles.size(); ++r) {
            const auto& tri = mesh.triangles[chart.triangles[r]];
            std::array<std::size_t, 3> idx{};
            std::array<Vec3d, 3> p{};
            for (int k = 0; k < 3; ++k) idx[k] = slot[s.welded[tri[k]]], p[k] = position(idx[k]);
            const Vec3d d1 = p[1] - p[0], d2 = p[2] - p[0];
            const double l1 = length(d1), area2 = length(cross(d1, d2));
            const std::array<Uv, 3> q{Uv{0, 0}, Uv{l1, 0}, Uv{dot(d2, d1) / l1, area2 / l1}};
            const double w = 1.0 / std::sqrt(2.0 * area2);  // √A / 2A with A = area2 / 2
            const auto row_u = Eigen::Index(2 * r), row_v = row_u + 1;
            for (int k = 0; k < 3; ++k) {
                const Uv& from = q[(k + 1) % 3];
                const Uv& to = q[(k + 2) % 3];
                const double gx = -(to[1] - from[1]) * w, gy = (to[0] - from[0]) * w;
                // r1 = Σ gx·u − gy·v ; r2 = Σ gy·u + gx·v
                const std::size_t i = idx[k];
                if (col[i] >= 0) {
                    const Eigen::Index cu = col[i], cv = col[i] + free;
                    entries.emplace_back(row_u, cu, gx);
                    entries.emplace_back(row_u, cv, -gy);
                    entries.emplace_back(row_v, cu, gy);
                    entries.emplace_back(row_v, cv, gx);
                } else {
                    rhs[row_u] -= gx * pinned[i][0] - gy * pinned[i][1];
                    rhs[row_v] -= gy * pinned[i][0] + gx * pinned[i][1];
                }
            }
        }
        Eigen::SparseMatrix<double> a(Eigen::Index(rows), Eigen::Index(2 * free));
        a.setFromTriplets(entries.begin(), entries.end());
        const Eigen::SparseMatrix<double> normal = a.transpose() * a;
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
        if (solver.info() == Eigen::Success) {
            const Eigen::VectorXd x = solver.solve(a.transpose() * rhs);
            if (solver.info() == Eigen::Success && x.allFinite()) {
                chart.uv.resize(n);
                for (std::size_t i = 0; i < n; ++i)
                    chart.uv[i] = col[i] < 0 ? pinned[i] : Uv{x[col[i]], x[col[i] + free]};
                solved = true;
            }
        }
        if (!solved) project_chart(mesh, s, chart);  // then the checks decide
    }
    // One scale: UV area = surface area (a conformal map keeps shape, not size).
    double uv = 0, surface = 0;
    for (std::uint32_t t : chart.triangles) {
        const auto& tri = mesh.triangles[t];
        uv += uv_area2(chart.uv[slot[s.welded[tri[0]]]], chart.uv[slot[s.welded[tri[1]]]],
                       chart.uv[slot[s.welded[tri[2]]]]);
        surface += 2 * s.area[t];
    }
    if (uv < 0)  // mirrored (not for a conformal map; possibly for the fallback)
        for (Uv& q : chart.uv) q[1] = -q[1];
    const double scale = std::abs(uv) > 0 ? std::sqrt(surface / std::abs(uv)) : 1.0;
    for (Uv& q : chart.uv) q = {q[0] * scale, q[1] * scale};
    for (std::uint32_t w : chart.vertices) slot[w] = kNone;
}

// The chart's worst triangle and its stretch (infinity: flipped or without UV area).
std::pair<std::uint32_t, double> worst_triangle(const Mesh& mesh, const Surface& s,
                                                const Chart& chart,
                                                std::vector<std::uint32_t>& slot) {
    for (std::size_t i = 0; i < chart.vertices.size(); ++i)
        slot[chart.vertices[i]] = std::uint32_t(i);
    std::pair<std::uint32_t, double> worst{chart.triangles[0], 0.0};
    for (std::uint32_t t : chart.triangles) {
        const auto& tri = mesh.triangles[t];
        std::array<Vec3d, 3> p{};
        std::array<Uv, 3> q{};
        for (int k = 0; k < 3; ++k) {
            p[k] = cast<double>(mesh.positions[tri[k]]);
            q[k] = chart.uv[slot[s.welded[tri[k]]]];
        }
        const double st = triangle_stretch(p[0], p[1], p[2], q[0], q[1], q[2]);
        if (st > worst.second) worst = {t, st};
    }
    for (std::uint32_t w : chart.vertices) slot[w] = kNone;
    return worst;
}

// A degenerate triangle's chart: its vertices along its longest extent (no area, no texels).
void degenerate_layout(const Mesh& mesh, const Surface& s, Chart& chart) {
    const auto& tri = mesh.triangles[chart.triangles[0]];
    chart.vertices.clear();
    for (std::uint32_t v : tri)
        if (std::find(chart.vertices.begin(), chart.vertices.end(), s.welded[v]) ==
            chart.vertices.end())
            chart.vertices.push_back(s.welded[v]);
    Vec3d dir{1, 0, 0};
    double longest = 0;
    for (std::uint32_t a : chart.vertices)
        for (std::uint32_t b : chart.vertices) {
            const Vec3d d =
                cast<double>(mesh.positions[s.rep[b]]) - cast<double>(mesh.positions[s.rep[a]]);
            if (length(d) > longest) longest = length(d), dir = d / length(d);
        }
    chart.uv.clear();
    for (std::uint32_t w : chart.vertices)
        chart.uv.push_back({dot(cast<double>(mesh.positions[s.rep[w]]), dir), 0.0});
}

// Turns the chart to its smallest bounding box (5° steps), lying flat (width ≥ height).
void turn_for_packing(Chart& chart) {
    double best_area = kInf, best_angle = 0;
    for (int step = 0; step < 18; ++step) {
        const double angle = step * kPi / 36, c = std::cos(angle), sn = std::sin(angle);
        double lo_u = kInf, hi_u = -kInf, lo_v = kInf, hi_v = -kInf;
        for (const Uv& q : chart.uv) {
            const double u = c * q[0] - sn * q[1], v = sn * q[0] + c * q[1];
            lo_u = std::min(lo_u, u), hi_u = std::max(hi_u, u);
            lo_v = std::min(lo_v, v), hi_v = std::max(hi_v, v);
        }
        const double area = (hi_u - lo_u) * (hi_v - lo_v);
        if (area < best_area * (1 - 1e-9)) best_area = area, best_angle = angle;
    }
    const double c = std::cos(best_angle), sn = std::sin(best_angle);
    double lo_u = kInf, hi_u = -kInf, lo_v = kInf, hi_v = -kInf;
    for (Uv& q : chart.uv) {
        q = {c * q[0] - sn * q[1], sn * q[0] + c * q[1]};
        lo_u = std::min(lo_u, q[0]), hi_u = std::max(hi_u, q[0]);
        lo_v = std::min(lo_v, q[1]), hi_v = std::max(hi_v, q[1]);
    }
    if (hi_v - lo_v > hi_u - lo_u)  // a quarter turn: (u, v) → (v, −u), orientation kept
        for (Uv& q : chart.uv) q = {q[1], -q[0]};
}

UvAtlasInfo conformal_atlas(Mesh& mesh, const UvAtlasOptions& options, const std::string& name) {
    const std::size_t V = mesh.vertex_count(), T = mesh.triangle_count();
    const Surface s = surface_of(mesh);
    UvAtlasInfo info;

    // Charts: breadth-first growth within the normal cone of the seed, over Surface::next.
    std::vector<Chart> charts;
    std::vector<std::uint32_t> chart_of(T, kNone);
    const double min_cos = std::cos(options.max_angle_deg * kPi / 180.0);
    for (std::size_t seed = 0; seed < T; ++seed) {
        if (chart_of[seed] != kNone) continue;
        const auto c = std::uint32_t(charts.size());
        Chart& chart = charts.emplace_back();
        chart_of[seed] = c;
        chart.triangles.push_back(std::uint32_t(seed));
        if (s.degenerate[seed]) continue;
        for (std::size_t q = 0; q < chart.triangles.size(); ++q)
            for (std::uint32_t u : s.next[chart.triangles[q]])
                if (u != kNone && chart_of[u] == kNone &&
                    dot(s.normal[u], s.normal[seed]) >= min_cos) {
                    chart_of[u] = c;
                    chart.triangles.push_back(u);
                }
    }

    // Layout, splitting charts with a flipped or too stretched triangle.
    std::vector<std::uint32_t> slot(s.rep.size(), kNone), member(T, 0), seen(T, 0);
    std::uint32_t tag = 0, stamp = 0;
    std::vector<Chart> done;
    // Lays out `work` and its halves until each is good; appends them to `done`.
    const auto settle = [&](std::vector<Chart> work) {
        while (!work.empty()) {
            Chart chart = std::move(work.back());
            work.pop_back();
            if (s.degenerate[chart.triangles[0]]) {
                ++info.degenerate_triangles;
                degenerate_layout(mesh, s, chart);
                done.push_back(std::move(chart));
                continue;
            }
            conformal_layout(mesh, s, chart, slot);
            const auto [bad, stretch] = worst_triangle(mesh, s, chart, slot);
            if (stretch <= options.max_stretch || chart.triangles.size() == 1) {
                turn_for_packing(chart);
                done.push_back(std::move(chart));
                continue;
            }
            ++(std::isinf(stretch) ? info.split_flipped : info.split_stretched);
            tag += 3;
            for (std::uint32_t t : chart.triangles) member[t] = tag;
            // Seeds: two far triangles (a far one from the worst, the farthest from that).
            const std::uint32_t a = farthest(s, bad, member, tag, seen, stamp);
            const std::uint32_t b = farthest(s, a, member, tag, seen, stamp);
            std::pair<Chart, Chart> halves;
            if (a != b) {
                halves = split(s, chart, a, b, member, tag);
            } else {  // the worst triangle reaches no other (a = b = bad): it goes alone
                for (std::uint32_t t : chart.triangles)
                    (t == bad ? halves.second : halves.first).triangles.push_back(t);
            }
            work.push_back(std::move(halves.second));
            work.push_back(std::move(halves.first));
        }
    };
    std::reverse(charts.begin(), charts.end());  // settle() takes from the back: seed order
    settle(std::move(charts));

    // Pack, apply to a copy of the mesh, check overlaps at the atlas's resolution; split a chart
    // that overlaps itself and pack again.
    bool by_texels = false;
    for (;;) {
        // Charts in a fixed order (their first triangle), so the result does not depend on the
        // order splits happened in.
        std::stable_sort(done.begin(), done.end(), [](const Chart& a, const Chart& b) {
            return a.triangles.front() < b.triangles.front();
        });
        std::vector<ChartBox> boxes(done.size());
        for (std::size_t c = 0; c < done.size(); ++c)
            for (const Uv& q : done[c].uv) {
                ChartBox& b = boxes[c];
                b.lo_u = std::min(b.lo_u, q[0]), b.hi_u = std::max(b.hi_u, q[0]);
                b.lo_v = std::min(b.lo_v, q[1]), b.hi_v = std::max(b.hi_v, q[1]);
            }
        std::vector<std::vector<std::array<Uv, 3>>> triangles(done.size());
        for (std::size_t c = 0; c < done.size(); ++c) {
            const Chart& chart = done[c];
            for (std::size_t i = 0; i < chart.vertices.size(); ++i)
                slot[chart.vertices[i]] = std::uint32_t(i);
            for (std::uint32_t t : chart.triangles) {
                const auto& tri = mesh.triangles[t];
                triangles[c].push_back({chart.uv[slot[s.welded[tri[0]]]],
                                        chart.uv[slot[s.welded[tri[1]]]],
                                        chart.uv[slot[s.welded[tri[2]]]]});
            }
            for (std::uint32_t w : chart.vertices) slot[w] = kNone;
        }
        // Boxes while splits for overlaps go on (cheap), then the texels (overlaps checked again:
        // the scale changed).
        const auto by_boxes = pack_atlas(boxes, options, name);
        const auto [resolution, tpm] =
            by_texels ? pack_texels(triangles, boxes, options, by_boxes) : by_boxes;
        const double side = resolution / tpm;

        Mesh trial = mesh;
        info.chart.assign(T, kNone);
        for (std::size_t c = 0; c < done.size(); ++c)
            for (std::uint32_t t : done[c].triangles) info.chart[t] = std::uint32_t(c);
        const std::vector<std::uint32_t> origin = split_vertices(trial, info.chart);
        trial.uvs.assign(trial.vertex_count(), {0.0f, 0.0f});
        for (std::size_t c = 0; c < done.size(); ++c) {
            const Chart& chart = done[c];
            const ChartBox& b = boxes[c];
            for (std::size_t i = 0; i < chart.vertices.size(); ++i)
                slot[chart.vertices[i]] = std::uint32_t(i);
            for (std::uint32_t t : chart.triangles)
                for (std::uint32_t v : trial.triangles[t]) {
                    const Uv& q = chart.uv[slot[s.welded[origin[v]]]];
                    trial.uvs[v] = {float((b.x + q[0] - b.lo_u) / side),
                                    float((b.y + q[1] - b.lo_v) / side)};
                }
            for (std::uint32_t w : chart.vertices) slot[w] = kNone;
        }
        // The boxes' pass checks on a finer grid than its own: the texels' pass packs at a larger
        // scale, where a chart may overlap itself in texels it did not cover before.
        const int grid =
            by_texels ? resolution : std::min(kMaxTexelSide, int(std::ceil(resolution * 1.5)));
        const std::vector<UvOverlap> overlaps =
            find_uv_overlaps(trial, grid, grid, std::size_t{1} << 20);
        if (overlaps.empty() && !by_texels) {
            by_texels = true;
            continue;
        }
        if (overlaps.empty()) {
            mesh = std::move(trial);
            info.charts = done.size();
            info.added_vertices = mesh.vertex_count() - V;
            info.resolution = resolution;
            info.texels_per_metre = tpm;
            info.overlaps_checked = true;
            std::vector<std::array<Uv, 3>> uv(T);
            for (std::size_t c = 0; c < done.size(); ++c)
                for (std::size_t i = 0; i < done[c].triangles.size(); ++i)
                    uv[done[c].triangles[i]] = triangles[c][i];
            measure(mesh, uv, info);
            return info;
        }
        // Each chart that overlaps itself is split once, between the first two triangles found.
        std::vector<std::array<std::uint32_t, 2>> seeds(done.size(), {kNone, kNone});
        for (const UvOverlap& o : overlaps) {
            const std::uint32_t c = info.chart[o.first];
            SHPRT_CHECK(c == info.chart[o.second], invalid_argument,
                        "{}: UV atlas: charts {} and {} overlap (a packing fault)", name, c,
                        info.chart[o.second]);
            if (seeds[c][0] == kNone) seeds[c] = {o.first, o.second};
        }
        std::vector<Chart> kept, work;
        for (std::size_t c = 0; c < done.size(); ++c) {
            if (seeds[c][0] == kNone) {
                kept.push_back(std::move(done[c]));
                continue;
            }
            ++info.split_overlapping;
            tag += 3;
            for (std::uint32_t t : done[c].triangles) member[t] = tag;
            auto halves = split(s, done[c], seeds[c][0], seeds[c][1], member, tag);
            work.push_back(std::move(halves.second));
            work.push_back(std::move(halves.first));
        }
        done = std::move(kept);
        settle(std::move(work));
    }
}

// --- projected charts (the generated room) ---------------------------------------------------

UvAtlasInfo projected_atlas(Mesh& mesh, const UvAtlasOptions& options, const std::string& name) {
    const std::size_t V = mesh.vertex_count(), T = mesh.triangle_count();
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

    split_vertices(mesh, info.chart);
    info.added_vertices = mesh.positions.size() - V;

    // Each chart projected along its axis (metres), then packed.
    const std::size_t N = mesh.vertex_count();
    std::vector<std::uint32_t> chart_of(N, kNone);
    for (std::size_t t = 0; t < T; ++t)
        for (std::uint32_t v : mesh.triangles[t]) chart_of[v] = info.chart[t];
    std::vector<Uv> local(N, {0.0, 0.0});
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
    const auto [resolution, tpm] = pack_atlas(boxes, options, name);
    const double side = resolution / tpm;
    mesh.uvs.assign(N, {0.0f, 0.0f});
    for (std::size_t v = 0; v < N; ++v) {
        const std::uint32_t c = chart_of[v];
        if (c == kNone) continue;
        const ChartBox& b = boxes[c];
        mesh.uvs[v] = {float((b.x + local[v][0] - b.lo_u) / side),
                       float((b.y + local[v][1] - b.lo_v) / side)};
    }
    info.resolution = resolution;
    info.texels_per_metre = tpm;
    std::vector<std::array<Uv, 3>> uv(T);
    for (std::size_t t = 0; t < T; ++t)
        for (int k = 0; k < 3; ++k) uv[t][std::size_t(k)] = local[mesh.triangles[t][k]];
    measure(mesh, uv, info);
    return info;
}

}  // namespace

UvAtlasInfo make_uv_atlas(Mesh& mesh, const UvAtlasOptions& options) {
    const std::size_t V = mesh.vertex_count(), T = mesh.triangle_count();
    const std::string name = mesh.source.empty() ? std::string("mesh") : mesh.source;
    SHPRT_CHECK(T > 0, invalid_argument, "{}: no triangles to lay out in UV space", name);
    SHPRT_CHECK(options.resolution >= 1 && options.resolution <= kMaxTexelSide &&
                    options.gutter_texels >= 0 && std::isfinite(options.gutter_texels) &&
                    options.max_angle_deg > 0 && options.max_angle_deg < 90 &&
                    options.texels_per_metre >= 0 && std::isfinite(options.texels_per_metre) &&
                    options.max_stretch > 1,
                invalid_argument,
                "UV atlas: resolution {}, gutter {}, angle {}, texels per metre {}, stretch {} out "
                "of range",
                options.resolution, options.gutter_texels, options.max_angle_deg,
                options.texels_per_metre, options.max_stretch);
    SHPRT_CHECK(mesh.normals.size() == V, invalid_argument, "{}: {} normals for {} vertices", name,
                mesh.normals.size(), V);
    for (const auto& t : mesh.triangles)
        SHPRT_CHECK(t[0] < V && t[1] < V && t[2] < V, invalid_argument,
                    "{}: triangle index out of range ({} vertices)", name, V);
    for (const Vec3f& p : mesh.positions)
        SHPRT_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
                    invalid_argument, "{}: a vertex position is not finite", name);
    return options.layout == ChartLayout::conformal ? conformal_atlas(mesh, options, name)
                                                    : projected_atlas(mesh, options, name);
}

std::string describe(const UvAtlasInfo& info) {
    const std::size_t splits = info.split_flipped + info.split_stretched + info.split_overlapping;
    std::string out = fmt::format("{} charts", info.charts);
    if (splits > 0)
        out += fmt::format(" ({} split: {} flipped, {} stretched, {} overlapping)", splits,
                           info.split_flipped, info.split_stretched, info.split_overlapping);
    out += fmt::format(
        ", {}x{} texels at {:.4g} texels/m, stretch max {:.3f} mean {:.3f}, {:.0f}% of the image "
        "in charts, +{} vertices",
        info.resolution, info.resolution, info.texels_per_metre, info.max_stretch,
        info.mean_stretch, 100 * info.chart_share, info.added_vertices);
    if (info.overlaps_checked) out += ", overlap 0";
    if (info.degenerate_triangles > 0)
        out += fmt::format(", {} triangle{} without area", info.degenerate_triangles,
                           info.degenerate_triangles == 1 ? "" : "s");
    return out;
}

const std::vector<OptionRow<UnwrapChoice>>& unwrap_option_table() {
    static const std::vector<OptionRow<UnwrapChoice>> table = [] {
        using C = UnwrapChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "texel_density", &C::texel_density, "Texels per metre (chooses the resolution)");
        add_row(t, "resolution", &C::resolution,
                "Square image side the atlas fills (default 1024)");
        add_row(t, "gutter", &C::gutter, "Empty texels between charts");
        add_row(t, "max_angle", &C::max_angle,
                "Largest angle (degrees) between a chart's normals and its seed's");
        add_row(t, "max_stretch", &C::max_stretch,
                "Split a chart while a triangle's stretch exceeds this (> 1)");
        return complete_rows(std::move(t));
    }();
    return table;
}

UvAtlasOptions unwrap_options_from(const UnwrapChoice& c) {
    SHPRT_CHECK(!(c.texel_density && c.resolution), invalid_argument,
                "--texel-density and --resolution: give one (the density chooses the resolution)");
    UvAtlasOptions atlas;
    atlas.layout = ChartLayout::conformal;
    atlas.gutter_texels = c.gutter;
    atlas.max_angle_deg = c.max_angle;
    atlas.max_stretch = c.max_stretch;
    if (c.texel_density) {
        SHPRT_CHECK(*c.texel_density > 0 && std::isfinite(*c.texel_density), invalid_argument,
                    "--texel-density {}: expected texels per metre, > 0", *c.texel_density);
        atlas.texels_per_metre = *c.texel_density;
    }
    if (c.resolution) {
        SHPRT_CHECK(*c.resolution >= 1 && *c.resolution <= kMaxTexelSide, invalid_argument,
                    "--resolution {}: expected 1 to {}", *c.resolution, kMaxTexelSide);
        atlas.resolution = *c.resolution;
    }
    return atlas;
}

}  // namespace shprt
