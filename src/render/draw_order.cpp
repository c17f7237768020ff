#include "shprt/render/draw_order.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/scene/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace shprt {

Vec3f draw_order_direction(int i) {
    SHPRT_CHECK(i >= 0 && i < kDrawOrderCount, invalid_argument, "draw order {} is not below {}", i,
                kDrawOrderCount);
    if (i < 6) {
        Vec3f d{0, 0, 0};
        const float sign = (i & 1) != 0 ? 1.0f : -1.0f;
        (i < 2 ? d.x : i < 4 ? d.y : d.z) = sign;
        return d;
    }
    const int c = i - 6;
    const float s = 1.0f / std::sqrt(3.0f);
    return {(c & 1) != 0 ? s : -s, (c & 2) != 0 ? s : -s, (c & 4) != 0 ? s : -s};
}

int draw_order_for(Vec3f forward) {
    int best = 0;
    float best_cos = -2.0f;
    for (int i = 0; i < kDrawOrderCount; ++i) {
        const float c = dot(forward, draw_order_direction(i));
        if (c > best_cos) {
            best_cos = c;
            best = i;
        }
    }
    return best;
}

bool draw_orders_fit(std::size_t triangles) {
    return triangles <= kMaxDrawOrderBytes / (kDrawOrderCount * 3 * sizeof(std::uint32_t));
}

std::vector<std::uint32_t> directional_draw_orders(const Mesh& mesh) {
    const std::size_t T = mesh.triangles.size();
    std::vector<Vec3f> centroid(T);
    for (std::size_t t = 0; t < T; ++t) {
        const auto& tri = mesh.triangles[t];
        centroid[t] = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) *
                      (1.0f / 3.0f);
    }
    std::vector<std::uint32_t> out(std::size_t(kDrawOrderCount) * T * 3);
    parallel_for(0, kDrawOrderCount, 1, Split::fixed, [&](std::size_t first, std::size_t last) {
        std::vector<std::pair<float, std::uint32_t>> key(T);
        for (std::size_t i = first; i != last; ++i) {
            const Vec3f d = draw_order_direction(int(i));
            for (std::size_t t = 0; t < T; ++t) key[t] = {dot(centroid[t], d), std::uint32_t(t)};
            std::stable_sort(key.begin(), key.end(),
                             [](const auto& a, const auto& b) { return a.first < b.first; });
            std::uint32_t* o = out.data() + i * T * 3;
            for (const auto& [depth, t] : key)
                for (int v = 0; v < 3; ++v) *o++ = mesh.triangles[t][v];
        }
    });
    return out;
}

}  // namespace shprt
