// GPU bake against the CPU bake on builtin:room, the paper's sweep: K = 32, 48, 64, 128, 256 and
// S = 1024, 4096. Per configuration: the time split of both bakes (BVH build on the host, tracing,
// projection, total), rays per second, peak device memory and the speed-up. Then the raw any-hit
// traversal rate of a kernel that only traces (the target on an H100: ≥ 1e9 rays/s), and
// the bake time of a room scaled to ~1M triangles at S = 4096 (target ≤ 2 s).
//
// "After start-up": the first GPU bake of a process pays for the CUDA context, loading cuBLAS
// and its first kernels; it is reported separately and excluded from the sweep. Every figure is
// the minimum over --reps runs.
//
// The benchmark validates what it times before the sweep: on the same direction set, the GPU bake
// must cast exactly the CPU bake's rays and its coefficients must agree with the CPU's to within
// kMaxRelativeDifference (max_v max_i |ΔC_vi| / max_i |C_vi|; gpu.hpp states the tolerance);
// the trace-only kernel must count the bake's rays. Otherwise it exits with status 1.
//
// Without a CUDA device it prints "no CUDA device: skipped" and exits 0.
//
// A plain main() rather than Google Benchmark: both backends are timed in one run, and each
// configuration is a multi-second job on the CPU.
//
// Usage: bench_gpu_bake [--reps N] [--threads N] [--quick] [--no-cpu] [--no-scaling]
#include "bake/stages.hpp"
#include "bench_cli.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/sh/sampler.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace shprt;
using Clock = std::chrono::steady_clock;

constexpr double kMaxRelativeDifference = 5e-2;  // a few grazing-ray flips at S = 1024

struct Args {
    int reps = 5;
    int threads = 0;
    bool quick = false;
    bool cpu = true;
    bool scaling = true;
};

Args parse_args(int argc, char** argv) {
    Args a;
    bench::BenchCli cli("bench_gpu_bake", "The GPU bake against the CPU bake");
    cli.reps(a.reps).threads(a.threads);
    cli.flag("--quick", a.quick, true, "Fewer configurations");
    cli.flag("--no-cpu", a.cpu, false, "Skip the CPU bakes");
    cli.flag("--no-scaling", a.scaling, false, "Skip the scaling table");
    cli.parse(argc, argv);
    return a;
}

// The fastest of `reps` bakes (by total time), with its stats.
TransferSet best_of(int reps, const Mesh& mesh, const BakeOptions& options, const DirectionSet& set,
                    bool gpu) {
    TransferSet best;
    double best_total = std::numeric_limits<double>::infinity();
    for (int r = 0; r < reps; ++r) {
        BakeOptions o = options;
        o.device = gpu ? Device::cuda : Device::cpu;
        TransferSet t = bake(mesh, o, set);
        if (t.stats.seconds_total < best_total) {
            best_total = t.stats.seconds_total;
            best = std::move(t);
        }
    }
    return best;
}

// The rays of the receivers the CPU bake copies from a twin (bake/stages.hpp, traced_receivers)
// instead of casting them: the device casts them too, so its count is the CPU's plus these.
std::uint64_t twin_rays(const Mesh& mesh, const DirectionSet& set) {
    const std::size_t V = mesh.vertex_count(), S = set.size();
    const std::vector<std::uint8_t> traced = detail::traced_receivers(
        mesh.positions.data(), mesh.normals.data(), V, auto_chunk_receivers(V, S), S);
    const detail::DirectionTable table = detail::make_direction_table(set, set.frame);
    std::vector<float> row(S);
    std::uint64_t rays = 0;
    for (std::size_t v = 0; v < V; ++v) {
        if (traced[v]) continue;
        detail::weight_row(mesh.normals[v], table, row.data());
        rays +=
            std::uint64_t(std::count_if(row.begin(), row.end(), [](float w) { return w != 0.0f; }));
    }
    return rays;
}

double max_relative_difference(const TransferSet& a, const TransferSet& b) {
    const int K = a.layout.K;
    double worst = 0;
    for (std::size_t v = 0; v < a.receiver_count(); ++v) {
        double diff = 0, scale = 0;
        for (int i = 0; i < K; ++i) {
            diff = std::max(diff,
                            std::fabs(double(a.coeffs[v * K + i]) - double(b.coeffs[v * K + i])));
            scale = std::max(scale, std::fabs(double(b.coeffs[v * K + i])));
        }
        worst = std::max(worst, scale > 0 ? diff / scale : diff);
    }
    return worst;
}

double ms(double seconds) { return 1e3 * seconds; }

}  // namespace

int main(int argc, char** argv) {
    const Args args = parse_args(argc, argv);
    const GpuInfo gpu = query_gpu();
    if (!gpu.available) {
        std::printf("no CUDA device: skipped (query_gpu: %s)\n", gpu.reason.c_str());
        return 0;
    }
    std::printf("GPU: %s, %.1f GiB, compute capability %d.%d, %d SMs\n", gpu.name.c_str(),
                double(gpu.memory_bytes) / double(1u << 30), gpu.compute_capability / 10,
                gpu.compute_capability % 10, gpu.multiprocessors);

    const Mesh room = load_scene("builtin:room");
    std::printf("scene: builtin:room, %zu vertices, %zu triangles; reps %d (minimum reported)\n",
                room.vertex_count(), room.triangle_count(), args.reps);

    BakeOptions options;
    options.threads = args.threads;
    options.direction_frame = DirectionFrame::sphere;  // the sets below are sphere sets
    // Start-up: the first GPU bake of the process.
    {
        const DirectionSet set = make_direction_set(SamplerKind::uniform, 1, 64);
        options.K = 16;
        const auto start = Clock::now();
        BakeOptions gpu_options = options;
        gpu_options.device = Device::cuda;
        bake(room, gpu_options, set);
        std::printf("start-up (first GPU bake, S=64 K=16): %.1f ms\n",
                    ms(std::chrono::duration<double>(Clock::now() - start).count()));
    }

    // Validation.
    {
        const DirectionSet set = make_direction_set(SamplerKind::uniform, 1, 1024);
        options.K = 32;
        BakeOptions gpu_options = options;
        gpu_options.device = Device::cuda;
        const TransferSet g = bake(room, gpu_options, set);
        const TransferSet c = bake(room, options, set);
        const double rel = max_relative_difference(g, c);
        const GpuTraversalResult trace = measure_gpu_traversal(room, set, 1);
        const std::uint64_t twins = twin_rays(room, set);  // cast by the GPU, copied by the CPU
        std::printf(
            "validation (S=1024 K=32): rays GPU %llu, CPU %llu + its twins' %llu, trace-only "
            "kernel %llu; max relative coefficient difference %.3e (limit %.0e)\n",
            (unsigned long long)g.stats.rays_cast, (unsigned long long)c.stats.rays_cast,
            (unsigned long long)twins, (unsigned long long)trace.rays, rel, kMaxRelativeDifference);
        if (g.stats.rays_cast != c.stats.rays_cast + twins ||
            trace.rays != c.stats.rays_cast + twins || !(rel <= kMaxRelativeDifference)) {
            std::printf("VALIDATION FAILED: not timing a result that disagrees with the CPU\n");
            return 1;
        }
    }

    // The sweep.
    const std::vector<int> Ks =
        args.quick ? std::vector<int>{32, 256} : std::vector<int>{32, 48, 64, 128, 256};
    const std::vector<std::uint32_t> Ss =
        args.quick ? std::vector<std::uint32_t>{1024} : std::vector<std::uint32_t>{1024, 4096};
    std::printf(
        "\n| S | K | GPU bvh ms | GPU trace ms | GPU project ms | GPU total ms | GPU "
        "Mrays/s | peak device MiB | CPU trace ms | CPU project ms | CPU total ms | CPU "
        "Mrays/s | speed-up |\n");
    std::printf("|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (std::uint32_t S : Ss) {
        const DirectionSet set = make_direction_set(SamplerKind::uniform, 1, S);
        for (int K : Ks) {
            options.K = K;
            const TransferSet g = best_of(args.reps, room, options, set, true);
            const BakeStats& gs = g.stats;
            std::printf("| %u | %d | %.2f | %.2f | %.2f | %.2f | %.0f | %.0f |", S, K,
                        ms(gs.seconds_bvh), ms(gs.seconds_trace), ms(gs.seconds_project),
                        ms(gs.seconds_total), 1e-6 * double(gs.rays_cast) / gs.seconds_trace,
                        double(gs.peak_bytes_device) / double(1u << 20));
            if (args.cpu) {
                const TransferSet c = best_of(std::min(args.reps, 2), room, options, set, false);
                const BakeStats& cs = c.stats;
                std::printf(" %.1f | %.1f | %.1f | %.1f | %.1f× |\n", ms(cs.seconds_trace),
                            ms(cs.seconds_project), ms(cs.seconds_total),
                            1e-6 * double(cs.rays_cast) / cs.seconds_trace,
                            cs.seconds_total / gs.seconds_total);
            } else {
                std::printf(" – | – | – | – | – |\n");
            }
            std::fflush(stdout);
        }
    }

    // Raw traversal.
    std::printf("\nany-hit traversal, trace-only kernel (fastest of %d launches):\n", args.reps);
    for (std::uint32_t S : Ss) {
        const DirectionSet set = make_direction_set(SamplerKind::uniform, 1, S);
        const GpuTraversalResult r = measure_gpu_traversal(room, set, args.reps);
        std::printf("  room S=%u: %llu rays (%.1f%% occluded) in %.2f ms = %.3g rays/s\n", S,
                    (unsigned long long)r.rays, 100.0 * double(r.occluded) / double(r.rays),
                    ms(r.seconds), double(r.rays) / r.seconds);
    }

    // A ~1M-triangle room at S = 4096 (target ≤ 2 s).
    if (args.scaling) {
        const Mesh big = generate_room(RoomOptions{1'000'000, false});
        const DirectionSet set = make_direction_set(SamplerKind::uniform, 1, 4096);
        options.K = 16;
        const TransferSet g = best_of(std::min(args.reps, 2), big, options, set, true);
        const BakeStats& s = g.stats;
        std::printf(
            "\nroom with %zu triangles, %zu vertices, S=4096 K=16: bvh %.0f ms, trace %.0f "
            "ms, project %.0f ms, total %.0f ms (%.3g rays/s, peak device %.0f MiB)\n",
            big.triangle_count(), big.vertex_count(), ms(s.seconds_bvh), ms(s.seconds_trace),
            ms(s.seconds_project), ms(s.seconds_total), double(s.rays_cast) / s.seconds_trace,
            double(s.peak_bytes_device) / double(1u << 20));
    }
    return 0;
}
