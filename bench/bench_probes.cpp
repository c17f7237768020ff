// Transfer probes on builtin:room (bake/probe_bake.hpp, docs/probes.md), in one run:
//   * bake cost: a 16×8×16 grid of 3-band (9×9) matrices over the room's interior against the
//     direct (shadowed) vertex bake of the same scene with the same S, each the minimum of --reps
//     runs, both through bake() with a caller's Embree tracer (no BVH time on either side);
//   * between probes: the room's grid at the default spacing (--probes auto), its matrices
//     interpolated (sample_probes, trilinear over valid probes) at every cell centre against a
//     probe baked exactly there (the grid of the centres), as the relative error of the incident
//     radiance's SH under a test light, |M_i·L − M_e·L| / |M_e·L|, over the centres whose exact
//     probe is valid: mean, 95th percentile and worst.
//
// Usage: bench_probes [--samples S] [--reps R] [--threads T] [--K K]
#include "bench_cli.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/probe_bake.hpp"
#include "shprt/core/host.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/trace/tracer.hpp"

#include <oneapi/tbb/info.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace {

using namespace shprt;

struct Args {
    int samples = 1024;
    int reps = 3;
    int threads = 0;
    int K = 16;  // the vertex bake's (the default of `shprt bake`)
};

// The probes of `grid` (its layout) baked with the bake's own entry: a vertex bake with probes
// beside it would time both, so the probes alone go through bake_probe_grid.
double bake_grid(ProbeGrid& grid, const Mesh& room, const BakeOptions& options,
                 const DirectionSet& set, const Tracer& tracer) {
    const auto start = Clock::now();
    bake_probe_grid(grid, room, options, set, &tracer);
    return seconds_since(start);
}

// The test light: a lobe toward the upper sky on a dim ambient (3 bands).
std::vector<double> test_light() {
    const Vec3d d = normalize(Vec3d{0.5, 1.0, 0.3});
    double y[9];
    sh_eval_k(9, d.x, d.y, d.z, y);
    const double a[3] = {2.0, 1.6, 0.7};
    std::vector<double> L(9);
    for (int l = 0, i = 0; l < 3; ++l)
        for (int m = -l; m <= l; ++m, ++i) L[std::size_t(i)] = a[l] * y[i];
    L[0] += 0.4;
    return L;
}

std::vector<double> apply(const float* M, const std::vector<double>& L) {
    std::vector<double> out(9, 0.0);
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) out[std::size_t(i)] += double(M[i * 9 + j]) * L[std::size_t(j)];
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    bench::BenchCli cli("bench_probes", "Transfer probes on the room: bake cost and interpolation");
    cli.samples(a.samples).reps(a.reps).threads(a.threads).K(a.K);
    cli.parse(argc, argv);
    const int threads = a.threads > 0 ? a.threads : tbb::info::default_concurrency();
    const Mesh room = load_scene("builtin:room");
    BakeOptions options;
    options.K = a.K;
    options.samples = std::uint32_t(a.samples);
    options.threads = threads;
    options.direction_frame = DirectionFrame::sphere;  // a probe has no frame: the sphere set
    const DirectionSet set = bake_direction_set(options);
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(room);
    std::printf(
        "# bench_probes: builtin:room, %zu vertices, %zu triangles, S = %d, %d threads, min of "
        "%d reps\n# host: %s\n\n",
        room.vertex_count(), room.triangle_count(), a.samples, threads, a.reps, host_cpu().c_str());

    // 1. Bake cost.
    // Over the room's interior (the bounds would put the outer probes inside the walls).
    ProbeSpec spec;
    spec.counts = {16, 8, 16};
    spec.box = std::array<Vec3f, 2>{Vec3f{-kRoomHalfWidth, 0.0f, -kRoomHalfDepth},
                                    Vec3f{kRoomHalfWidth, kRoomWallHeight, kRoomHalfDepth}};
    ProbeGrid grid = probe_grid_layout(spec, room, false);
    double vertex_s = std::numeric_limits<double>::infinity(), probe_s = vertex_s;
    for (int r = 0; r < a.reps; ++r) {
        const auto start = Clock::now();
        const TransferSet t = bake_with_tracer(room, options, set, *tracer);
        vertex_s = std::min(vertex_s, seconds_since(start));
        probe_s = std::min(probe_s, bake_grid(grid, room, options, set, *tracer));
    }
    std::size_t valid = 0;
    for (std::uint8_t v : grid.valid) valid += v;
    std::printf(
        "| bake | receivers | rays each | seconds | per receiver |\n|---|---|---|---|---|\n");
    std::printf("| vertices, K = %d, shadowed | %zu | %d (above the horizon) | %.3f | %.1f us |\n",
                a.K, room.vertex_count(), a.samples, vertex_s,
                1e6 * vertex_s / double(room.vertex_count()));
    std::printf(
        "| probes 16x8x16, 9x9 matrices (%zu valid) | %zu | %d (whole sphere) | %.3f | "
        "%.1f us |\n",
        valid, grid.count(), a.samples, probe_s, 1e6 * probe_s / double(grid.count()));
    std::printf("\nprobes / vertex bake: %.2fx the time for %.1f%% of the receivers\n\n",
                probe_s / vertex_s, 100.0 * double(grid.count()) / double(room.vertex_count()));

    // 2. Between probes: the default grid against probes baked at its cell centres.
    ProbeGrid coarse = probe_grid_layout(ProbeSpec{}, room, false);
    bake_grid(coarse, room, options, set, *tracer);
    ProbeGrid centres = coarse;
    for (int k = 0; k < 3; ++k) {
        centres.counts[std::size_t(k)] = std::max(1, coarse.counts[std::size_t(k)] - 1);
        centres.origin[k] = coarse.origin[k] + 0.5f * coarse.spacing[k];
    }
    bake_grid(centres, room, options, set, *tracer);
    const std::vector<double> L = test_light();
    double sky2 = 0;  // |L|²: the incident radiance's SH under the open sky is L itself
    for (double l : L) sky2 += l * l;
    // Per valid centre: |ΔL_in| relative to the exact probe's own |L_in| (where that is at least
    // kLit of the open sky's: a probe in the dark has no relative error to speak of), and
    // relative to the open sky's |L| (every valid centre).
    constexpr double kLit = 0.05;
    std::vector<double> own, to_sky;
    double worst_own = 0;  // and where
    std::array<int, 3> worst_at{0, 0, 0};
    std::size_t fallback = 0;
    for (int z = 0; z < centres.counts[2]; ++z)
        for (int y = 0; y < centres.counts[1]; ++y)
            for (int x = 0; x < centres.counts[0]; ++x) {
                const std::size_t p = centres.index(x, y, z);
                if (!centres.valid[p]) continue;
                const ProbeSample s = sample_probes(coarse, centres.position(x, y, z));
                fallback += s.fallback || s.no_valid;
                const std::vector<double> want = apply(centres.matrix(p), L);
                const std::vector<double> got = apply(s.matrix.data(), L);
                double d2 = 0, w2 = 0;
                for (int i = 0; i < 9; ++i) {
                    d2 += (got[std::size_t(i)] - want[std::size_t(i)]) *
                          (got[std::size_t(i)] - want[std::size_t(i)]);
                    w2 += want[std::size_t(i)] * want[std::size_t(i)];
                }
                to_sky.push_back(std::sqrt(d2 / sky2));
                if (w2 >= kLit * kLit * sky2) {
                    own.push_back(std::sqrt(d2 / w2));
                    if (own.back() > worst_own) worst_own = own.back(), worst_at = {x, y, z};
                }
            }
    const auto stats = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        double mean = 0;
        for (double e : v) mean += e;
        mean /= double(std::max<std::size_t>(v.size(), 1));
        return std::array<double, 3>{mean, v[v.size() * 95 / 100], v.back()};
    };
    const auto lit = stats(own), all = stats(to_sky);
    std::printf(
        "default grid %dx%dx%d (spacing %.2f x %.2f x %.2f m, %zu probes) interpolated at %zu "
        "valid cell centres (%zu by the nearest-valid fallback) against probes baked there, "
        "|dL_in|:\n",
        coarse.counts[0], coarse.counts[1], coarse.counts[2], coarse.spacing.x, coarse.spacing.y,
        coarse.spacing.z, coarse.count(), to_sky.size(), fallback);
    std::printf(
        "| relative to | centres | mean | 95th percentile | worst |\n|---|---|---|---|---|\n");
    std::printf(
        "| the exact probe's own |L_in| (where >= %.0f%% of the open sky's) | %zu | %.3f | "
        "%.3f | %.3f |\n",
        100 * kLit, own.size(), lit[0], lit[1], lit[2]);
    std::printf("| the open sky's |L| | %zu | %.3f | %.3f | %.3f |\n", to_sky.size(), all[0],
                all[1], all[2]);
    const Vec3f w = centres.position(worst_at[0], worst_at[1], worst_at[2]);
    std::printf("\nthe worst relative to its own |L_in|: the centre at (%.2f, %.2f, %.2f)\n", w.x,
                w.y, w.z);
    return 0;
}
