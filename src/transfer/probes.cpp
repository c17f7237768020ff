#include "shprt/transfer/probes.hpp"

#include "shprt/core/error.hpp"
#include "shprt/transfer/transfer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shprt {

void ProbeGrid::validate() const {
    for (int a = 0; a < 3; ++a) {
        if (counts[a] < 1) {
            throw Error(ErrorCode::invalid_argument, "probe grid: every count must be at least 1");
        }
        if (!(spacing[a] > 0) || !std::isfinite(spacing[a])) {
            throw Error(ErrorCode::invalid_argument, "probe grid: every spacing must be positive");
        }
    }
    if (K < 1 || K > kMaxTransferK) {
        throw Error(ErrorCode::invalid_argument, "probe grid: K out of range");
    }
    if (channels != 1 && channels != 3) {
        throw Error(ErrorCode::invalid_argument, "probe grid: channels must be 1 or 3");
    }
    if (matrices.size() != count() * std::size_t(channels) * std::size_t(K) * std::size_t(K) ||
        valid.size() != count()) {
        throw Error(ErrorCode::invalid_argument, "probe grid: arrays do not match the grid's size");
    }
    // Its code, if it has one: one row per valid probe.
    std::size_t n = 0;
    for (std::uint8_t v : valid) n += v;
    shprt::validate(cpca, n, std::size_t(channels) * std::size_t(K) * std::size_t(K));
}

std::string describe_probes(const ProbeGrid& g) {
    std::size_t valid = 0;
    for (std::uint8_t v : g.valid) valid += v;
    const Vec3f far = g.far_corner();
    return fmt::format(
        "{}x{}x{} = {} ({} valid), spacing {:.3g} x {:.3g} x {:.3g} m, from ({:.3g}, {:.3g}, "
        "{:.3g}) to ({:.3g}, {:.3g}, {:.3g}); K = {} ({}x{} matrices), {} channel{}{}",
        g.counts[0], g.counts[1], g.counts[2], g.count(), valid, g.spacing.x, g.spacing.y,
        g.spacing.z, g.origin.x, g.origin.y, g.origin.z, far.x, far.y, far.z, g.K, g.K, g.K,
        g.channels, g.channels == 1 ? "" : "s",
        g.cpca.empty()
            ? std::string()
            : fmt::format("; CPCA {} clusters x {} vectors", g.cpca.clusters, g.cpca.vectors));
}

ProbeSample sample_probes(const ProbeGrid& grid, Vec3f p) {
    const std::size_t n = std::size_t(grid.channels) * std::size_t(grid.K) * std::size_t(grid.K);
    ProbeSample out;
    out.matrix.assign(n, 0.0f);
    int lo[3];
    float t[3];
    for (int a = 0; a < 3; ++a) {
        const float u = (p[a] - grid.origin[a]) / grid.spacing[a];
        const float top = float(grid.counts[a] - 1);
        const float c = std::clamp(u, 0.0f, top);
        if (c != u) out.clamped = true;
        lo[a] = std::min(int(std::floor(c)), std::max(grid.counts[a] - 2, 0));
        t[a] = grid.counts[a] > 1 ? c - float(lo[a]) : 0.0f;
    }
    double total = 0;
    double w[8];
    std::size_t probe[8];
    for (int corner = 0; corner < 8; ++corner) {
        int q[3];
        double weight = 1;
        for (int a = 0; a < 3; ++a) {
            const int bit = (corner >> a) & 1;
            q[a] = std::min(lo[a] + bit, grid.counts[a] - 1);
            weight *= bit ? t[a] : 1.0f - t[a];
        }
        probe[corner] = grid.index(q[0], q[1], q[2]);
        w[corner] = grid.valid[probe[corner]] ? weight : 0.0;
        total += w[corner];
    }
    if (total <= 0) {
        // The nearest valid probe, by distance from the clamped point.
        double best = std::numeric_limits<double>::infinity();
        std::size_t best_probe = 0;
        for (int z = 0; z < grid.counts[2]; ++z)
            for (int y = 0; y < grid.counts[1]; ++y)
                for (int x = 0; x < grid.counts[0]; ++x) {
                    const std::size_t i = grid.index(x, y, z);
                    if (!grid.valid[i]) continue;
                    const Vec3f d = grid.position(x, y, z) - p;
                    const double d2 = double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z;
                    if (d2 < best) best = d2, best_probe = i;
                }
        if (!std::isfinite(best)) {
            out.no_valid = true;
            return out;
        }
        out.fallback = true;
        std::copy_n(grid.matrix(best_probe), n, out.matrix.begin());
        return out;
    }
    for (int corner = 0; corner < 8; ++corner) {
        if (w[corner] == 0) continue;
        const float weight = float(w[corner] / total);
        const float* m = grid.matrix(probe[corner]);
        for (std::size_t i = 0; i < n; ++i) out.matrix[i] += weight * m[i];
    }
    return out;
}

}  // namespace shprt
