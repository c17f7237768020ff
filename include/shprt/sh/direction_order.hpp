// A spatially coherent order of a direction set, for tracing: rays from one origin whose
// directions follow each other along a space-filling curve share most of their BVH traversal,
// so Embree casts them faster (the room, 1 thread: the same rays in a shuffled order cost
// 24–33 % more; issue 39). The order is a permutation only: a bake traces in this order and
// writes each answer at the direction's own index, so the set, its nested prefixes and the
// projection's bits do not change.
//  * Octahedral map: E. Praun, H. Hoppe, "Spherical parametrization and remeshing", SIGGRAPH
//    2003; Q. Meyer et al., "On floating-point normal vectors", EGSR 2010.
//  * Hilbert index: the cell → index loop of J. Skilling, "Programming the Hilbert curve", AIP
//    Conf. Proc. 707, 2004 (the usual xy2d form).
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/sh/sampler.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace shprt {

// Cells per side of the octahedral square: 2^16 (keys of 32 bits).
inline constexpr int kHilbertOrder = 16;

// Index of cell (x, y), 0 ≤ x, y < 2^16, along the Hilbert curve over the 2^16 × 2^16 grid:
// consecutive indices are edge-adjacent cells.
SHPRT_HD_INLINE std::uint32_t hilbert_index(std::uint32_t x, std::uint32_t y) {
    std::uint32_t d = 0;
    for (std::uint32_t s = std::uint32_t(1) << (kHilbertOrder - 1); s > 0; s /= 2) {
        const std::uint32_t rx = (x & s) ? 1u : 0u, ry = (y & s) ? 1u : 0u;
        d += s * s * ((3u * rx) ^ ry);
        x &= s - 1;
        y &= s - 1;
        // Turn the quadrant so that the curve inside it runs from its entry to its exit.
        if (ry == 0) {
            if (rx == 1) {
                x = s - 1 - x;
                y = s - 1 - y;
            }
            const std::uint32_t t = x;
            x = y;
            y = t;
        }
    }
    return d;
}

// Key of the direction (x, y, z) along the Hilbert curve over its octahedral map:
// p = d / (|x| + |y| + |z|), the lower hemisphere (z < 0) folded out to the corners as
// (sign(x)·(1 − |y|), sign(y)·(1 − |x|)), the square [−1, 1]² cut into 2^16 × 2^16 cells. Nearby
// keys are nearby directions. A pure function of the float bits of (x, y, z); the zero vector
// gets key 0.
SHPRT_HD_INLINE std::uint32_t octahedral_hilbert_key(float x, float y, float z) {
    const float l1 = std::fabs(x) + std::fabs(y) + std::fabs(z);
    if (!(l1 > 0.0f)) return 0;
    float u = x / l1, v = y / l1;
    if (z < 0.0f) {
        const float fu = (1.0f - std::fabs(v)) * (u < 0.0f ? -1.0f : 1.0f);
        const float fv = (1.0f - std::fabs(u)) * (v < 0.0f ? -1.0f : 1.0f);
        u = fu;
        v = fv;
    }
    constexpr float kSide = float(std::uint32_t(1) << kHilbertOrder);
    const auto cell = [](float t) {
        const float c = (t + 1.0f) * 0.5f * kSide;
        return static_cast<std::uint32_t>(c < 0.0f ? 0.0f : c > kSide - 1.0f ? kSide - 1.0f : c);
    };
    return hilbert_index(cell(u), cell(v));
}

// The permutation that sorts `set` by octahedral_hilbert_key (ties by index): order[i] is the
// index in `set` of the i-th direction to trace. Host only, single-threaded (a sort of S keys);
// the same set gives the same order on every machine.
std::vector<std::uint32_t> coherent_order(const DirectionSet& set);
// The same within each new segment of the nested prefixes [0, P), [P, 2P), [2P, 4P), … (the
// last one cut at the set's size): positions [a, b) of the order hold the indices [a, b), sorted
// by key, so that an error-bounded bake traces one segment as one coherent stream. P ≥ 1.
std::vector<std::uint32_t> coherent_order(const DirectionSet& set, std::size_t first_prefix);

}  // namespace shprt
