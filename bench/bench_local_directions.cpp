// The sphere direction set against the local one (docs/sampling.md, "The local set"; issue 39,
// item 1), on the room under a 16-band sky plus a 2° sun, shaded to per-vertex luminance:
//
//  1. variance at equal rays: for a fixed set of receivers (every 64th vertex), the variance over
//     16 seeds of each receiver's luminance, sphere vs local at the same S and at the same rays
//     (a sphere set of S casts about S/2 rays per receiver, a local set S);
//  2. error against time: the relative RMS luminance error of whole-room bakes against a
//     65536-sample sphere Sobol bake with another seed (kept in --reference-cache), for S from 64
//     up, sphere and local interleaved (min wall time of --reps runs each), and the time each
//     needs for 1 % by log–log interpolation between the bracketing S.
//
//  3. the error-bounded bake (docs/sampling.md, "Error-bounded bakes"), local Sobol at
//     --target-error E for E = 0.04, 0.02, 0.01, 0.005: its wall time and luminance error on the
//     same curve's terms, and each receiver's true error ‖ĉ − c‖/‖c_open‖ against a local bake of
//     --bound-reference-samples with another seed (worst, 99th percentile, mean), on the room and
//     on two small builtin scenes.
//
//  4. the viewer's rounds (bake/background.hpp): an error-bounded bake to E = 0.02 in rounds of
//     at most 256, 1024 and 4096 samples, as three separate bakes (before the bake session) and
//     as one session going on from round to round (BakeSession::bake_to), interleaved, min wall
//     time of --reps runs each; the last rounds' rows are checked equal. And the CLI's bake to the
//     same bound: one pass (bake()) against the same rounds in one call (bake_in_rounds), which
//     the CLI runs for its progress; their rows are checked equal.
//
//  5. the allocation limit: the rays for 1 % when each receiver's prefix is chosen from its true
//     error instead of an estimate (an oracle), with doubling prefixes and with 1.5x steps,
//     against the error-bounded bake of 3.
//
//     build/bench/bench_local_directions [--K 256] [--max-samples 8192] [--reps 2]
//
// Wall times are the bake's own (the direction set made, traced and projected; the BVH is built
// once outside and not counted: the same for both). The load average is printed before and after:
// other programs share this machine.
#include "room_study.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/session.hpp"
#include "shprt/core/host.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/estimates.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <ctime>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace shprt {
namespace {

using Clock = std::chrono::steady_clock;

// CPU seconds of the whole process (every worker thread of the bake).
double process_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Args {
    int K = 256;
    std::uint32_t max_samples = 8192, reference_samples = 65536;
    int reps = 2, threads = 2, seeds = 16;
    std::string reference_cache = "/tmp/bench_local_directions_reference.bin";
    std::uint32_t bound_reference_samples = 16384, bound_max_samples = kDefaultMaxSamples;
    std::vector<double> bound_targets = {0.04, 0.02, 0.01, 0.005};  // study 3's E
};

using room_study::luminance;
using room_study::relative_rms;
using room_study::true_errors;

BakeOptions options_for(const Args& a, DirectionFrame frame, std::uint32_t S, std::uint64_t seed) {
    BakeOptions o;
    o.K = a.K;
    o.samples = S;
    o.seed = seed;
    o.threads = a.threads;
    o.sampler = SamplerKind::sobol;
    o.direction_frame = frame;
    return o;
}

void print_load(const char* when) {
    std::printf("load average %s: ", when);
    std::fflush(stdout);
    std::system("cut -d' ' -f1-3 /proc/loadavg");
}

// 1. Per-receiver variance over seeds.
void variance_study(const Args& a, const Mesh& mesh, const Tracer& tracer, const ShLight& light) {
    std::vector<Vec3f> p, n;
    for (std::size_t v = 0; v < mesh.vertex_count(); v += 64) {
        p.push_back(mesh.positions[v]);
        n.push_back(mesh.normals[v]);
    }
    const Receivers rx = Receivers::all(ReceiverDomain::vertex, p.data(), n.data(), p.size());
    std::printf(
        "\n1. variance over %d seeds of the luminance of %zu receivers (every 64th vertex), "
        "K = %d\n\n",
        a.seeds, p.size(), a.K);
    std::printf(
        "| set | S | rays/receiver | mean variance | mean var. / sphere's at S | "
        "median per-receiver ratio sphere/local |\n|---|---:|---:|---:|---:|---:|\n");
    auto variances = [&](DirectionFrame frame, std::uint32_t S, double& rays) {
        std::vector<double> sum(p.size(), 0.0), sum2(p.size(), 0.0);
        rays = 0;
        for (int seed = 1; seed <= a.seeds; ++seed) {
            HostSink sink;
            BakeJob job{&mesh, rx, &sink, nullptr, &tracer, nullptr};
            const TransferInfo info = bake(job, options_for(a, frame, S, std::uint64_t(seed)));
            rays += double(info.stats.rays_cast) / double(p.size()) / a.seeds;
            const std::vector<double> y = luminance(sink.take_rows(), a.K, light);
            for (std::size_t r = 0; r < y.size(); ++r) {
                sum[r] += y[r];
                sum2[r] += y[r] * y[r];
            }
        }
        std::vector<double> var(p.size());
        for (std::size_t r = 0; r < p.size(); ++r) {
            const double m = sum[r] / a.seeds;
            var[r] = std::max(0.0, (sum2[r] / a.seeds - m * m) * a.seeds / (a.seeds - 1));
        }
        return var;
    };
    auto mean = [](const std::vector<double>& v) {
        double s = 0;
        for (double x : v) s += x;
        return s / double(v.size());
    };
    for (const std::uint32_t S : {256u, 1024u, 4096u}) {
        double rays_s = 0, rays_l = 0, rays_h = 0;
        const std::vector<double> vs = variances(DirectionFrame::sphere, S, rays_s);
        const std::vector<double> vl = variances(DirectionFrame::local, S, rays_l);
        const std::vector<double> vh = variances(DirectionFrame::local, S / 2, rays_h);
        auto median_ratio = [&](const std::vector<double>& local) {
            std::vector<double> r;
            for (std::size_t i = 0; i < vs.size(); ++i)
                if (local[i] > 0 && vs[i] > 0) r.push_back(vs[i] / local[i]);
            std::sort(r.begin(), r.end());
            return r.empty() ? 0.0 : r[r.size() / 2];
        };
        std::printf("| sphere | %u | %.0f | %.4g | 1 | 1 |\n", S, rays_s, mean(vs));
        std::printf("| local | %u | %.0f | %.4g | %.3f | %.2f |\n", S, rays_l, mean(vl),
                    mean(vl) / mean(vs), median_ratio(vl));
        std::printf("| local (equal rays) | %u | %.0f | %.4g | %.3f | %.2f |\n", S / 2, rays_h,
                    mean(vh), mean(vh) / mean(vs), median_ratio(vh));
        std::fflush(stdout);
    }
}

// 2. Error against time.
struct Point {
    std::uint32_t S;
    double seconds, error;  // seconds: wall or CPU, as the curve is
};

double time_to(const std::vector<Point>& curve, double target) {
    for (std::size_t i = 1; i < curve.size(); ++i) {
        const Point &a = curve[i - 1], &b = curve[i];
        if (a.error >= target && b.error <= target) {
            const double t = std::log(a.error / target) / std::log(a.error / b.error);
            return std::exp(std::log(a.seconds) + t * std::log(b.seconds / a.seconds));
        }
    }
    if (curve.size() >= 2 && curve.back().error > target) {  // past the curve: extrapolated
        const Point &a = curve[curve.size() - 2], &b = curve.back();
        const double t = std::log(a.error / target) / std::log(a.error / b.error);
        return -std::exp(std::log(a.seconds) + t * std::log(b.seconds / a.seconds));
    }
    return curve.empty() ? NAN : curve.front().seconds;
}

std::vector<double> error_curve(const Args& a, const Mesh& mesh, const Tracer& tracer,
                                const ShLight& light, bool measure) {
    const std::vector<double> ref = room_study::reference_luminance(
        mesh, tracer, light, a.K, a.reference_samples, a.threads, a.reference_cache);
    if (!measure) return ref;
    std::printf(
        "\n2. relative RMS luminance error against the reference, K = %d, %d threads, "
        "min wall of %d runs (sphere and local interleaved)\n\n",
        a.K, a.threads, a.reps);
    std::printf(
        "| S | sphere: wall s | sphere: error | plain local: wall s | plain local: error | "
        "local: wall s | local: CPU s | local: error | local: Mrays |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    // 0: the sphere set; 1: the local set without the open part (BakeOptions::open_control
    // off, the plain estimator); 2: the local set as it bakes.
    constexpr int kSeries = 3;
    std::vector<Point> curves[kSeries], cpu_curves[kSeries];
    for (std::uint32_t S = 64; S <= a.max_samples; S *= 2) {
        double best[kSeries], cpu[kSeries], error[kSeries] = {}, rays[kSeries] = {};
        std::fill(best, best + kSeries, 1e30);
        std::fill(cpu, cpu + kSeries, 1e30);
        for (int rep = 0; rep < a.reps; ++rep)
            for (int f = 0; f < kSeries; ++f) {
                const DirectionFrame frame =
                    f == 0 ? DirectionFrame::sphere : DirectionFrame::local;
                BakeOptions o = options_for(a, frame, S, 1);
                o.open_control = f == 2;
                const auto start = Clock::now();
                const double cpu_start = process_cpu_seconds();
                const TransferSet t = bake_with_tracer(mesh, o, bake_direction_set(o), tracer);
                const double wall = std::chrono::duration<double>(Clock::now() - start).count();
                best[f] = std::min(best[f], wall);
                cpu[f] = std::min(cpu[f], process_cpu_seconds() - cpu_start);
                if (rep == 0) {
                    error[f] = relative_rms(luminance(t.coeffs, a.K, light), ref);
                    rays[f] = double(t.stats.rays_cast) * 1e-6;
                }
            }
        for (int f = 0; f < kSeries; ++f) {
            curves[f].push_back({S, best[f], error[f]});
            cpu_curves[f].push_back({S, cpu[f], error[f]});
        }
        std::printf("| %u | %.3f | %.3f %% | %.3f | %.3f %% | %.3f | %.3f | %.3f %% | %.1f |\n", S,
                    best[0], 100 * error[0], best[1], 100 * error[1], best[2], cpu[2],
                    100 * error[2], rays[2]);
        std::fflush(stdout);
    }
    std::printf("\n");
    for (const double target : {0.02, 0.01}) {
        double wall[kSeries], cpu[kSeries];
        bool extrapolated = false;
        for (int f = 0; f < kSeries; ++f) {
            wall[f] = time_to(curves[f], target), cpu[f] = time_to(cpu_curves[f], target);
            extrapolated = extrapolated || wall[f] < 0;
            wall[f] = std::fabs(wall[f]), cpu[f] = std::fabs(cpu[f]);
        }
        std::printf(
            "time to %.0f %% (log-log interpolation%s): wall sphere %.3f s, plain local %.3f s, "
            "local %.3f s (%.2fx the sphere's); CPU %.3f s, %.3f s, %.3f s\n",
            100 * target, extrapolated ? ", one extrapolated past the last S" : "", wall[0],
            wall[1], wall[2], wall[0] / wall[2], cpu[0], cpu[1], cpu[2]);
    }
    return ref;
}

// 3. The error-bounded bake.
std::vector<float> bound_reference(const Args& a, const Mesh& mesh, const Tracer& tracer) {
    BakeOptions o = options_for(a, DirectionFrame::local, a.bound_reference_samples, 7919);
    return bake_with_tracer(mesh, o, bake_direction_set(o), tracer).coeffs;
}

TransferSet bake_bounded(const Args& a, const Mesh& mesh, const Tracer& tracer, double E,
                         double& wall, double& cpu) {
    BakeOptions o = options_for(a, DirectionFrame::local, 0, 1);
    o.samples = 1;
    o.target_error = E;
    o.max_samples = a.bound_max_samples;
    HostSink sink;
    BakeJob job{&mesh, vertex_receivers(mesh), &sink, nullptr, &tracer, nullptr};
    const auto start = Clock::now();
    const double cpu_start = process_cpu_seconds();
    TransferSet t;
    static_cast<TransferInfo&>(t) = bake(job, o);
    wall = std::chrono::duration<double>(Clock::now() - start).count();
    cpu = process_cpu_seconds() - cpu_start;
    t.coeffs = sink.take_rows();
    sink.take_estimates(t);
    return t;
}

// The room's rows of study 3, for study 5.
struct RoomBound {
    std::vector<Point> points;                        // per E: x Mrays cast, error luminance
    std::vector<double> targets;                      // the E of each
    std::vector<std::vector<std::uint32_t>> samples;  // each E's prefix per receiver
};

RoomBound bound_study(const Args& a, const Mesh& room, const Tracer& room_tracer,
                      const ShLight& light, const std::vector<double>& ref_luminance) {
    RoomBound room_bound;
    const std::vector<double>& targets = a.bound_targets;
    std::printf(
        "\n3. error-bounded bake (local Sobol, --target-error E, at most %u samples), K = %d, %d "
        "threads; luminance error against the reference of 2.; true per-receiver error against a "
        "local Sobol bake of S = %u, seed 7919\n\n",
        a.bound_max_samples, a.K, a.threads, a.bound_reference_samples);
    struct Scene {
        const char* name;
        const Mesh* mesh;
        const Tracer* tracer;
    };
    const Mesh box = make_builtin("box_on_plane"), corner = make_builtin("corner");
    const auto box_tracer = make_embree_tracer(box), corner_tracer = make_embree_tracer(corner);
    const Scene scenes[] = {{"room", &room, &room_tracer},
                            {"box_on_plane", &box, box_tracer.get()},
                            {"corner", &corner, corner_tracer.get()}};
    std::printf(
        "| scene | E | wall s | CPU s | mean S | luminance error | true error: worst | 99th "
        "pct | mean | estimate: worst | mean | over 2E | Mrays |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Scene& sc : scenes) {
        const auto start = Clock::now();
        const std::vector<float> ref = bound_reference(a, *sc.mesh, *sc.tracer);
        std::printf("<!-- %s reference: %.1f s -->\n", sc.name,
                    std::chrono::duration<double>(Clock::now() - start).count());
        for (const double E : targets) {
            double wall = 0, cpu = 0;
            const TransferSet t = bake_bounded(a, *sc.mesh, *sc.tracer, E, wall, cpu);
            const std::vector<double> truth = true_errors(t.coeffs, ref, a.K);
            std::size_t over = 0;
            for (double e : truth) over += e > 2 * E ? 1 : 0;
            const ErrorSpread spread = error_spread(truth);
            const EstimateSummary est = summarize_estimates(t);
            const bool is_room = sc.mesh == &room;
            const double lum =
                is_room ? relative_rms(luminance(t.coeffs, a.K, light), ref_luminance) : NAN;
            if (is_room) {
                room_bound.points.push_back({0, double(t.stats.rays_cast) * 1e-6, lum});
                room_bound.targets.push_back(E);
                room_bound.samples.push_back(t.receiver_samples);
            }
            std::printf(
                "| %s | %.3g | %.3f | %.3f | %.0f | %s | %.4f | %.4f | %.4f | %.4f | %.4f | %zu "
                "of %zu | %.1f |\n",
                sc.name, E, wall, cpu, est.mean_samples,
                is_room ? fmt::format("{:.3f} %", 100 * lum).c_str() : "–", spread.worst,
                spread.p99, spread.mean, est.error.worst, est.error.mean, over, truth.size(),
                double(t.stats.rays_cast) * 1e-6);
            std::fflush(stdout);
        }
    }
    return room_bound;
}

// 4. The viewer's rounds: separate bakes against one session.
void rounds_study(const Args& a, const Mesh& mesh, const Tracer& tracer) {
    BakeOptions o = options_for(a, DirectionFrame::local, 0, 1);
    o.samples = 1;
    o.target_error = 0.02;
    o.max_samples = 4096;
    const std::uint32_t caps[] = {256, 1024, 4096};
    std::printf(
        "\n4. the viewer's rounds: --target-error 0.02 in rounds of at most 256, 1024, 4096 "
        "samples (local Sobol), K = %d, %d threads, BVH built once outside; min of %d runs\n\n"
        "| rounds | wall s | Mrays |\n|---|---:|---:|\n",
        a.K, a.threads, a.reps);
    double separate = INFINITY, session_wall = INFINITY, one_wall = INFINITY,
           in_rounds_wall = INFINITY;
    std::uint64_t separate_rays = 0, session_rays = 0, one_rays = 0, in_rounds_rays = 0;
    std::vector<float> last_separate, last_session, one_rows, in_rounds_rows;
    for (int rep = 0; rep < a.reps; ++rep) {
        // The CLI's bake: one pass (bake()) against the same rounds breadth first
        // (BakeSession::bake_in_rounds), which the CLI runs so that its progress shows the error.
        auto begin = Clock::now();
        {
            HostSink sink;
            one_rays = bake(BakeJob{&mesh, vertex_receivers(mesh), &sink, nullptr, &tracer}, o)
                           .stats.rays_cast;
            one_rows = sink.take_rows();
        }
        one_wall = std::min(one_wall, std::chrono::duration<double>(Clock::now() - begin).count());
        begin = Clock::now();
        {
            HostSink sink;
            BakeSession session(BakeJob{&mesh, vertex_receivers(mesh), nullptr, nullptr, &tracer},
                                o);
            in_rounds_rays = session.bake_in_rounds(sink).stats.rays_cast;
            in_rounds_rows = sink.take_rows();
        }
        in_rounds_wall =
            std::min(in_rounds_wall, std::chrono::duration<double>(Clock::now() - begin).count());
        auto start = Clock::now();
        separate_rays = 0;
        for (const std::uint32_t cap : caps) {
            BakeOptions r = o;
            r.max_samples = cap;
            HostSink sink;
            separate_rays +=
                bake(BakeJob{&mesh, vertex_receivers(mesh), &sink, nullptr, &tracer}, r)
                    .stats.rays_cast;
            last_separate = sink.take_rows();
        }
        separate = std::min(separate, std::chrono::duration<double>(Clock::now() - start).count());
        start = Clock::now();
        BakeSession session(BakeJob{&mesh, vertex_receivers(mesh), nullptr, nullptr, &tracer}, o);
        for (const std::uint32_t cap : caps) {
            HostSink sink;
            session.bake_to(cap, sink);
            last_session = sink.take_rows();
        }
        session_wall =
            std::min(session_wall, std::chrono::duration<double>(Clock::now() - start).count());
        session_rays = session.rays_cast();
    }
    std::printf("| three separate bakes | %.3f | %.1f |\n", separate, double(separate_rays) * 1e-6);
    std::printf("| one session | %.3f | %.1f |\n", session_wall, double(session_rays) * 1e-6);
    std::printf("| one bake (bake(), one pass) | %.3f | %.1f |\n", one_wall,
                double(one_rays) * 1e-6);
    std::printf("| one bake in rounds (BakeSession::bake_in_rounds, the CLI's) | %.3f | %.1f |\n",
                in_rounds_wall, double(in_rounds_rays) * 1e-6);
    std::printf("\nthe last rounds' rows are %s; in rounds and in one pass, %s\n",
                last_session == last_separate ? "the same bits" : "DIFFERENT",
                in_rounds_rows == one_rows ? "the same bits" : "DIFFERENT");
}

// 5. The allocation limit. An error-bounded bake chooses each receiver's prefix from an estimate;
// here an oracle chooses it from the receiver's true error (against the local reference of 3.):
// the smallest prefix of the schedule whose true error is at most E there and at every longer
// prefix. Sweeping E gives the rays such a choice needs for 1 % luminance error, the fewest that
// any choice of one prefix per receiver without knowing the light can need with these prefixes
// (the oracle also profits from lucky draws, so it is if anything optimistic). The prefixes are
// fixed-S bakes of seed 1 (the bound's rows at a prefix are those bits); the doubling schedule
// is the bound's, the finer one adds 1.5·2^k.
void oracle_study(const Args& a, const Mesh& mesh, const Tracer& tracer, const ShLight& light,
                  const std::vector<double>& ref_luminance, const RoomBound& bound) {
    std::printf(
        "\n5. the allocation limit: each receiver's prefix chosen by an oracle from its true error "
        "(local Sobol, seed 1, against the local reference of 3.), K = %d, %d threads\n\n"
        "| S | wall s | Mrays/s (wall) | mean true error | luminance error |\n"
        "|---:|---:|---:|---:|---:|\n",
        a.K, a.threads);
    const std::vector<float> ref = bound_reference(a, mesh, tracer);
    std::vector<std::uint32_t> all;
    for (std::uint32_t S = kTargetFirstSamples * 2; S <= a.bound_max_samples; S *= 2) {
        all.push_back(S);
        if (S * 3 / 2 < a.bound_max_samples) all.push_back(S * 3 / 2);
    }
    std::sort(all.begin(), all.end());
    std::vector<std::vector<double>> truth, lum;  // [prefix][receiver]
    double rate = 0;                              // Mrays/s of the fixed bakes, all S
    double rays_all = 0, wall_all = 0;
    for (const std::uint32_t S : all) {
        const BakeOptions o = options_for(a, DirectionFrame::local, S, 1);
        const DirectionSet set = bake_direction_set(o);
        const auto start = Clock::now();
        const TransferSet t = bake_with_tracer(mesh, o, set, tracer);
        const double wall = std::chrono::duration<double>(Clock::now() - start).count();
        truth.push_back(true_errors(t.coeffs, ref, a.K));
        lum.push_back(luminance(t.coeffs, a.K, light));
        double mean = 0;
        for (const double e : truth.back()) mean += e / double(truth.back().size());
        rays_all += double(t.stats.rays_cast), wall_all += wall;
        std::printf("| %u | %.3f | %.1f | %.4f | %.3f %% |\n", S, wall,
                    double(t.stats.rays_cast) * 1e-6 / wall, mean,
                    100 * relative_rms(lum.back(), ref_luminance));
        std::fflush(stdout);
    }
    rate = rays_all * 1e-6 / wall_all;
    const std::size_t V = mesh.vertex_count();
    // Each receiver's prefix (an index of `all`) at E: the start of the longest tail of the
    // schedule's prefixes whose true errors are all at most E.
    auto picks = [&](bool finer, double E) {
        std::vector<std::size_t> idx;  // the schedule's prefixes, as indices of `all`
        for (std::size_t i = 0; i < all.size(); ++i)
            if (finer || std::has_single_bit(all[i])) idx.push_back(i);
        std::vector<std::size_t> pick(V, idx.back());
        for (std::size_t v = 0; v < V; ++v)
            for (std::size_t k = idx.size(); k-- > 0;) {
                if (truth[idx[k]][v] > E) break;
                pick[v] = idx[k];
            }
        return pick;
    };
    auto outcome = [&](const std::vector<std::size_t>& pick) {  // x: Mrays, error: luminance
        double rays = 0;
        std::vector<double> y(V);
        for (std::size_t v = 0; v < V; ++v) rays += all[pick[v]], y[v] = lum[pick[v]][v];
        return Point{0, rays * 1e-6, relative_rms(y, ref_luminance)};
    };
    constexpr double kStep = 1.02;  // the sweep's E ratio
    auto sweep = [&](bool finer) {
        std::vector<Point> curve;
        for (double E = 0.06; E > 0.004; E /= kStep) curve.push_back(outcome(picks(finer, E)));
        return curve;
    };
    const std::vector<Point> doubling = sweep(false), finer = sweep(true);
    auto at_one = [](std::vector<Point> c) {
        std::sort(c.begin(), c.end(),
                  [](const Point& p, const Point& q) { return p.seconds < q.seconds; });
        return std::fabs(time_to(c, 0.01));
    };
    const double d = at_one(doubling), f = at_one(finer), b = at_one(bound.points);
    std::printf(
        "\nrays for 1 %% luminance error (log-log interpolation): oracle, doubling prefixes %.1f "
        "M; "
        "oracle, prefixes 1.5x apart %.1f M; the error-bounded bake of 3. %.1f M (%.2fx the "
        "oracle's)\nat the fixed bakes' own rate (%.1f Mrays/s wall, tracing and projection "
        "together), the oracle's rays take %.3f s, the bound's %.3f s\n",
        d, f, b, b / d, rate, d / rate, b / rate);

    // Where the bound's rays go, against the oracle's at the same luminance error (the first E of
    // the sweep, from above, whose luminance error is at most the bound's): receivers by the
    // reference's visible fraction β = c₀/c₀,open (closed β < 0.01, open β > 0.99).
    std::printf(
        "\nthe bound's rays and the oracle's (doubling prefixes) at the same luminance error, by "
        "receiver (visible fraction of the reference: closed < 0.01, open > 0.99)\n\n"
        "| E | luminance error | oracle's E | closed: n | bound Mrays | oracle Mrays | open: n | "
        "bound Mrays | oracle Mrays | partly: n | bound Mrays | oracle Mrays |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    const double open0 = 0.5 * std::sqrt(3.14159265358979323846);  // π·y₀₀
    std::vector<int> cls(V);
    for (std::size_t v = 0; v < V; ++v) {
        const double beta = ref[v * std::size_t(a.K)] / open0;
        cls[v] = beta < 0.01 ? 0 : beta > 0.99 ? 1 : 2;
    }
    for (std::size_t r = 0; r < bound.points.size(); ++r) {
        double E = 0.06;
        std::vector<std::size_t> pick = picks(false, E);
        while (outcome(pick).error > bound.points[r].error && E > 0.002)
            pick = picks(false, E /= kStep);
        double n[3] = {}, b_rays[3] = {}, o_rays[3] = {};
        for (std::size_t v = 0; v < V; ++v) {
            n[cls[v]] += 1, b_rays[cls[v]] += bound.samples[r][v] * 1e-6;
            o_rays[cls[v]] += all[pick[v]] * 1e-6;
        }
        std::printf(
            "| %.3g | %.3f %% | %.4f | %.0f | %.1f | %.1f | %.0f | %.1f | %.1f | %.0f | %.1f | "
            "%.1f "
            "|\n",
            bound.targets[r], 100 * bound.points[r].error, E, n[0], b_rays[0], o_rays[0], n[1],
            b_rays[1], o_rays[1], n[2], b_rays[2], o_rays[2]);
    }
}

}  // namespace
}  // namespace shprt

int main(int argc, char** argv) {
    using namespace shprt;
    Args a;
    CLI::App app{"The sphere direction set against the local one (bench/RESULTS.md)"};
    app.add_option("--K", a.K, "basis size (default 256)");
    app.add_option("--max-samples", a.max_samples, "largest S of the curve (default 8192)");
    app.add_option("--reference-samples", a.reference_samples, "default 65536");
    app.add_option("--reps", a.reps, "runs per point, min wall time (default 2)");
    app.add_option("--threads", a.threads, "default 2");
    app.add_option("--seeds", a.seeds, "seeds of the variance study (default 16)");
    app.add_option("--reference-cache", a.reference_cache, "the reference's luminance");
    app.add_option("--bound-reference-samples", a.bound_reference_samples,
                   "3.: the local reference's S (default 16384)");
    app.add_option("--bound-max-samples", a.bound_max_samples,
                   "3.: the error-bounded bake's --max-samples (default 16384)");
    bool skip_variance = false, skip_curve = false, skip_bound = false, skip_rounds = false,
         skip_oracle = false;
    app.add_option("--bound-targets", a.bound_targets,
                   "study 3's target errors E (default 0.04 0.02 0.01 0.005)")
        ->check(CLI::PositiveNumber);
    app.add_flag("--skip-variance", skip_variance);
    app.add_flag("--skip-curve", skip_curve);
    app.add_flag("--skip-bound", skip_bound);
    app.add_flag("--skip-rounds", skip_rounds);
    app.add_flag("--skip-oracle", skip_oracle, "5. (it needs 3.)");
    CLI11_PARSE(app, argc, argv);

    std::printf("bench_local_directions: builtin:room, K = %d, %d threads, OPENBLAS_CORETYPE=%s\n",
                a.K, a.threads,
                std::getenv("OPENBLAS_CORETYPE") ? std::getenv("OPENBLAS_CORETYPE") : "(unset)");
    std::printf("host: %s\n", host_cpu().c_str());
    print_load("at start");
    const Mesh mesh = make_builtin("room");
    std::printf(
        "room: %zu vertices, %zu triangles; light: gradient sky + 2 degree sun "
        "(sun:0.4,0.8,-0.3,2), projected to K = %d\n",
        mesh.vertex_count(), mesh.triangle_count(), a.K);
    const ShLight light = room_study::light(a.K);
    const auto tracer = make_embree_tracer(mesh);
    if (!skip_variance) variance_study(a, mesh, *tracer, light);
    if (!skip_curve || !skip_bound) {
        const std::vector<double> ref = error_curve(a, mesh, *tracer, light, !skip_curve);
        const RoomBound bound =
            skip_bound ? RoomBound{} : bound_study(a, mesh, *tracer, light, ref);
        if (!skip_oracle && !skip_bound) oracle_study(a, mesh, *tracer, light, ref, bound);
    }
    if (!skip_rounds) rounds_study(a, mesh, *tracer);
    print_load("at end");
    return 0;
}
