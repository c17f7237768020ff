// Tessellated primitives for the generated scenes (see shprt/scene/builder.hpp). Plain geometry;
// the icosphere is the usual midpoint subdivision of an icosahedron.
#include "shprt/scene/builder.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

namespace shprt {
namespace {

constexpr double kTwoPi = 2.0 * kPi;
// Interval lengths are divided by the cell size and rounded up; this slack keeps a length that
// is an exact multiple of the cell (up to rounding) from getting one extra sliver of a cell.
constexpr double kCeilSlack = 1e-9;

std::size_t segments(double length, double cell) {
    const double n = std::ceil(length / cell - kCeilSlack);
    return n < 1.0 ? 1 : static_cast<std::size_t>(n);
}

// Sorted, de-duplicated cut positions along one side of a rectangle: its two ends and every
// hole edge (clamped to the side).
std::vector<double> cuts_along(double lo, double hi, std::span<const Rect2> holes, bool a_side) {
    std::vector<double> cuts{lo, hi};
    for (const Rect2& h : holes) {
        cuts.push_back(std::clamp(a_side ? h.a0 : h.b0, lo, hi));
        cuts.push_back(std::clamp(a_side ? h.a1 : h.b1, lo, hi));
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    return cuts;
}

// Grid line positions: each interval between consecutive cuts divided evenly into cells of at
// most `cell`.
std::vector<double> grid_lines(const std::vector<double>& cuts, double cell) {
    std::vector<double> lines{cuts.front()};
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
        const std::size_t n = segments(cuts[i + 1] - cuts[i], cell);
        for (std::size_t k = 1; k <= n; ++k)
            lines.push_back(k == n ? cuts[i + 1]
                                   : cuts[i] + (cuts[i + 1] - cuts[i]) * static_cast<double>(k) /
                                                   static_cast<double>(n));
    }
    return lines;
}

// Number of cells between cut positions lo and hi (both cuts).
std::size_t cells_between(const std::vector<double>& cuts, double lo, double hi, double cell) {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
        if (cuts[i] >= lo && cuts[i + 1] <= hi) n += segments(cuts[i + 1] - cuts[i], cell);
    return n;
}

Vec3d axis_point(int axis, double coord, double a, double b) {
    Vec3d p{0, 0, 0};
    p[axis] = coord;
    p[(axis + 1) % 3] = a;
    p[(axis + 2) % 3] = b;
    return p;
}

}  // namespace

void MeshBuilder::set_placement(Vec3d origin, double yaw) {
    m_origin = origin;
    m_cos = std::cos(yaw);
    m_sin = std::sin(yaw);
    // Snap quarter turns so walls and furniture placed at 90 degrees meet exactly.
    const double quarter = yaw / (0.5 * kPi);
    if (std::abs(quarter - std::round(quarter)) < 1e-12) {
        const long q = ((std::lround(quarter) % 4) + 4) % 4;
        constexpr double kCos[4] = {1, 0, -1, 0};
        constexpr double kSin[4] = {0, 1, 0, -1};
        m_cos = kCos[q];
        m_sin = kSin[q];
    }
}

std::uint32_t MeshBuilder::add_vertex(Vec3d p, Vec3d n, Vec3f albedo) {
    const Vec3d wp{m_origin.x + m_cos * p.x + m_sin * p.z, m_origin.y + p.y,
                   m_origin.z - m_sin * p.x + m_cos * p.z};
    const Vec3d wn = normalize(Vec3d{m_cos * n.x + m_sin * n.z, n.y, -m_sin * n.x + m_cos * n.z});
    SHPRT_CHECK(m_mesh.positions.size() < std::numeric_limits<std::uint32_t>::max(),
                invalid_argument, "generated mesh exceeds 2^32 - 1 vertices");
    m_mesh.positions.push_back(cast<float>(wp));
    m_mesh.normals.push_back(cast<float>(wn));
    m_mesh.albedo.push_back(albedo);
    return static_cast<std::uint32_t>(m_mesh.positions.size() - 1);
}

void MeshBuilder::add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    m_mesh.triangles.push_back({a, b, c});
}

void MeshBuilder::add_rect(Axis axis_enum, double coord, int sign, Rect2 r, double cell,
                           Vec3f albedo, std::span<const Rect2> holes) {
    SHPRT_CHECK(cell > 0 && r.a1 > r.a0 && r.b1 > r.b0, invalid_argument,
                "add_rect: empty rectangle or non-positive cell size {}", cell);
    const int axis = static_cast<int>(axis_enum);
    const std::vector<double> cuts_a = cuts_along(r.a0, r.a1, holes, true);
    const std::vector<double> cuts_b = cuts_along(r.b0, r.b1, holes, false);

    if (m_count_only) {
        std::size_t cells =
            cells_between(cuts_a, r.a0, r.a1, cell) * cells_between(cuts_b, r.b0, r.b1, cell);
        for (const Rect2& h : holes)
            cells -=
                cells_between(cuts_a, h.a0, h.a1, cell) * cells_between(cuts_b, h.b0, h.b1, cell);
        m_triangle_count += 2 * cells;
        return;
    }

    const std::vector<double> la = grid_lines(cuts_a, cell);
    const std::vector<double> lb = grid_lines(cuts_b, cell);
    const std::size_t na = la.size() - 1, nb = lb.size() - 1;
    Vec3d normal{0, 0, 0};
    normal[axis] = sign > 0 ? 1.0 : -1.0;

    constexpr std::uint32_t kUnset = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> index((na + 1) * (nb + 1), kUnset);
    auto vertex = [&](std::size_t i, std::size_t j) {
        std::uint32_t& v = index[j * (na + 1) + i];
        if (v == kUnset) v = add_vertex(axis_point(axis, coord, la[i], lb[j]), normal, albedo);
        return v;
    };
    for (std::size_t j = 0; j < nb; ++j) {
        const double cb = 0.5 * (lb[j] + lb[j + 1]);
        for (std::size_t i = 0; i < na; ++i) {
            const double ca = 0.5 * (la[i] + la[i + 1]);
            const bool in_hole = std::any_of(holes.begin(), holes.end(), [&](const Rect2& h) {
                return ca > h.a0 && ca < h.a1 && cb > h.b0 && cb < h.b1;
            });
            if (in_hole) continue;
            const std::uint32_t v00 = vertex(i, j), v10 = vertex(i + 1, j);
            const std::uint32_t v11 = vertex(i + 1, j + 1), v01 = vertex(i, j + 1);
            // cross(a, b) = +axis, so (00, 10, 11) is counter-clockwise seen from +axis.
            if (sign > 0) {
                add_triangle(v00, v10, v11);
                add_triangle(v00, v11, v01);
            } else {
                add_triangle(v00, v11, v10);
                add_triangle(v00, v01, v11);
            }
            m_triangle_count += 2;
        }
    }
}

void MeshBuilder::add_box(Vec3d lo, Vec3d hi, double cell, Vec3f albedo, unsigned faces) {
    for (int axis = 0; axis < 3; ++axis) {
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        const Rect2 r{lo[a], hi[a], lo[b], hi[b]};
        if (faces & (1u << (2 * axis))) add_rect(Axis(axis), lo[axis], -1, r, cell, albedo);
        if (faces & (1u << (2 * axis + 1))) add_rect(Axis(axis), hi[axis], +1, r, cell, albedo);
    }
}

void MeshBuilder::add_cylinder(Vec3d base, double r0, double r1, double height, double cell,
                               Vec3f albedo, bool bottom_cap, bool top_cap) {
    SHPRT_CHECK(cell > 0 && height > 0 && r0 >= 0 && r1 >= 0 && r0 + r1 > 0, invalid_argument,
                "add_cylinder: bad dimensions (radii {}, {}, height {}, cell {})", r0, r1, height,
                cell);
    const std::size_t n = std::max<std::size_t>(8, segments(kTwoPi * std::max(r0, r1), cell));
    const double slant = std::hypot(height, r0 - r1);
    const std::size_t rings = segments(slant, cell);
    const std::size_t rings_bottom = segments(r0, cell), rings_top = segments(r1, cell);
    if (m_count_only) {
        m_triangle_count += 2 * n * rings;
        if (bottom_cap && r0 > 0) m_triangle_count += n * (2 * rings_bottom - 1);
        if (top_cap && r1 > 0) m_triangle_count += n * (2 * rings_top - 1);
        return;
    }
    std::vector<double> cs(n), sn(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double phi = kTwoPi * static_cast<double>(k) / static_cast<double>(n);
        cs[k] = std::cos(phi);
        sn[k] = std::sin(phi);
    }
    // Side: rows of n vertices (the seam shares vertices via k + 1 mod n).
    const std::uint32_t side0 = static_cast<std::uint32_t>(m_mesh.positions.size());
    for (std::size_t j = 0; j <= rings; ++j) {
        const double t = static_cast<double>(j) / static_cast<double>(rings);
        const double radius = r0 + (r1 - r0) * t;
        for (std::size_t k = 0; k < n; ++k)
            add_vertex({base.x + radius * cs[k], base.y + height * t, base.z + radius * sn[k]},
                       {height * cs[k], r0 - r1, height * sn[k]}, albedo);
    }
    auto side = [&](std::size_t j, std::size_t k) {
        return side0 + static_cast<std::uint32_t>(j * n + k % n);
    };
    // Angle phi runs from +X toward +Z, i.e. clockwise seen from above; with y up, the quad
    // (j,k) -> (j,k+1) -> (j+1,k+1) is counter-clockwise seen from outside when reversed.
    for (std::size_t j = 0; j < rings; ++j)
        for (std::size_t k = 0; k < n; ++k) {
            add_triangle(side(j, k), side(j + 1, k + 1), side(j, k + 1));
            add_triangle(side(j, k), side(j + 1, k), side(j + 1, k + 1));
            m_triangle_count += 2;
        }
    auto cap = [&](double y, double radius, std::size_t cap_rings, bool up) {
        const Vec3d normal{0, up ? 1.0 : -1.0, 0};
        const std::uint32_t centre = add_vertex({base.x, y, base.z}, normal, albedo);
        const std::uint32_t ring0 = static_cast<std::uint32_t>(m_mesh.positions.size());
        for (std::size_t j = 1; j <= cap_rings; ++j) {
            const double rr = radius * static_cast<double>(j) / static_cast<double>(cap_rings);
            for (std::size_t k = 0; k < n; ++k)
                add_vertex({base.x + rr * cs[k], y, base.z + rr * sn[k]}, normal, albedo);
        }
        auto ring = [&](std::size_t j, std::size_t k) {  // j >= 1
            return ring0 + static_cast<std::uint32_t>((j - 1) * n + k % n);
        };
        // Seen from above (+Y), increasing k turns clockwise, so an upward cap lists k + 1 first.
        auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
            if (up)
                add_triangle(a, c, b);
            else
                add_triangle(a, b, c);
            ++m_triangle_count;
        };
        for (std::size_t k = 0; k < n; ++k) tri(centre, ring(1, k), ring(1, k + 1));
        for (std::size_t j = 1; j < cap_rings; ++j)
            for (std::size_t k = 0; k < n; ++k) {
                tri(ring(j, k), ring(j + 1, k), ring(j + 1, k + 1));
                tri(ring(j, k), ring(j + 1, k + 1), ring(j, k + 1));
            }
    };
    if (bottom_cap && r0 > 0) cap(base.y, r0, rings_bottom, false);
    if (top_cap && r1 > 0) cap(base.y + height, r1, rings_top, true);
}

void MeshBuilder::add_icosphere(Vec3d centre, double radius, int level, Vec3f albedo) {
    SHPRT_CHECK(radius > 0 && level >= 0 && level <= 10, invalid_argument,
                "add_icosphere: bad radius {} or level {}", radius, level);
    if (m_count_only) {
        m_triangle_count += std::size_t{20} << (2 * level);
        return;
    }
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                            {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                            {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3d& p : v) p = normalize(p);
    std::vector<std::array<std::uint32_t, 3>> f = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            v.push_back(normalize(v[a] + v[b]));
            const auto id = static_cast<std::uint32_t>(v.size() - 1);
            midpoint.emplace(key, id);
            return id;
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        next.reserve(f.size() * 4);
        for (const auto& tri : f) {
            const std::uint32_t ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]),
                                ca = mid(tri[2], tri[0]);
            next.push_back({tri[0], ab, ca});
            next.push_back({tri[1], bc, ab});
            next.push_back({tri[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        f = std::move(next);
    }
    const auto first = static_cast<std::uint32_t>(m_mesh.positions.size());
    for (const Vec3d& p : v) add_vertex(centre + p * radius, p, albedo);
    for (const auto& tri : f) {
        add_triangle(first + tri[0], first + tri[1], first + tri[2]);
        ++m_triangle_count;
    }
}

void MeshBuilder::add_sphere(Vec3d centre, double radius, double cell, Vec3f albedo) {
    // Icosahedron edge on the unit sphere: 1 / sin(2 pi / 5); each level halves it (roughly).
    const double edge = radius / std::sin(kTwoPi / 5.0);
    int level = 1;
    while (level < 7 && edge / static_cast<double>(1 << level) > cell) ++level;
    add_icosphere(centre, radius, level, albedo);
}

Mesh MeshBuilder::take_mesh(std::string source) {
    SHPRT_CHECK(!m_count_only, invalid_argument, "take_mesh on a counting MeshBuilder");
    Mesh out = std::move(m_mesh);
    out.source = std::move(source);
    m_mesh = Mesh{};
    m_triangle_count = 0;
    return out;
}

}  // namespace shprt
