// Probe grids built in tests (transfer/probes.hpp): each probe's matrix a multiple of the identity
// — an unoccluded point under the distant light, dimmed by `brightness(probe position)`.
#pragma once

#include "shprt/transfer/probes.hpp"

#include <functional>

namespace shprt::test {

inline ProbeGrid identity_probe_grid(Vec3f origin, Vec3f spacing, std::array<int, 3> counts, int K,
                                     const std::function<float(Vec3f)>& brightness = {}) {
    ProbeGrid g;
    g.origin = origin;
    g.spacing = spacing;
    g.counts = counts;
    g.K = K;
    g.channels = 1;
    g.matrices.assign(g.count() * std::size_t(K) * std::size_t(K), 0.0f);
    g.valid.assign(g.count(), 1);
    for (int z = 0; z < counts[2]; ++z)
        for (int y = 0; y < counts[1]; ++y)
            for (int x = 0; x < counts[0]; ++x) {
                const std::size_t probe = g.index(x, y, z);
                const float b = brightness ? brightness(g.position(x, y, z)) : 1.0f;
                float* m = g.matrices.data() + probe * std::size_t(K) * std::size_t(K);
                for (int i = 0; i < K; ++i) m[i * K + i] = b;
            }
    g.validate();
    return g;
}

}  // namespace shprt::test
