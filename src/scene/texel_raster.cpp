// Texel samples (texel_raster.hpp): conservative rasterisation of a mesh's triangles in UV space
// (T. Akenine-Möller and T. Aila, "Conservative and Tiled Rasterization Using a Modified Triangle
// Setup", JGT 10(3), 2005: the edge function tested at the texel corner most inside the edge),
// barycentric interpolation of position, normal and albedo.
#include "shprt/scene/texel_raster.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

namespace shprt {
namespace {

struct UvPoint {
    double x, y;
};

double cross2(UvPoint a, UvPoint b) { return a.x * b.y - a.y * b.x; }
UvPoint sub(UvPoint a, UvPoint b) { return {a.x - b.x, a.y - b.y}; }

// A triangle in texel space (x right, y down; texel (x, y) is the unit square at (x, y)).
struct UvTriangle {
    std::array<UvPoint, 3> p;
    double area2 = 0;  // twice the signed area
    double sign = 1;   // of area2: edge functions are multiplied by it so inside is positive

    // Barycentrics of `q`: (λ_0, λ_1, λ_2), summing to 1.
    std::array<double, 3> barycentric(UvPoint q) const {
        const double inv = 1.0 / std::abs(area2);
        return {sign * cross2(sub(p[2], p[1]), sub(q, p[1])) * inv,
                sign * cross2(sub(p[0], p[2]), sub(q, p[2])) * inv,
                sign * cross2(sub(p[1], p[0]), sub(q, p[0])) * inv};
    }
    // Whether the unit texel square centred at `c` overlaps the triangle (closed test).
    bool overlaps_texel(UvPoint c) const {
        for (int e = 0; e < 3; ++e) {
            const UvPoint a = p[e], b = p[(e + 1) % 3];
            const UvPoint d = sub(b, a);
            const double f = sign * cross2(d, sub(c, a)) + 0.5 * (std::abs(d.x) + std::abs(d.y));
            if (f < 0) return false;
        }
        return true;
    }
};

// Triangle `t` of `mesh` in the texel space of a W × H image.
UvTriangle uv_triangle(const Mesh& mesh, std::size_t t, std::size_t W, std::size_t H) {
    UvTriangle tri;
    for (int k = 0; k < 3; ++k) {
        const auto& uv = mesh.uvs[mesh.triangles[t][k]];
        tri.p[k] = {double(uv[0]) * double(W), (1.0 - double(uv[1])) * double(H)};
    }
    tri.area2 = cross2(sub(tri.p[1], tri.p[0]), sub(tri.p[2], tri.p[0]));
    tri.sign = tri.area2 < 0 ? -1.0 : 1.0;
    return tri;
}

// A centre with every barycentric above this lies strictly inside (not on a shared edge).
constexpr double kStrictlyInside = 1e-4;
// A centre with every barycentric above this lies inside or on the boundary.
constexpr double kInside = -1e-9;

// Coverage of a width × height image by `mesh`'s triangles in UV space: each texel's owner (see
// the top of texel_raster.hpp), and the overlaps found, in triangle order, up to `most` (owner
// is then incomplete).
std::vector<UvOverlap> cover_texels(const Mesh& mesh, int width, int height,
                                    const std::string& name, std::vector<std::int32_t>& owner,
                                    std::size_t most) {
    std::vector<UvOverlap> overlaps;
    SHPRT_CHECK(
        mesh.uvs.size() == mesh.vertex_count() && mesh.normals.size() == mesh.vertex_count(),
        invalid_argument, "{}: {} UVs and {} normals for {} vertices", name, mesh.uvs.size(),
        mesh.normals.size(), mesh.vertex_count());
    SHPRT_CHECK(width >= 1 && height >= 1 && width <= kMaxTexelSide && height <= kMaxTexelSide,
                invalid_argument, "texel resolution {}x{}: each side must be 1 to {}", width,
                height, kMaxTexelSide);
    const std::size_t W = std::size_t(width), H = std::size_t(height);
    owner.assign(W * H, -1);
    std::vector<std::uint8_t> owner_inside(W * H, 0), owner_strict(W * H, 0);
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const UvTriangle tri = uv_triangle(mesh, t, W, H);
        for (const UvPoint& q : tri.p)
            SHPRT_CHECK(std::isfinite(q.x) && std::isfinite(q.y), invalid_argument,
                        "{}: triangle {} has a non-finite texture coordinate", name, t);
        if (!(std::abs(tri.area2) > 1e-12)) continue;  // no area in UV space: no texel of its own
        double lo_x = tri.p[0].x, hi_x = lo_x, lo_y = tri.p[0].y, hi_y = lo_y;
        for (const UvPoint& q : tri.p) {
            lo_x = std::min(lo_x, q.x), hi_x = std::max(hi_x, q.x);
            lo_y = std::min(lo_y, q.y), hi_y = std::max(hi_y, q.y);
        }
        const auto x0 = static_cast<long long>(std::max(0.0, std::floor(lo_x)));
        const auto x1 = static_cast<long long>(std::min(double(W) - 1, std::ceil(hi_x) - 1));
        const auto y0 = static_cast<long long>(std::max(0.0, std::floor(lo_y)));
        const auto y1 = static_cast<long long>(std::min(double(H) - 1, std::ceil(hi_y) - 1));
        for (long long y = y0; y <= y1; ++y)
            for (long long x = x0; x <= x1; ++x) {
                const UvPoint c{double(x) + 0.5, double(y) + 0.5};
                if (!tri.overlaps_texel(c)) continue;
                const auto l = tri.barycentric(c);
                const double least = std::min({l[0], l[1], l[2]});
                const bool inside = least >= kInside, strict = least > kStrictlyInside;
                const std::size_t i = std::size_t(y) * W + std::size_t(x);
                if (strict && owner_strict[i]) {
                    overlaps.push_back({std::uint32_t(owner[i]), std::uint32_t(t), int(x), int(y)});
                    if (overlaps.size() >= most) return overlaps;
                    continue;
                }
                if (owner[i] < 0 || (inside && !owner_inside[i])) {
                    owner[i] = static_cast<std::int32_t>(t);
                    owner_inside[i] = inside;
                }
                owner_strict[i] |= strict;
            }
    }
    return overlaps;
}

std::string mesh_name(const Mesh& mesh) {
    return mesh.source.empty() ? std::string("mesh") : mesh.source;
}

}  // namespace

std::vector<UvOverlap> find_uv_overlaps(const Mesh& mesh, int width, int height, std::size_t most) {
    SHPRT_CHECK(!mesh.uvs.empty(), invalid_argument, "{}: has no texture coordinates",
                mesh_name(mesh));
    std::vector<std::int32_t> owner;
    return cover_texels(mesh, width, height, mesh_name(mesh), owner, most);
}

TexelSamples rasterize_texels(const Mesh& mesh, int width, int height, int uv_set) {
    const std::string name = mesh_name(mesh);
    SHPRT_CHECK(!mesh.uvs.empty(), invalid_argument,
                "{}: has no texture coordinates (UV set {}); per-texel transfer needs a UV atlas "
                "(--unwrap makes one)",
                name, uv_set);
    std::vector<std::int32_t> owner;
    if (const auto found = cover_texels(mesh, width, height, name, owner, 1); !found.empty()) {
        const UvOverlap* o = &found[0];
        fail(ErrorCode::invalid_argument,
             "{}: triangles {} and {} overlap in UV space at texel ({}, {}) of {}x{}; per-texel "
             "transfer needs a UV atlas without overlaps",
             name, o->first, o->second, o->x, o->y, width, height);
    }
    const std::size_t W = std::size_t(width), H = std::size_t(height);
    const auto uv_triangle = [&](std::size_t t) { return shprt::uv_triangle(mesh, t, W, H); };

    TexelSamples out;
    out.width = width;
    out.height = height;
    const bool has_albedo = mesh.albedo.size() == mesh.vertex_count();
    for (std::size_t i = 0; i < W * H; ++i) {
        if (owner[i] < 0) continue;
        const auto t = static_cast<std::size_t>(owner[i]);
        const UvTriangle tri = uv_triangle(t);
        auto l = tri.barycentric({double(i % W) + 0.5, double(i / W) + 0.5});
        double sum = 0;
        for (double& x : l) sum += (x = std::max(0.0, x));
        for (double& x : l) x /= sum;
        Vec3d p{0, 0, 0}, n{0, 0, 0}, a{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[t][k];
            p = p + cast<double>(mesh.positions[v]) * l[k];
            n = n + cast<double>(mesh.normals[v]) * l[k];
            if (has_albedo) a = a + cast<double>(mesh.albedo[v]) * l[k];
        }
        if (!(length(n) > 0)) {  // opposite normals cancel: the face's own
            const auto& tr = mesh.triangles[t];
            n = cross(cast<double>(mesh.positions[tr[1]]) - cast<double>(mesh.positions[tr[0]]),
                      cast<double>(mesh.positions[tr[2]]) - cast<double>(mesh.positions[tr[0]]));
        }
        if (!(length(n) > 0)) n = {0, 1, 0};
        out.texel.push_back(static_cast<std::uint32_t>(i));
        out.positions.push_back(cast<float>(p));
        out.normals.push_back(cast<float>(normalize(n)));
        out.albedo.push_back(cast<float>(a));
        out.triangle.push_back(static_cast<std::uint32_t>(t));
    }
    SHPRT_CHECK(!out.texel.empty(), invalid_argument,
                "{}: no texel of the {}x{} image is covered (UVs outside [0, 1]?)", name, width,
                height);
    return out;
}

}  // namespace shprt
