// Small meshes, ray sets and a brute-force reference for the tracing tests. Self-contained on
// purpose (no dependence on the scene area's built-ins).
#pragma once

#include "shprt/scene/mesh.hpp"
#include "shprt/trace/ray.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace shprt::test {

inline std::uint32_t add_vertex(Mesh& m, Vec3f p, Vec3f n) {
    m.positions.push_back(p);
    m.normals.push_back(n);
    m.albedo.push_back({0.5f, 0.5f, 0.5f});
    return static_cast<std::uint32_t>(m.positions.size() - 1);
}

// A grid of (n+1)² vertices spanning origin + [0,1]²·(eu, ev), two triangles per cell, all
// facing `normal` (counter-clockwise seen from the normal's side when normal = eu × ev).
// Vertices are computed as origin + i/n·eu + j/n·ev in float, so a tilted grid is only planar
// to rounding.
inline void add_grid(Mesh& m, Vec3f origin, Vec3f eu, Vec3f ev, Vec3f normal, int n) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float s = static_cast<float>(i) / static_cast<float>(n);
            const float t = static_cast<float>(j) / static_cast<float>(n);
            add_vertex(m, origin + eu * s + ev * t, normal);
        }
    const auto row = static_cast<std::uint32_t>(n + 1);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t v00 = base + static_cast<std::uint32_t>(j) * row + i;
            const std::uint32_t v10 = v00 + 1, v01 = v00 + row, v11 = v01 + 1;
            m.triangles.push_back({v00, v10, v11});
            m.triangles.push_back({v00, v11, v01});
        }
}

// Horizontal plane y = height over [x0, x0+size] × [z0, z0+size], normal +Y.
inline Mesh make_plane(int n, float size, float height, float x0 = 0, float z0 = 0) {
    Mesh m;
    m.source = "test:plane";
    add_grid(m, {x0, height, z0 + size}, {size, 0, 0}, {0, 0, -size}, {0, 1, 0}, n);
    return m;
}

// A unit-ish tilted plane: spanned by two non-axis vectors, its unit normal returned in `normal`.
inline Mesh make_tilted_plane(int n, Vec3f& normal) {
    Mesh m;
    m.source = "test:tilted-plane";
    const Vec3d u{0.8, 0.35, 0.1}, v{-0.15, 0.3, -0.9};
    const Vec3d nd = normalize(cross(u, v));
    normal = cast<float>(nd);
    add_grid(m, {-0.3f, 0.7f, 0.2f}, cast<float>(u) * 2.0f, cast<float>(v) * 2.0f, normal, n);
    return m;
}

// An axis-aligned box [lo, hi] with unshared vertices per face (hard edges), each face an n×n
// grid facing outwards. Without a bottom face when `bottom` is false (a box resting on a floor:
// a bottom face would be coplanar with the floor, and closest hits there would tie).
inline void add_box(Mesh& m, Vec3f lo, Vec3f hi, int n, bool bottom = true) {
    const Vec3f e = hi - lo;
    add_grid(m, {lo.x, lo.y, hi.z}, {e.x, 0, 0}, {0, e.y, 0}, {0, 0, 1}, n);               // +Z
    add_grid(m, {hi.x, lo.y, lo.z}, {-e.x, 0, 0}, {0, e.y, 0}, {0, 0, -1}, n);             // -Z
    add_grid(m, {hi.x, lo.y, hi.z}, {0, 0, -e.z}, {0, e.y, 0}, {1, 0, 0}, n);              // +X
    add_grid(m, {lo.x, lo.y, lo.z}, {0, 0, e.z}, {0, e.y, 0}, {-1, 0, 0}, n);              // -X
    add_grid(m, {lo.x, hi.y, hi.z}, {e.x, 0, 0}, {0, 0, -e.z}, {0, 1, 0}, n);              // +Y
    if (bottom) add_grid(m, {lo.x, lo.y, lo.z}, {e.x, 0, 0}, {0, 0, e.z}, {0, -1, 0}, n);  // -Y
}

// A tessellated plane [-2, 2]² at y = 0 with a box [-0.53, 0.47] × [0, 0.8] × [-0.41, 0.58]
// on it, placed off the floor grid so no floor vertex lies on a box face
// (no bottom face).
inline Mesh make_box_on_plane() {
    Mesh m = make_plane(24, 4.0f, 0.0f, -2.0f, -2.0f);
    m.source = "test:box-on-plane";
    add_box(m, {-0.53f, 0.0f, -0.41f}, {0.47f, 0.8f, 0.58f}, 6, false);
    return m;
}

// `count` random triangles in [0, 1]³ with edge lengths up to `max_edge`, plus a few long
// slivers that exercise spatial splits.
inline Mesh make_triangle_soup(int count, float max_edge, std::uint32_t seed) {
    Mesh m;
    m.source = "test:soup";
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), edge(-max_edge, max_edge);
    for (int t = 0; t < count; ++t) {
        const Vec3f a{unit(rng), unit(rng), unit(rng)};
        Vec3f b = a + Vec3f{edge(rng), edge(rng), edge(rng)};
        Vec3f c = a + Vec3f{edge(rng), edge(rng), edge(rng)};
        if (t % 50 == 0) {  // a long sliver
            b = Vec3f{unit(rng), unit(rng), unit(rng)};
            c = b + Vec3f{edge(rng), edge(rng), edge(rng)} * 0.1f;
        }
        const Vec3f n = cross(b - a, c - a);
        const float len = length(n);
        const Vec3f nn = len > 0 ? n / len : Vec3f{0, 1, 0};
        const std::uint32_t ia = add_vertex(m, a, nn), ib = add_vertex(m, b, nn),
                            ic = add_vertex(m, c, nn);
        m.triangles.push_back({ia, ib, ic});
    }
    return m;
}

// Uniform direction on the sphere.
template <class Rng>
Vec3f random_direction(Rng& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float z = 1.0f - 2.0f * u(rng);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 6.2831853f * u(rng);
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// An orthonormal frame (t, b) around unit n.
inline void make_frame(Vec3d n, Vec3d& t, Vec3d& b) {
    const Vec3d helper = std::fabs(n.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    t = normalize(cross(helper, n));
    b = cross(n, t);
}

// `count` directions in the open upper hemisphere of unit n: a first part random (cosine of the
// polar angle uniform), the rest grazing, with n·d from 1e-1 down to 1e-7. Each direction is
// checked in double to lie strictly above the plane orthogonal to n.
inline std::vector<Vec3f> hemisphere_directions(Vec3f n_f, int count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Vec3d n = normalize(cast<double>(n_f));
    Vec3d t, b;
    make_frame(n, t, b);
    std::vector<Vec3f> dirs;
    const int grazing = count / 4;
    const double kGrazing[] = {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
    while (static_cast<int>(dirs.size()) < count) {
        const int i = static_cast<int>(dirs.size());
        const double cos_theta = i < count - grazing ? u(rng) : kGrazing[i % 7] * (0.5 + u(rng));
        const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
        const double phi = 6.283185307179586 * u(rng);
        const Vec3d d =
            t * (sin_theta * std::cos(phi)) + b * (sin_theta * std::sin(phi)) + n * cos_theta;
        const Vec3f df = cast<float>(d);
        if (dot(cast<double>(df), n) > 0.0) dirs.push_back(df);
    }
    return dirs;
}

// Brute force over every triangle with the same watertight test the BVH uses.
inline Hit brute_force_intersect(const Mesh& m, Vec3f o, Vec3f d, float tmin, float tmax) {
    const WatertightRay r = make_watertight_ray(o, d);
    Hit best{false, kNoTriangle, tmax, 0, 0};
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
        const auto& tri = m.triangles[i];
        float t, u, v;
        if (intersect_triangle_watertight(r, m.positions[tri[0]], m.positions[tri[1]],
                                          m.positions[tri[2]], tmin, best.t, t, u, v))
            best = Hit{true, static_cast<std::uint32_t>(i), t, u, v};
    }
    return best;
}

}  // namespace shprt::test
