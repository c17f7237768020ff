// End-to-end CPU bake of builtin:room: time split (load, BVH, tracing, projection, write) for
// K = 32, 48, 64, 128, 256 and S = 1024, 4096, for the paper's uniform set on the sphere and for
// the default local Sobol set (--directions), and two ratios measured in the same run:
//   * tracing rate ÷ a plain Embree loop casting exactly the same rays at the same triangles
//     (merge_coplanar's, as the tracer; same origins, the same
//     above-horizon directions, one rtcOccluded1M stream call per vertex, same threads, same
//     chunks) and nothing else, in the fastest of two orders: the set's own and the coherent
//     order of sh/direction_order.hpp (both are reported: Embree's rate depends on the order);
//   * projection rate ÷ bare cblas_sgemm calls of the same shapes (the same chunk×S · S×K
//     products on the same threads, single-threaded OpenBLAS as in the bake), and, for context,
//     one multi-threaded SGEMM of the whole V×S · S×K product. A local set's projection stage
//     also rotates every row to world space (and projects onto the full bands, K' ≥ K), which
//     the bare SGEMM does not: its ratio is the price of both.
// Then the bake time against V (room at 20k, 200k, 2M triangles) to show linear cost.
//
// A plain main() rather than Google Benchmark: the ratios need both sides timed in one run, and
// each configuration is a multi-second job. Every figure is the minimum over --reps runs (the
// machine is shared; the minimum is the least disturbed). The benchmark validates what it times:
// the plain loop's per-vertex c_0 must equal the bake's to float rounding.
//
// Usage: bench_bake [--threads N] [--reps N] [--quick] [--no-scaling] [--only-scaling]
//                   [--chunk N] [--K K]...
// (--chunk overrides the automatic chunk size, --K (repeatable) the list of K.)
#include "bench_cli.hpp"
#include "plain_embree.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/host.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/sh/direction_order.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/ray.hpp"
#include "trace/embree_common.hpp"

#include <cblas.h>
#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <unistd.h>
#include <xmmintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace shprt;
struct Args {
    int threads = 0;
    int reps = 3;
    bool quick = false;
    bool scaling = true;
    bool only_scaling = false;
    std::size_t chunk = 0;            // 0 = the bake's automatic chunk size
    std::vector<int> Ks;              // empty = the default list
    std::string directions = "both";  // sphere, local or both
};

// ---------------------------------------------------------------------------------------------
// Bare SGEMM of the bake's shapes.

// Data shaped like W: about half zeros, the rest in (0, 0.01] (a hash, not an RNG: cheap).
void fill_like_w(std::vector<float>& w) {
    for (std::size_t i = 0; i < w.size(); ++i) {
        const std::uint32_t h = static_cast<std::uint32_t>(i) * 2654435761u;
        w[i] = (h >> 31) ? float((h >> 8) & 0xFFFFu) * 1.5e-7f + 1e-6f : 0.0f;
    }
}

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// The bake's products alone: every chunk's W[chunk×S]·Y[S×K] on the arena's threads with
// single-threaded OpenBLAS, each thread with its own W buffer (prepared beforehand). With
// `cold`, each thread sweeps a 4 MiB buffer before each product (untimed), as tracing a chunk
// does to the caches in the bake: a diagnostic of what the bake's interleaving costs the SGEMM.
// Returns the CPU seconds spent inside cblas_sgemm, summed over threads.
class BareChunkSgemm {
public:
    BareChunkSgemm(std::size_t S, std::size_t chunk, int threads)
        : m_S(S), m_chunk(chunk), m_arena(threads) {
        // Buffers touched before timing (first-touch page faults are not SGEMM).
        m_arena.execute([&] {
            tbb::parallel_for(std::size_t(0), std::size_t(threads) * 8,
                              [&](std::size_t) { prepare(); });
        });
    }
    double run(std::size_t V, int K, const std::vector<float>& Y, std::vector<float>& C,
               bool cold) {
        openblas_set_num_threads(1);
        tbb::enumerable_thread_specific<double> inside(0.0);
        m_arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, (V + m_chunk - 1) / m_chunk, 1),
                [&](const tbb::blocked_range<std::size_t>& r) {
                    Buffers& b = prepare();
                    for (std::size_t c = r.begin(); c != r.end(); ++c) {
                        if (cold) {
                            float sum = 0;
                            for (std::size_t i = 0; i < b.sweep.size(); i += 16) sum += b.sweep[i];
                            b.sink += sum;
                        }
                        const std::size_t first = c * m_chunk;
                        const std::size_t count = std::min(m_chunk, V - first);
                        const double t = thread_cpu_seconds();
                        cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, int(count), K,
                                    int(m_S), 1.0f, b.w.data(), int(m_S), Y.data(), K, 0.0f,
                                    C.data() + first * K, K);
                        inside.local() += thread_cpu_seconds() - t;
                    }
                },
                tbb::simple_partitioner());
        });
        double total = 0;
        for (double x : inside) total += x;
        return total;
    }

private:
    struct Buffers {
        std::vector<float> w, sweep;
        float sink = 0;
    };
    Buffers& prepare() {
        Buffers& b = m_buffers.local();
        if (b.w.empty()) {
            b.w.resize(m_chunk * m_S);
            fill_like_w(b.w);
            b.sweep.assign(std::size_t(1) << 20, 1.0f);  // 4 MiB
        }
        return b;
    }
    std::size_t m_S, m_chunk;
    tbb::task_arena m_arena;
    tbb::enumerable_thread_specific<Buffers> m_buffers;
};

// ---------------------------------------------------------------------------------------------
// Timing: wall clock, and the process's CPU time (all threads). On a machine shared with other
// work the wall clock stretches; CPU time ÷ threads is what the work costs when it has the
// cores to itself (busy threads, no waiting), and is the fair basis for rates then.

double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Cost {
    double wall = 1e30, cpu = 1e30;
    void keep_min(const Cost& c) {
        wall = std::min(wall, c.wall);
        cpu = std::min(cpu, c.cpu);
    }
};

template <class F>
Cost measure(F&& f) {
    const auto w = Clock::now();
    const double c = cpu_seconds();
    f();
    return {seconds_since(w), cpu_seconds() - c};
}

// ---------------------------------------------------------------------------------------------

// One configuration's figures; the *_s are seconds on one basis (wall, or CPU ÷ threads).
struct Figures {
    double load_s, bvh_s, trace_s, project_s, write_s, bake_s;
    double mrays, plain_mrays, gflops, bare_gflops, whole_gflops;
    double cold_gflops;  // bare SGEMM after a cache sweep (CPU basis only)
    double plain_set_mrays, plain_coherent_mrays;  // plain_mrays is the larger
};

struct Row {
    const char* set;  // "sphere" (the paper's uniform set) or "local" (the default Sobol set)
    int K;
    std::uint32_t S;
    Figures wall, cpu;
    double peak_mib;
};

std::string temp_path(const char* name) {
    return (std::filesystem::temp_directory_path() /
            (std::string("bench_bake_") + std::to_string(::getpid()) + "_" + name))
        .string();
}

void print_table(const std::vector<Row>& rows, bool cpu_basis) {
    std::printf(
        "\n%s\n\n"
        "| set    |   K |    S | load s | BVH s | trace s | project s | write s | bake s | "
        "end-to-end s |"
        " Mrays/s | plain Embree Mrays/s, set order | plain, coherent order | trace ratio |"
        " GFLOP/s | bare SGEMM GFLOP/s |"
        " proj. ratio | bare SGEMM, cold cache GFLOP/s | one big SGEMM GFLOP/s | peak MiB |\n"
        "|--------|----:|-----:|-------:|------:|--------:|----------:|--------:|-------:|---------"
        "----:|"
        "--------:|--------------------------------:|----------------------:|------------:|"
        "--------:|-------------------:|"
        "------------:|-------------------------------:|----------------------:|---------:|\n",
        cpu_basis ? "CPU time ÷ threads (the cost with the cores to oneself):" : "Wall clock:");
    for (const Row& r : rows) {
        const Figures& f = cpu_basis ? r.cpu : r.wall;
        std::printf(
            "| %-6s | %3d | %4u | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.1f | %.1f | "
            "%.1f | "
            "%.3f | %.1f | %.1f | %.3f | %s | %.1f | %.1f |\n",
            r.set, r.K, r.S, f.load_s, f.bvh_s, f.trace_s, f.project_s, f.write_s, f.bake_s,
            f.load_s + f.bake_s + f.write_s, f.mrays, f.plain_set_mrays, f.plain_coherent_mrays,
            f.mrays / f.plain_mrays, f.gflops, f.bare_gflops, f.gflops / f.bare_gflops,
            cpu_basis ? fmt::format("{:.1f}", f.cold_gflops).c_str() : "–", f.whole_gflops,
            r.peak_mib);
    }
}

Args parse_args(int argc, char** argv) {
    Args a;
    bench::BenchCli cli("bench_bake",
                        "The diffuse bake against a plain Embree loop and bare SGEMM");
    cli.threads(a.threads).reps(a.reps).Ks(a.Ks);
    cli.flag("--quick", a.quick, true, "Fewer configurations");
    cli.flag("--no-scaling", a.scaling, false, "Skip the thread-scaling table");
    cli.flag("--only-scaling", a.only_scaling, true, "Only the thread-scaling table");
    cli.option("--chunk", a.chunk, "Receivers per chunk (0 = the bake's automatic size)");
    cli.option("--directions", a.directions,
               "sphere (the paper's uniform set), local (the default Sobol set) or both (default)");
    cli.parse(argc, argv);
    if (a.threads <= 0) a.threads = tbb::info::default_concurrency();
    return a;
}

// Checks that the plain loop cast the bake's rays with the bake's answers; returns failures.
int validate(const TransferSet& t, std::uint64_t plain_rays, const std::vector<float>& plain_c0) {
    int failures = 0;
    if (plain_rays != t.stats.rays_cast) {
        std::printf("MISMATCH: plain Embree cast %llu rays, the bake %llu\n",
                    (unsigned long long)plain_rays, (unsigned long long)t.stats.rays_cast);
        ++failures;
    }
    std::size_t bad = 0;
    for (std::size_t v = 0; v < t.receiver_count(); ++v)
        bad += std::fabs(plain_c0[v] - t.receiver(v)[0]) > 1e-4f;
    // The bake's tracer answers most blocked rays from blocker cones (trace/tracer.hpp), which
    // differ from plain Embree on rare rays through gaps of Embree's own triangle test (the room:
    // one ray at one vertex, where the watertight flat BVH answers as the cones; see
    // test_blocker_cones). A few receivers in 10 000 may differ by such a ray.
    if (bad > 0 && bad <= t.receiver_count() / 5000) {
        std::printf(
            "note: c_0 of %zu of %zu vertices differs from the plain loop (a grazing ray)\n", bad,
            t.receiver_count());
        bad = 0;
    }
    if (bad > 0) {
        std::printf("MISMATCH: c_0 of %zu of %zu vertices differs from the plain loop\n", bad,
                    t.receiver_count());
        ++failures;
    }
    return failures;
}

void run_scaling(const Args& args) {
    std::printf(
        "\nTime against V (room --triangles N; K = 64, S = 256, %d threads; min of %d runs, "
        "1 at 2M):\n\n"
        "| triangles | vertices | generate s | bake wall s | bake CPU÷threads s | BVH s | "
        "trace s | project s | ns per vertex (CPU÷threads) | Mrays/s (CPU basis) | peak MiB |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        args.threads, args.reps);
    for (std::size_t tris : {std::size_t(20000), std::size_t(200000), std::size_t(2000000)}) {
        Mesh m;
        const Cost gen = measure([&] { m = generate_room(RoomOptions{tris, false}); });
        BakeOptions options;
        options.K = 64;
        options.samples = 256;
        options.sampler = SamplerKind::uniform;  // as in the recorded table (RESULTS.md)
        options.direction_frame = DirectionFrame::sphere;
        options.threads = args.threads;
        Cost best;
        TransferSet t, best_t;
        const int reps = tris >= 2000000 ? 1 : args.reps;
        for (int r = 0; r < reps; ++r) {
            const Cost c = measure([&] { t = bake(m, options); });
            if (c.cpu < best.cpu) best_t = std::move(t);
            best.keep_min(c);
        }
        const double busy = best.cpu / args.threads;
        const double f = busy / best.wall;  // wall → CPU-basis scale of this run's phases
        const BakeStats& s = best_t.stats;
        std::printf(
            "| %zu | %zu | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.0f | %.1f | %.1f |\n",
            m.triangle_count(), m.vertex_count(), gen.cpu, best.wall, busy, s.seconds_bvh * f,
            s.seconds_trace * f, s.seconds_project * f, busy / double(m.vertex_count()) * 1e9,
            double(s.rays_cast) / (s.seconds_trace * f) * 1e-6,
            double(s.peak_bytes_host) / (1 << 20));
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    const Args args = parse_args(argc, argv);
    std::printf("bench_bake: builtin:room, %d threads, min of %d runs, OPENBLAS_CORETYPE=%s\n",
                args.threads, args.reps,
                std::getenv("OPENBLAS_CORETYPE") ? std::getenv("OPENBLAS_CORETYPE") : "(unset)");
    std::printf("host: %s\n", host_cpu().c_str());
    std::printf("load average at start: ");
    std::fflush(stdout);
    std::system("cut -d' ' -f1-3 /proc/loadavg");

    if (args.only_scaling) {
        run_scaling(args);
        return 0;
    }
    Cost load;
    Mesh mesh;
    for (int r = 0; r < args.reps; ++r)
        load.keep_min(measure([&] { mesh = load_scene("builtin:room"); }));
    const std::size_t V = mesh.vertex_count();
    std::printf("room: %zu vertices, %zu triangles, load %.4f s wall, %.4f s CPU\n", V,
                mesh.triangle_count(), load.wall, load.cpu);
    const bench::PlainEmbree plain(mesh);
    const std::string out_path = temp_path("room.shprt");
    const double T = args.threads;

    const std::vector<int> Ks = !args.Ks.empty() ? args.Ks
                                : args.quick     ? std::vector<int>{32, 256}
                                                 : std::vector<int>{32, 48, 64, 128, 256};
    const std::vector<std::uint32_t> Ss =
        args.quick ? std::vector<std::uint32_t>{1024} : std::vector<std::uint32_t>{1024, 4096};
    std::vector<Row> rows;
    int failures = 0;
    std::vector<DirectionFrame> frames;
    if (args.directions != "local") frames.push_back(DirectionFrame::sphere);
    if (args.directions != "sphere") frames.push_back(DirectionFrame::local);
    for (const DirectionFrame frame : frames)
        for (std::uint32_t S : Ss) {
            // The paper's uniform set on the sphere, as in the recorded tables (RESULTS.md), or the
            // default: the local Sobol set, cosine-weighted.
            const bool local = frame == DirectionFrame::local;
            const SamplerKind sampler = local ? SamplerKind::sobol : SamplerKind::uniform;
            const DirectionSet set =
                local ? make_local_direction_set(sampler, 1, S, HemisphereDensity::cosine)
                      : make_direction_set(sampler, 1, S);
            const std::vector<std::uint32_t> coherent = coherent_order(set);
            const std::size_t chunk = args.chunk > 0 ? args.chunk : auto_chunk_receivers(V, S);
            BareChunkSgemm bare(S, chunk, args.threads);
            for (int K : Ks) {
                BakeOptions options;
                options.K = K;
                options.samples = S;
                options.sampler = sampler;  // the set the plain loops use (above)
                options.direction_frame = frame;
                // The plain estimator, whose c_0 the plain loop's sum validates (the open part
                // exactly changes the rows, not the rays: it costs a row's scaling).
                options.open_control = false;
                options.threads = args.threads;
                options.chunk_receivers = chunk;
                const std::vector<float> Y = basis_table(K, set);
                std::vector<float> plain_c0, C(V * K);
                std::uint64_t plain_rays = 0;
                TransferSet t;
                BakeStats wall_stats, cpu_stats;  // of the runs with the least wall / CPU time
                Cost bake_cost, plain_cost, coherent_cost, bare_cost, whole_cost, write_cost;
                double bare_inside = 1e30, cold_inside = 1e30;  // CPU s inside SGEMM, all threads
                for (int r = 0; r < args.reps; ++r) {
                    // Interleaved, so that a disturbance hits both sides of a ratio alike.
                    const Cost b = measure([&] { t = bake(mesh, options); });
                    if (b.wall < bake_cost.wall) wall_stats = t.stats;
                    if (b.cpu < bake_cost.cpu) {
                        cpu_stats = t.stats;
                        // The CPU-basis phases: this run's wall split, scaled to its CPU ÷ threads.
                        const double f = b.cpu / T / b.wall;
                        cpu_stats.seconds_bvh *= f;
                        cpu_stats.seconds_trace *= f;
                        cpu_stats.seconds_project *= f;
                    }
                    bake_cost.keep_min(b);
                    plain_cost.keep_min(measure([&] {
                        plain.run<false>(mesh, set, chunk, args.threads, plain_rays, plain_c0);
                    }));
                    plain_cost.keep_min(measure([&] {
                        plain.run<true>(mesh, set, chunk, args.threads, plain_rays, plain_c0);
                    }));
                    for (bool branch_free : {false, true}) {
                        std::uint64_t rays = 0;
                        std::vector<float> c0;
                        coherent_cost.keep_min(measure([&] {
                            if (branch_free)
                                plain.run<true>(mesh, set, chunk, args.threads, rays, c0,
                                                coherent.data());
                            else
                                plain.run<false>(mesh, set, chunk, args.threads, rays, c0,
                                                 coherent.data());
                        }));
                        failures += validate(t, rays, c0);
                    }
                    double inside = 0;
                    bare_cost.keep_min(measure([&] { inside = bare.run(V, K, Y, C, false); }));
                    bare_inside = std::min(bare_inside, inside);
                    cold_inside = std::min(cold_inside, bare.run(V, K, Y, C, true));
                    write_cost.keep_min(measure([&] { write_shprt(out_path, mesh, t); }));
                }
                {
                    // One SGEMM of the whole product, OpenBLAS's own threads (context only; the
                    // V×S matrix exists only here).
                    std::vector<float> W(V * S);
                    fill_like_w(W);
                    openblas_set_num_threads(args.threads);
                    for (int r = 0; r < args.reps; ++r)
                        whole_cost.keep_min(measure([&] {
                            cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, int(V), K,
                                        int(S), 1.0f, W.data(), int(S), Y.data(), K, 0.0f, C.data(),
                                        K);
                        }));
                    openblas_set_num_threads(1);
                }
                failures += validate(t, plain_rays, plain_c0);

                const double flop = 2.0 * double(V) * S * K;
                const double rays = double(t.stats.rays_cast);
                auto figures = [&](const BakeStats& s, double load_s, double bake_s, double write_s,
                                   double plain_s, double coherent_s, double bare_s,
                                   double whole_s) {
                    return Figures{load_s,
                                   s.seconds_bvh,
                                   s.seconds_trace,
                                   s.seconds_project,
                                   write_s,
                                   bake_s,
                                   rays / s.seconds_trace * 1e-6,
                                   rays / std::min(plain_s, coherent_s) * 1e-6,
                                   flop / s.seconds_project * 1e-9,
                                   flop / bare_s * 1e-9,
                                   flop / whole_s * 1e-9,
                                   flop / (cold_inside / T) * 1e-9,
                                   rays / plain_s * 1e-6,
                                   rays / coherent_s * 1e-6};
                };
                Row row;
                row.set = local ? "local" : "sphere";
                row.K = K;
                row.S = S;
                row.wall =
                    figures(wall_stats, load.wall, bake_cost.wall, write_cost.wall, plain_cost.wall,
                            coherent_cost.wall, bare_cost.wall, whole_cost.wall);
                // CPU basis of the bare SGEMM: the time inside the calls (no TBB scheduling).
                row.cpu = figures(cpu_stats, load.cpu, bake_cost.cpu / T, write_cost.cpu,
                                  plain_cost.cpu / T, coherent_cost.cpu / T, bare_inside / T,
                                  whole_cost.cpu / T);
                row.peak_mib = double(t.stats.peak_bytes_host) / (1 << 20);
                rows.push_back(row);
                std::printf(
                    "%s K=%d S=%u: bake %.4f s wall, %.4f s CPU÷threads, trace %.4f s wall; plain "
                    "Embree %.1f (set order), %.1f (coherent) Mrays/s wall; trace ratio to the "
                    "fastest %.3f (wall) %.3f (CPU); projection ratio %.3f (wall) %.3f (CPU)\n",
                    row.set, K, S, row.wall.bake_s, row.cpu.bake_s, row.wall.trace_s,
                    row.wall.plain_set_mrays, row.wall.plain_coherent_mrays,
                    row.wall.mrays / row.wall.plain_mrays, row.cpu.mrays / row.cpu.plain_mrays,
                    row.wall.gflops / row.wall.bare_gflops, row.cpu.gflops / row.cpu.bare_gflops);
                std::fflush(stdout);
            }
        }
    std::filesystem::remove(out_path);
    print_table(rows, false);
    print_table(rows, true);
    if (args.scaling) run_scaling(args);
    std::printf("load average at end: ");
    std::fflush(stdout);
    std::system("cut -d' ' -f1-3 /proc/loadavg");
    if (failures) std::printf("\n%d validation failures\n", failures);
    return failures ? 1 : 0;
}
