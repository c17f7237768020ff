// Polygon triangulation by ear clipping (G. H. Meisters, "Polygons have ears", 1975), in the
// plane of the Newell normal (M. E. Newell; see Sutherland, Sproull and Schumacker 1974).
#include "shprt/scene/polygon.hpp"

#include <cmath>

namespace shprt {
namespace {

constexpr std::size_t kMaxEarClipCorners = 1000;  // O(n^3) worst case beyond this is not worth it

struct P2 {
    double x, y;
};

double orient(P2 a, P2 b, P2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// Inside or on the boundary of the counter-clockwise triangle (a, b, c).
bool in_triangle(P2 p, P2 a, P2 b, P2 c) {
    return orient(a, b, p) >= 0.0 && orient(b, c, p) >= 0.0 && orient(c, a, p) >= 0.0;
}

void fan(std::span<const std::uint32_t> polygon, std::vector<std::array<std::uint32_t, 3>>& out) {
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
        out.push_back({polygon[0], polygon[i], polygon[i + 1]});
}

}  // namespace

void triangulate_polygon(std::span<const Vec3f> positions, std::span<const std::uint32_t> polygon,
                         std::vector<std::array<std::uint32_t, 3>>& out) {
    const std::size_t n = polygon.size();
    if (n < 3) return;
    if (n == 3 || n > kMaxEarClipCorners) return fan(polygon, out);

    Vec3d normal{0, 0, 0};  // Newell: robust for non-planar and concave polygons
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3d a = cast<double>(positions[polygon[i]]);
        const Vec3d b = cast<double>(positions[polygon[(i + 1) % n]]);
        normal +=
            Vec3d{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    }
    const double len = length(normal);
    if (!(len > 0.0) || !std::isfinite(len)) return fan(polygon, out);
    normal = normal / len;
    // A frame (u, v) with u x v = normal, so the polygon runs counter-clockwise in it.
    const Vec3d helper = std::abs(normal.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    const Vec3d u = normalize(cross(helper, normal));
    const Vec3d v = cross(normal, u);
    std::vector<P2> p(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3d q = cast<double>(positions[polygon[i]]);
        p[i] = {dot(q, u), dot(q, v)};
    }

    std::vector<std::size_t> rest(n);
    for (std::size_t i = 0; i < n; ++i) rest[i] = i;
    while (rest.size() > 3) {
        const std::size_t m = rest.size();
        bool clipped = false;
        // Trying corner 1 first makes a convex polygon come out as the fan from corner 0.
        for (std::size_t k = 1; k <= m && !clipped; ++k) {
            const std::size_t ia = rest[k - 1], ib = rest[k % m], ic = rest[(k + 1) % m];
            if (!(orient(p[ia], p[ib], p[ic]) > 0.0)) continue;  // reflex or flat corner
            bool empty = true;
            for (std::size_t j : rest)
                if (j != ia && j != ib && j != ic && in_triangle(p[j], p[ia], p[ib], p[ic])) {
                    empty = false;
                    break;
                }
            if (!empty) continue;
            out.push_back({polygon[ia], polygon[ib], polygon[ic]});
            rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(k % m));
            clipped = true;
        }
        if (!clipped) {  // no ear: self-intersecting or degenerate; cover what is left
            std::vector<std::uint32_t> left;
            for (std::size_t j : rest) left.push_back(polygon[j]);
            return fan(left, out);
        }
    }
    out.push_back({polygon[rest[0]], polygon[rest[1]], polygon[rest[2]]});
}

}  // namespace shprt
