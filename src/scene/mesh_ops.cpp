// Vertex normals weighted by area and incident angle: G. Thürmer and C. A. Wüthrich, "Computing
// vertex normals from polygonal facets" (JGT 1998), and N. Max, "Weights for computing vertex
// normals from facet normals" (JGT 1999). Validation and bounds.
#include "shprt/scene/mesh_ops.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

namespace shprt {
namespace {

bool finite(Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Angle between two edges, robust for small and obtuse angles (atan2 of |cross| and dot).
double angle_between(Vec3d a, Vec3d b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

// Accumulates area- and angle-weighted face normals into sums[group[v]] and writes the
// normalised result to every vertex.
void weighted_normals(Mesh& mesh, const std::vector<std::uint32_t>* group, std::size_t groups) {
    std::vector<Vec3d> sums(groups, Vec3d{0, 0, 0});
    const auto& p = mesh.positions;
    for (const auto& t : mesh.triangles) {
        const Vec3d p0 = cast<double>(p[t[0]]), p1 = cast<double>(p[t[1]]),
                    p2 = cast<double>(p[t[2]]);
        // |cross| is twice the area, so the unnormalised cross product carries the area weight.
        const Vec3d face = cross(p1 - p0, p2 - p0);
        if (!(dot(face, face) > 0.0)) continue;
        const double angles[3] = {angle_between(p1 - p0, p2 - p0), angle_between(p2 - p1, p0 - p1),
                                  angle_between(p0 - p2, p1 - p2)};
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t g = group ? (*group)[t[c]] : t[c];
            sums[g] += face * angles[c];
        }
    }
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3d s = sums[group ? (*group)[v] : v];
        const double len = length(s);
        mesh.normals[v] = len > 0.0 && std::isfinite(len) ? cast<float>(s / len) : Vec3f{0, 1, 0};
    }
}

struct PositionKey {
    std::uint32_t x, y, z;
    bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
        h ^= (h >> 29) ^ (k.y * 0xBF58476D1CE4E5B9ull);
        h ^= (h >> 31) ^ (k.z * 0x94D049BB133111EBull);
        return static_cast<std::size_t>(h ^ (h >> 32));
    }
};

}  // namespace

void compute_vertex_normals(Mesh& mesh) { weighted_normals(mesh, nullptr, mesh.positions.size()); }

void compute_vertex_normals_by_position(Mesh& mesh) {
    std::vector<std::uint32_t> group(mesh.positions.size());
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> ids;
    // Not reserved for every vertex: 8 bytes of buckets per vertex (240 MB for the 30 M vertices
    // of an OBJ whose faces share 3 positions) when few positions are distinct; it grows as needed.
    ids.reserve(std::min<std::size_t>(mesh.positions.size(), std::size_t(1) << 16));
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3f p = mesh.positions[v];
        // + 0.0f folds -0 into +0 so the two zeros weld.
        const PositionKey key{std::bit_cast<std::uint32_t>(p.x + 0.0f),
                              std::bit_cast<std::uint32_t>(p.y + 0.0f),
                              std::bit_cast<std::uint32_t>(p.z + 0.0f)};
        group[v] = ids.try_emplace(key, static_cast<std::uint32_t>(ids.size())).first->second;
    }
    weighted_normals(mesh, &group, ids.size());
}

std::optional<std::size_t> bad_brdf_index(const Mesh& mesh) {
    for (std::size_t v = 0; v < mesh.brdf_index.size(); ++v)
        if (mesh.brdf_index[v] != Mesh::kNoBrdf && mesh.brdf_index[v] >= mesh.brdfs.size())
            return v;
    return std::nullopt;
}

std::optional<std::size_t> bad_albedo(const Mesh& mesh) {
    const auto in_range = [](float c) { return c >= 0.0f && c <= 1.0f; };
    for (std::size_t v = 0; v < mesh.albedo.size(); ++v) {
        const Vec3f a = mesh.albedo[v];
        if (!in_range(a.x) || !in_range(a.y) || !in_range(a.z)) return v;
    }
    return std::nullopt;
}

std::optional<std::size_t> zero_normal(const Mesh& mesh) {
    for (std::size_t v = 0; v < mesh.normals.size(); ++v) {
        const Vec3f n = mesh.normals[v];
        const float length2 = n.x * n.x + n.y * n.y + n.z * n.z;
        if (!(length2 > 0.0f) || !std::isfinite(length2)) return v;
    }
    return std::nullopt;
}

std::string describe_brdfs(const Mesh& mesh) {
    if (mesh.brdf_index.empty()) return "none";
    std::vector<std::size_t> count(mesh.brdfs.size() + 1, 0);  // the last: kNoBrdf
    for (std::uint32_t i : mesh.brdf_index) ++count[std::min<std::size_t>(i, mesh.brdfs.size())];
    std::string out;
    for (std::size_t i = 0; i < count.size(); ++i) {
        if (count[i] == 0) continue;
        out += fmt::format("{}{} ({} vert{})", out.empty() ? "" : ", ",
                           i < mesh.brdfs.size() ? to_string(mesh.brdfs[i]) : "none", count[i],
                           count[i] == 1 ? "ex" : "ices");
    }
    return out;
}

void validate_mesh(Mesh& mesh, const std::string& name) {
    const std::size_t nv = mesh.positions.size();
    SHPRT_CHECK(nv > 0, format, "{}: empty mesh (no vertices)", name);
    SHPRT_CHECK(!mesh.triangles.empty(), format, "{}: empty mesh (no triangles)", name);
    SHPRT_CHECK(nv <= std::numeric_limits<std::uint32_t>::max(), invalid_argument,
                "{}: {} vertices exceed the limit of 2^32 - 1", name, nv);
    SHPRT_CHECK(mesh.normals.empty() || mesh.normals.size() == nv, invalid_argument,
                "{}: {} normals for {} vertices", name, mesh.normals.size(), nv);
    SHPRT_CHECK(mesh.albedo.empty() || mesh.albedo.size() == nv, invalid_argument,
                "{}: {} albedo values for {} vertices", name, mesh.albedo.size(), nv);
    SHPRT_CHECK(mesh.source_vertex.empty() || mesh.source_vertex.size() == nv, invalid_argument,
                "{}: {} source_vertex entries for {} vertices", name, mesh.source_vertex.size(),
                nv);
    SHPRT_CHECK(mesh.uvs.empty() || mesh.uvs.size() == nv, invalid_argument,
                "{}: {} texture coordinates for {} vertices", name, mesh.uvs.size(), nv);
    SHPRT_CHECK(mesh.parents.empty() || mesh.parents.size() == nv, invalid_argument,
                "{}: {} vertex parents for {} vertices", name, mesh.parents.size(), nv);
    SHPRT_CHECK(mesh.brdf_index.empty() || mesh.brdf_index.size() == nv, invalid_argument,
                "{}: {} BRDF indices for {} vertices", name, mesh.brdf_index.size(), nv);
    if (const auto v = bad_brdf_index(mesh))
        fail(ErrorCode::format, "{}: vertex {} has BRDF index {} but the scene has {} BRDFs", name,
             *v, mesh.brdf_index[*v], mesh.brdfs.size());

    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3f p = mesh.positions[v];
        SHPRT_CHECK(finite(p), format, "{}: vertex {} has a non-finite coordinate ({}, {}, {})",
                    name, v, p.x, p.y, p.z);
    }
    for (std::size_t v = 0; v < mesh.normals.size(); ++v)
        SHPRT_CHECK(finite(mesh.normals[v]), format, "{}: vertex {} has a non-finite normal", name,
                    v);
    for (std::size_t v = 0; v < mesh.albedo.size(); ++v) {
        Vec3f& a = mesh.albedo[v];
        SHPRT_CHECK(finite(a), format, "{}: vertex {} has a non-finite colour", name, v);
        a = {std::clamp(a.x, 0.0f, 1.0f), std::clamp(a.y, 0.0f, 1.0f), std::clamp(a.z, 0.0f, 1.0f)};
    }

    const std::size_t total = mesh.triangles.size();
    std::size_t kept = 0;
    for (std::size_t t = 0; t < total; ++t) {
        const auto tri = mesh.triangles[t];
        for (std::uint32_t i : tri)
            SHPRT_CHECK(i < nv, format,
                        "{}: triangle {} has vertex index {} out of range (the mesh has {} "
                        "vertices)",
                        name, t, i, nv);
        bool degenerate = tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
        if (!degenerate) {
            const Vec3d p0 = cast<double>(mesh.positions[tri[0]]);
            const Vec3d c = cross(cast<double>(mesh.positions[tri[1]]) - p0,
                                  cast<double>(mesh.positions[tri[2]]) - p0);
            degenerate = !(dot(c, c) > 0.0);
        }
        if (!degenerate) mesh.triangles[kept++] = tri;
    }
    // The failure first: a failure is one line, with no warning before it.
    SHPRT_CHECK(kept > 0, format, "{}: empty mesh (all {} triangles are degenerate)", name, total);
    if (kept < total) {
        mesh.triangles.resize(kept);
        log_warn("{}: dropped {} degenerate triangle{} (of {})", name, total - kept,
                 total - kept == 1 ? "" : "s", total);
    }
}

Bounds mesh_bounds(const Mesh& mesh) {
    if (mesh.positions.empty()) return {{0, 0, 0}, {0, 0, 0}};
    Bounds b{mesh.positions[0], mesh.positions[0]};
    for (const Vec3f& p : mesh.positions) {
        b.lo = vmin(b.lo, p);
        b.hi = vmax(b.hi, p);
    }
    return b;
}

double mesh_surface_area(const Mesh& mesh) {
    double area = 0.0;
    for (const auto& t : mesh.triangles) {
        const Vec3d p0 = cast<double>(mesh.positions[t[0]]);
        area += 0.5 * length(cross(cast<double>(mesh.positions[t[1]]) - p0,
                                   cast<double>(mesh.positions[t[2]]) - p0));
    }
    return area;
}

std::string describe(const Mesh& mesh) {
    const Bounds b = mesh_bounds(mesh);
    return fmt::format(
        "{} vertices, {} triangles\nbounds: [{:.4g}, {:.4g}, {:.4g}] .. [{:.4g}, {:.4g}, {:.4g}]\n"
        "surface area: {:.4g}\n",
        mesh.vertex_count(), mesh.triangle_count(), b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z,
        mesh_surface_area(mesh));
}

}  // namespace shprt
