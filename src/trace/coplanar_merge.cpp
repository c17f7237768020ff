// merge_coplanar (coplanar_merge.hpp): welding, pairing triangles into quads, merging quads.
#include "shprt/trace/coplanar_merge.hpp"

#include "trace/embree_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <utility>

namespace shprt {
namespace {

// "Straight" and "in one plane": within this many units in the last place (2^-24 of the largest
// coordinate magnitude involved) of the line or plane. A float grid's vertices, computed as
// origin + i/n·edge, are off their line by one or two.
constexpr double kRoundingUlps = 8.0;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

double tolerance(std::initializer_list<Vec3d> points) {
    double m = 0;
    for (const Vec3d& p : points) m = std::max({m, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    return kRoundingUlps * 0x1p-24 * m;
}

// Distance of p from the line through a and b (a ≠ b).
double line_distance(Vec3d a, Vec3d b, Vec3d p) {
    const Vec3d ab = b - a;
    return length(cross(ab, p - a)) / length(ab);
}

// a → p → b runs straight on through p: p on the segment's line, between a and b.
bool straight(Vec3d a, Vec3d p, Vec3d b) {
    return a != b && dot(p - a, b - p) > 0 && line_distance(a, b, p) <= tolerance({a, p, b});
}

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

double triangle_area(Vec3d a, Vec3d b, Vec3d c) { return 0.5 * length(cross(b - a, c - a)); }

struct Welded {
    std::vector<Vec3d> p;                  // welded positions (float values, held as double)
    std::vector<std::uint32_t> of_vertex;  // mesh vertex -> welded id
};

Welded weld(const Mesh& mesh) {
    struct KeyHash {
        std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
            std::uint64_t h = 0x9E3779B97F4A7C15ull;
            for (std::uint32_t v : k) h = (h ^ v) * 0xBF58476D1CE4E5B9ull;
            return std::size_t(h ^ (h >> 31));
        }
    };
    std::unordered_map<std::array<std::uint32_t, 3>, std::uint32_t, KeyHash> ids;
    ids.reserve(mesh.positions.size());
    Welded w;
    w.of_vertex.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3f p = mesh.positions[v];
        std::array<std::uint32_t, 3> key{};
        const float c[3] = {p.x + 0.0f, p.y + 0.0f, p.z + 0.0f};  // -0 welds with +0
        std::memcpy(key.data(), c, sizeof(c));
        const auto [it, fresh] = ids.try_emplace(key, std::uint32_t(w.p.size()));
        if (fresh) w.p.push_back({double(c[0]), double(c[1]), double(c[2])});
        w.of_vertex[v] = it->second;
    }
    return w;
}

using Tri = std::array<std::uint32_t, 3>;
using Quad = std::array<std::uint32_t, 4>;

// Step 2: pairs across mutual longest edges. Returns the quads; `paired` marks their triangles.
std::vector<Quad> pair_triangles(const std::vector<Vec3d>& p, const std::vector<Tri>& tris,
                                 std::vector<char>& paired) {
    const std::size_t T = tris.size();
    std::vector<std::uint8_t> longest(T);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // (key, 3·t + edge)
    edges.reserve(3 * T);
    for (std::size_t t = 0; t < T; ++t) {
        double best = -1;
        for (int e = 0; e < 3; ++e) {
            const Vec3d d = p[tris[t][(e + 1) % 3]] - p[tris[t][e]];
            if (dot(d, d) > best) best = dot(d, d), longest[t] = std::uint8_t(e);
            edges.emplace_back(edge_key(tris[t][e], tris[t][(e + 1) % 3]),
                               std::uint32_t(3 * t + e));
        }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<std::uint32_t> across(3 * T, kNone);  // the one other half-edge on this edge
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].first == edges[i].first) ++j;
        if (j - i == 2) {
            across[edges[i].second] = edges[i + 1].second;
            across[edges[i + 1].second] = edges[i].second;
        }
        i = j;
    }
    std::vector<Quad> quads;
    for (std::size_t t = 0; t < T; ++t) {
        if (paired[t]) continue;
        const int e = longest[t];
        const std::uint32_t h = across[3 * t + std::size_t(e)];
        if (h == kNone) continue;
        const std::uint32_t s = h / 3, es = h % 3;
        if (paired[s] || longest[s] != es) continue;
        const std::uint32_t a = tris[t][e], b = tris[t][(e + 1) % 3], c = tris[t][(e + 2) % 3];
        if (tris[s][es] != b || tris[s][(es + 1) % 3] != a) continue;  // windings disagree
        const std::uint32_t d = tris[s][(es + 2) % 3];
        const Quad q{a, d, b, c};  // t's winding, its edge a → b replaced by a → d → b
        const Vec3d n = normalize(cross(p[b] - p[a], p[c] - p[a]));
        if (std::fabs(dot(p[d] - p[a], n)) > tolerance({p[a], p[b], p[c], p[d]})) continue;
        bool convex = true;
        for (int k = 0; k < 4; ++k) {
            const Vec3d prev = p[q[(k + 3) % 4]], at = p[q[k]], next = p[q[(k + 1) % 4]];
            convex = convex && dot(cross(at - prev, next - at), n) > 0;
        }
        if (!convex) continue;
        paired[t] = paired[s] = 1;
        quads.push_back(q);
    }
    return quads;
}

// Step 3: the quads that share each side. A side of more than two quads is never merged across.
class Sides {
public:
    explicit Sides(std::size_t quads) { m_slots.reserve(4 * quads); }
    void add(const Quad& q, std::uint32_t id) {
        for (int k = 0; k < 4; ++k) {
            Slot& s = m_slots[edge_key(q[k], q[(k + 1) % 4])];
            if (s.n < 2) s.q[s.n] = id;
            ++s.n;
        }
    }
    void remove(const Quad& q, std::uint32_t id) {
        for (int k = 0; k < 4; ++k) {
            const auto it = m_slots.find(edge_key(q[k], q[(k + 1) % 4]));
            Slot& s = it->second;
            if (s.n <= 2) {
                if (s.q[0] == id) s.q[0] = s.q[1];
            } else {
                s.poisoned = true;  // which ids remain is no longer known
            }
            if (--s.n == 0) m_slots.erase(it);
        }
    }
    // The one other quad on side (a, b), or kNone.
    std::uint32_t other(std::uint32_t a, std::uint32_t b, std::uint32_t id) const {
        const auto it = m_slots.find(edge_key(a, b));
        if (it == m_slots.end() || it->second.n != 2 || it->second.poisoned) return kNone;
        return it->second.q[0] == id ? it->second.q[1] : it->second.q[0];
    }

private:
    struct Slot {
        std::uint32_t q[2] = {kNone, kNone};
        std::uint32_t n = 0;
        bool poisoned = false;
    };
    std::unordered_map<std::uint64_t, Slot> m_slots;
};

// Merges quad `id` with its neighbour across side k (q_k → q_{k+1}) when both neighbouring sides
// run straight on: q_{k+3} → q_k → r_a and r_b → q_{k+1} → q_{k+2}. The union is
// (r_a, r_b, q_{k+2}, q_{k+3}).
bool merge_across(const std::vector<Vec3d>& p, std::vector<Quad>& quads, std::vector<char>& alive,
                  Sides& sides, std::uint32_t id, int k) {
    const Quad q = quads[id];
    const std::uint32_t qk = q[k], qk1 = q[(k + 1) % 4], qk2 = q[(k + 2) % 4], qk3 = q[(k + 3) % 4];
    const std::uint32_t other = sides.other(qk, qk1, id);
    if (other == kNone || !alive[other]) return false;
    const Quad r = quads[other];
    int j = 0;
    while (j < 4 && !(r[j] == qk1 && r[(j + 1) % 4] == qk)) ++j;
    if (j == 4) return false;  // the side runs the same way in both: windings disagree
    const std::uint32_t ra = r[(j + 2) % 4], rb = r[(j + 3) % 4];
    if (!straight(p[qk3], p[qk], p[ra]) || !straight(p[rb], p[qk1], p[qk2])) return false;
    sides.remove(q, id);
    sides.remove(r, other);
    alive[other] = 0;
    quads[id] = {ra, rb, qk2, qk3};
    sides.add(quads[id], id);
    return true;
}

}  // namespace

MergedTriangles merge_coplanar(const Mesh& mesh) {
    trace_detail::validate_mesh(mesh);  // the tracers' checks, before any index is followed
    MergedTriangles out;
    out.input_triangles = mesh.triangles.size();
    const Welded w = weld(mesh);
    const std::vector<Vec3d>& p = w.p;

    std::vector<Tri> tris;  // the non-degenerate triangles, welded
    tris.reserve(mesh.triangles.size());
    double area_in = 0;
    for (const auto& t : mesh.triangles) {
        const Tri wt{w.of_vertex[t[0]], w.of_vertex[t[1]], w.of_vertex[t[2]]};
        const double area = triangle_area(p[wt[0]], p[wt[1]], p[wt[2]]);
        if (wt[0] == wt[1] || wt[1] == wt[2] || wt[0] == wt[2] || !(area > 0)) continue;
        tris.push_back(wt);
        area_in += area;
    }

    std::vector<char> paired(tris.size(), 0);
    std::vector<Quad> quads = pair_triangles(p, tris, paired);
    std::vector<char> alive(quads.size(), 1);
    Sides sides(quads.size());
    for (std::size_t i = 0; i < quads.size(); ++i) sides.add(quads[i], std::uint32_t(i));
    for (bool changed = true; changed;) {
        changed = false;
        for (std::uint32_t id = 0; id < quads.size(); ++id) {
            for (bool grew = alive[id] != 0; grew;) {
                grew = false;
                for (int k = 0; k < 4 && !grew; ++k)
                    grew = merge_across(p, quads, alive, sides, id, k);
                changed = changed || grew;
            }
        }
    }

    // The merged quads, split along their shorter diagonal, and the triangles left unpaired.
    std::vector<Tri> merged;
    for (std::size_t i = 0; i < quads.size(); ++i) {
        if (!alive[i]) continue;
        const Quad& q = quads[i];
        const Vec3d d02 = p[q[2]] - p[q[0]], d13 = p[q[3]] - p[q[1]];
        if (dot(d02, d02) <= dot(d13, d13)) {
            merged.push_back({q[0], q[1], q[2]});
            merged.push_back({q[0], q[2], q[3]});
        } else {
            merged.push_back({q[1], q[2], q[3]});
            merged.push_back({q[1], q[3], q[0]});
        }
    }
    for (std::size_t t = 0; t < tris.size(); ++t)
        if (!paired[t]) merged.push_back(tris[t]);

    double area_out = 0;
    for (const Tri& t : merged) area_out += triangle_area(p[t[0]], p[t[1]], p[t[2]]);
    if (!(std::fabs(area_out - area_in) <= 1e-6 * area_in)) {
        out.area_check_failed = true;
        out.positions = mesh.positions;
        out.triangles = mesh.triangles;
        return out;
    }
    std::vector<std::uint32_t> remap(p.size(), kNone);
    for (Tri& t : merged)
        for (std::uint32_t& v : t) {
            if (remap[v] == kNone) {
                remap[v] = std::uint32_t(out.positions.size());
                out.positions.push_back({float(p[v].x), float(p[v].y), float(p[v].z)});
            }
            v = remap[v];
        }
    out.triangles = std::move(merged);
    return out;
}

Mesh merged_mesh(const Mesh& mesh) {
    MergedTriangles merged = merge_coplanar(mesh);
    Mesh out;
    out.source = mesh.source;
    out.positions = std::move(merged.positions);
    out.triangles = std::move(merged.triangles);
    return out;
}

}  // namespace shprt
