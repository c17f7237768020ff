// Test helpers for the scene tests: a mesh validity check and a brute-force ray cast over all
// triangles (the slow reference the tracing code is compared with elsewhere).
#pragma once

#include "common/ray_triangle.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace shprt::test {

constexpr float kUnitTol = 1e-5f;       // |n| - 1 for stored float normals
constexpr float kWindingMinCos = 0.5f;  // face normal . vertex normal (smooth cylinders: 0.92)

// Checks what every generated mesh promises: finite data, unit normals, albedo in [0, 1],
// indices in range, every vertex used, no degenerate triangle, winding agreeing with normals.
inline void expect_valid_generated(const Mesh& m) {
    ASSERT_GT(m.vertex_count(), 0u);
    ASSERT_EQ(m.normals.size(), m.vertex_count());
    ASSERT_EQ(m.albedo.size(), m.vertex_count());
    EXPECT_TRUE(m.source_vertex.empty());
    std::size_t bad_normals = 0, bad_albedo = 0, bad_winding = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const Vec3f p = m.positions[v], n = m.normals[v], a = m.albedo[v];
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << v;
        if (!(std::abs(length(n) - 1.0f) < kUnitTol)) ++bad_normals;
        for (int c = 0; c < 3; ++c)
            if (!(a[c] >= 0.0f && a[c] <= 1.0f)) ++bad_albedo;
    }
    EXPECT_EQ(bad_normals, 0u);
    EXPECT_EQ(bad_albedo, 0u);
    std::vector<bool> used(m.vertex_count(), false);
    for (const auto& t : m.triangles) {
        for (std::uint32_t i : t) {
            ASSERT_LT(i, m.vertex_count());
            used[i] = true;
        }
        const Vec3d p0 = cast<double>(m.positions[t[0]]);
        const Vec3d c =
            cross(cast<double>(m.positions[t[1]]) - p0, cast<double>(m.positions[t[2]]) - p0);
        ASSERT_GT(length(c), 0.0) << "degenerate triangle";
        const Vec3f fn = cast<float>(normalize(c));
        for (std::uint32_t i : t)
            if (!(dot(fn, m.normals[i]) > kWindingMinCos)) ++bad_winding;
    }
    EXPECT_EQ(bad_winding, 0u) << "triangle corners whose winding disagrees with the normal";
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "unused vertices";
    Mesh copy = m;
    validate_mesh(copy, m.source);
    EXPECT_EQ(copy.triangle_count(), m.triangle_count());
}

// Closest hit distance along origin + t * dir, t > t_min, over all triangles (double-precision
// Moller-Trumbore); nullopt when the ray escapes.
inline std::optional<double> brute_force_hit(const Mesh& m, Vec3d origin, Vec3d dir,
                                             double t_min = 1e-9) {
    std::optional<double> best;
    for (const auto& t : m.triangles) {
        const Vec3d p0 = cast<double>(m.positions[t[0]]);
        const auto h = intersect_triangle(origin, dir, p0, cast<double>(m.positions[t[1]]) - p0,
                                          cast<double>(m.positions[t[2]]) - p0);
        if (h && h->t > t_min && (!best || h->t < *best)) best = h->t;
    }
    return best;
}

// SplitMix64 uniform doubles in [0, 1) for reproducible Monte Carlo checks.
class TestRng {
public:
    explicit TestRng(std::uint64_t seed) : m_state(seed) {}
    double next() {
        std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
    }

private:
    std::uint64_t m_state;
};

}  // namespace shprt::test
