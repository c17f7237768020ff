// Transfer probes (issue 37, docs/probes.md): a regular grid of points in the scene's volume, each
// with a transfer matrix from the distant light's SH to the SH of the radiance *arriving* at that
// point (occluded by the scene; with interreflected transfer, including the light it bounces).
// Things that move through the baked scene — objects that were not baked with it — are lit from
// the probes interpolated at their position: L_in(p) = P(p)·L.
//
// Probe (x, y, z), 0 ≤ x < nx, …, sits at origin + (x·spacing.x, y·spacing.y, z·spacing.z) and is
// number x + nx·(y + ny·z). Its matrix per channel is K×K, row-major, [out][in]:
//
//     matrices[(probe·channels + channel)·K·K + i·K + j]  (i: radiance coefficient, j: light's)
//
// A probe inside geometry (most of its directions see back faces) is invalid: its matrix is zero
// and interpolation skips it.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/transfer/cpca_code.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

// Most probes along one axis and in all (the bake's and the file reader's bound).
inline constexpr int kMaxProbeSide = 1024;
inline constexpr std::size_t kMaxProbes = std::size_t(1) << 22;

struct ProbeGrid {
    Vec3f origin{0, 0, 0};
    Vec3f spacing{1, 1, 1};              // each > 0
    std::array<int, 3> counts{0, 0, 0};  // nx, ny, nz ≥ 1 (all 0: no probes)
    int K = 9;                           // SH size of the light in and the radiance out
    int channels = 1;                    // 1, or 3 (RGB: interreflected transfer with an albedo)
    std::vector<float> matrices;         // count() · channels · K · K
    std::vector<std::uint8_t> valid;     // count(): 1 valid, 0 inside geometry
    // Empty, or the CPCA code the matrices were rebuilt from (compress_probes, transfer/cpca.hpp):
    // one row per valid probe, in probe order; a file stores it instead of the matrices.
    CpcaCode cpca;

    bool empty() const { return counts[0] == 0; }
    std::size_t count() const {
        return std::size_t(counts[0]) * std::size_t(counts[1]) * std::size_t(counts[2]);
    }
    std::size_t index(int x, int y, int z) const {
        return std::size_t(x) +
               std::size_t(counts[0]) * (std::size_t(y) + std::size_t(counts[1]) * std::size_t(z));
    }
    Vec3f position(int x, int y, int z) const {
        return {origin.x + float(x) * spacing.x, origin.y + float(y) * spacing.y,
                origin.z + float(z) * spacing.z};
    }
    Vec3f far_corner() const { return position(counts[0] - 1, counts[1] - 1, counts[2] - 1); }
    const float* matrix(std::size_t probe, int channel = 0) const {
        return matrices.data() + (probe * std::size_t(channels) + std::size_t(channel)) *
                                     std::size_t(K) * std::size_t(K);
    }
    // Throws Error(invalid_argument) naming the problem: counts, spacing, K, channels or the
    // arrays' sizes inconsistent.
    void validate() const;
    bool operator==(const ProbeGrid&) const = default;
};

// The grid in one line, for people (`shprt info`, `shprt bake`): "16x6x16 = 1536 (1212 valid),
// spacing 0.5 x 0.5 x 0.5 m, from (x, y, z) to (x, y, z); K = 9 (9x9 matrices), 1 channel", and
// "; CPCA 64 clusters x 8 vectors" for a grid stored as a code.
std::string describe_probes(const ProbeGrid& grid);

// The probes' matrices interpolated at `p`: trilinear over the (up to 8) probes of the cell that
// holds p, the weights of invalid probes dropped and the rest renormalised. A point outside the
// grid is clamped to it first (`clamped`). When every probe of the cell is invalid, the nearest
// valid probe is used (`fallback`); with no valid probe at all the matrix is zero (`no_valid`).
struct ProbeSample {
    std::vector<float> matrix;  // channels · K · K, as one probe's
    bool clamped = false, fallback = false, no_valid = false;
};
ProbeSample sample_probes(const ProbeGrid& grid, Vec3f p);

}  // namespace shprt
