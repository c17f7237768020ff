// The CPU bake: visibility by stream ray casting, projection by SGEMM over chunks of receivers.
//
// Sloan, Kautz & Snyder 2002 (PRT) with Green 2003's Monte Carlo projection, organised as in the
// paper: one direction set for every receiver and the basis table Y[S×K] computed once, so that
// projecting a chunk of receivers is the matrix product C[chunk×K] = W[chunk×S]·Y[S×K]. Each
// chunk runs the stages of stages.hpp (weight → trace → project) and hands its rows to the sink.
//
// Threads: TBB runs chunks in parallel in an arena of `threads` workers; each chunk is traced
// and then projected by one cblas_sgemm on the same thread, whose W is still in its cache.
// OpenBLAS is told to use one thread: it would otherwise run its own pthreads inside every call
// and fight the TBB workers for the same cores (oversubscription: T workers × T BLAS threads on T
// cores, each waking and spinning), and a chunk's product would depend on how OpenBLAS split it.
// With one BLAS thread per chunk, each chunk's coefficients depend only on that chunk's data:
// bit-identical results for any thread count.
#include "bake/bake_internal.hpp"
#include "bake/bake_progress.hpp"
#include "bake/error_bound.hpp"
#include "bake/stages.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <numeric>
#include <vector>

namespace shprt::detail {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

// The sink of a pass that hands over no rows: a round before the last of
// BakeSession::bake_in_rounds, which takes the kept rows further and reports their estimates.
class NullSink final : public TransferSink {
public:
    void begin(const TransferLayout&, std::size_t, std::size_t) override {}
    void write(std::size_t, std::size_t, const float*) override {}
};

// One worker's buffers, reused for every chunk it runs.
struct Scratch {
    std::vector<float> w;        // W[chunk×S], row-major
    std::vector<float> c;        // C[chunk×K] when the sink has no host rows to project into
    std::vector<float> c_local;  // C'[chunk×KL] in the receivers' frames (local sets)
    TraceScratch trace;
    std::vector<std::uint32_t> twin;  // the range's twins (stages.hpp: find_twins)
    ErrorBoundScratch bound;          // the error-bounded bake's buffers
    double trace_seconds = 0;         // CPU time in weighting and tracing (this worker)
    double project_seconds = 0;       // CPU time in SGEMM (this worker)
};

}  // namespace

CpuBakeTables::CpuBakeTables(const BakeOptions& options, const DirectionSet& directions) {
    const TransferKindRow& row = kind_row(options.transfer);
    glossy = is_matrix(row);     // packed matrices: the pair-product table
    shadowed = row.traces_rays;  // rays are cast
    hemisphere = !row.cosine;    // W without the cosine
    bounded = options.target_error > 0;
    local = options.direction_frame == DirectionFrame::local;
    S = directions.size();
    K = options.K;
    table = make_direction_table(directions, options.direction_frame,
                                 bounded ? kTargetFirstSamples : 0);
    // The basis table, once for all receivers: Y[s*KL + i] = y_i(w_s), KL = K (a local set: the
    // full bands that hold K, in the frame; rotated to K in world space after the product).
    // Glossy transfer projects onto the pair-product table instead (stages.hpp): its F =
    // K(K+1)/2 columns are the packed upper triangle of each receiver's matrix.
    KL = projected_coeffs(options);
    Y = glossy ? pair_product_table(basis_table(KL, directions), S, KL)
               : basis_table(KL, directions);
    F = glossy ? K * (K + 1) / 2 : K;      // columns of a row
    FL = glossy ? KL * (KL + 1) / 2 : KL;  // columns of the product
    // A local set's rows get the open part exactly (stages.hpp, OpenControl).
    if (local && options.open_control && !bounded)
        open_control = make_open_control(table.weight.data(), Y.data(), S, 1.0, KL, glossy);
    // A local set's W is its one weight or 0, so its rows are projected by sums (the error
    // bound keeps its own, per segment).
    if (local && !bounded && FL >= kSumsMinColumns) weight = common_weight(table);
    if (weight != 0.0f) sums = segment_sums(Y.data(), S, FL);
    if (bounded) bound = make_error_bound(options, table, Y.data(), KL, shadowed);
}

std::size_t CpuBakeTables::bytes() const {
    return (Y.size() + sums.size()) * sizeof(float) + table.bytes();
}

TransferInfo bake_cpu(const BakeJob& job, const BakeOptions& options,
                      const DirectionSet& directions, const Tracer* tracer, double seconds_bvh) {
    const CpuBakeTables tables(options, directions);
    return bake_cpu_pass(job, options, tables, tracer, seconds_bvh);
}

TransferInfo bake_cpu_pass(const BakeJob& job, const BakeOptions& options,
                           const CpuBakeTables& tables, const Tracer* tracer, double seconds_bvh,
                           BoundRows kept, std::size_t cap) {
    const auto start = Clock::now();
    const bool glossy = tables.glossy, shadowed = tables.shadowed, local = tables.local;
    const bool bounded = tables.bounded;
    SHPRT_CHECK(!shadowed || tracer != nullptr, invalid_argument,
                "shadowed transfer needs a tracer");
    SHPRT_CHECK(job.sink == nullptr || job.sink->device_rows() == nullptr, unsupported,
                "the CPU bake cannot write into a device buffer (a DeviceSink needs device "
                "'cuda')");
    const Receivers& rx = job.receivers;
    const std::size_t S = tables.S;
    const int K = tables.K, KL = tables.KL, F = tables.F, FL = tables.FL;
    const int threads = thread_count(options.threads);
    // The chunks are a grid over the whole receiver set, from receiver 0, with a size set by the
    // set (not by the range baked): a receiver is always projected at the same row of an SGEMM
    // of the same height, whatever range it is baked in. OpenBLAS's Haswell and Zen SGEMM
    // kernels give a row other bits at another row of the call or in a call of another height
    // (a Zen 3 EPYC, Debian's OpenBLAS 0.3.21: a third to a half of the coefficients differ in
    // the last bits), and a shard, a resumed gap or a sub-range must give the whole bake's bytes.
    // A chunk that the range only partly covers is projected whole, the rows outside the range
    // with zero weights (a row's bits do not depend on the other rows' values), and only the
    // range's rows are kept.
    // The error-bounded bake sizes its grid by its first prefix, the W that every row needs.
    const std::size_t chunk =
        options.chunk_receivers > 0
            ? options.chunk_receivers
            : auto_chunk_receivers(rx.total,
                                   bounded ? std::min<std::size_t>(S, kTargetFirstSamples) : S);
    const std::size_t first_chunk = rx.first / chunk;
    const std::size_t chunk_count = (rx.end() + chunk - 1) / chunk - first_chunk;
    const DirectionTable& table = tables.table;
    const std::vector<float>& Y = tables.Y;
    const OpenControl& open_control = tables.open_control;
    const ErrorBound& bound = tables.bound;
    if (cap == 0) cap = S;

    TransferInfo info = bake_info(options, rx, S);
    // No sink: a round of an error-bounded session that only takes its rows further (kept).
    SHPRT_CHECK(job.sink != nullptr || (bounded && kept.acc != nullptr), invalid_argument,
                "a bake needs a sink for its rows");
    NullSink no_rows;
    TransferSink& sink = job.sink ? *job.sink : no_rows;
    const bool hand_over = job.sink != nullptr;
    sink.begin(info.layout, rx.first, rx.count);
    if (bounded) sink.begin_estimates();

    BakeProgress progress(options.progress, shadowed, rx.count, S);
    tbb::enumerable_thread_specific<Scratch> scratch;

    // Twins in other chunks share their visibility (stages.hpp, SharedVisibility) over the
    // grid's chunks that the range touches: the error-bounded bake per nested segment, a fixed-S
    // bake over its whole set.
    std::unique_ptr<SharedVisibility> shared;
    if (shadowed) {
        const std::size_t origin = first_chunk * chunk;
        shared = std::make_unique<SharedVisibility>(
            rx.positions, rx.normals, origin,
            std::min(rx.total, (first_chunk + chunk_count) * chunk) - origin, chunk,
            bounded ? *bound.table : table, bounded ? bound.first_samples : S);
    }

    // The error-bounded chunk: every row of the grid's chunk baked to the bound (error_bound.hpp
    // says why the whole chunk), the range's rows rotated (local) or copied to the sink.
    auto run_bounded_chunk = [&](std::size_t grid_first, std::size_t height, std::size_t first,
                                 std::size_t count, Scratch& sc) {
        ErrorBoundScratch& eb = sc.bound;
        BoundRows rows = kept.acc != nullptr ? BoundRows{kept.acc + grid_first * std::size_t(KL),
                                                         kept.samples + grid_first,
                                                         kept.error + grid_first,
                                                         kept.visible + grid_first,
                                                         kept.blocked + grid_first,
                                                         kept.more + grid_first}
                                             : eb.fresh_rows(height, KL);
        bake_chunk_to_error(bound, cap, tracer, rx, grid_first, height, rows, eb, progress,
                            shared.get());
        if (progress.stopped()) return;
        const std::size_t lead = first - grid_first;
        if (!hand_over) {
            progress.add_errors(rows.error + lead, count, options.target_error);
            progress.add(count, 0);
            return;
        }
        const double rows_start = thread_cpu_seconds();
        float* C = sink.host_rows(first, count);
        if (C == nullptr) {
            if (sc.c.size() < count * std::size_t(F)) sc.c.resize(count * std::size_t(F));
            C = sc.c.data();
        }
        const float* out = eb.out.data() + lead * std::size_t(KL);
        if (local)
            rotate_rows_to_world(rx.normals + first, count, KL, K, false, out, C);
        else
            std::copy(out, out + count * std::size_t(K), C);
        sc.project_seconds += thread_cpu_seconds() - rows_start;
        progress.add_errors(rows.error + lead, count, options.target_error);
        progress.add(count, 0);
        sink.write(first, count, C);
        sink.write_estimates(first, count, rows.samples + lead, rows.error + lead);
    };

    auto run_chunk = [&](std::size_t c) {
        if (progress.stopped()) return;
        Scratch& sc = scratch.local();
        if (!bounded && sc.w.empty()) sc.w.resize(chunk * S);
        // The grid's chunk [grid_first, grid_first + height) and the range's part of it.
        const std::size_t grid_first = (first_chunk + c) * chunk;
        const std::size_t height = std::min(chunk, rx.total - grid_first);
        const std::size_t first = std::max(grid_first, rx.first);
        const std::size_t count = std::min(grid_first + height, rx.end()) - first;
        const std::size_t lead = first - grid_first;  // rows of the chunk before the range
        const bool whole = count == height;
        if (bounded) return run_bounded_chunk(grid_first, height, first, count, sc);
        if (!whole) std::fill(sc.w.begin(), sc.w.begin() + std::ptrdiff_t(height * S), 0.0f);
        const double trace_start = thread_cpu_seconds();
        std::uint64_t local_rays = 0;
        find_twins(rx.positions + first, rx.normals + first, count, sc.twin);
        for (std::size_t j = 0; j < count; ++j) {
            const std::size_t r = first + j;
            float* row = sc.w.data() + (lead + j) * S;
            if (sc.twin[j] != j) {  // the same row as its twin's: not traced again
                const float* same = sc.w.data() + (lead + sc.twin[j]) * S;
                std::copy(same, same + S, row);
            } else {
                weight_row(rx.normals[r], table, row, tables.hemisphere);
                const std::uint32_t slot = shared ? shared->slot(r) : CrossTwins::kNoSlot;
                if (slot != CrossTwins::kNoSlot)  // twins in other chunks: traced once
                    local_rays += shared->mask(slot, *tracer, rx.positions[r], rx.normals[r],
                                               DirectionRange{0, S}, row, sc.trace);
                else if (shadowed)
                    local_rays +=
                        trace_row(*tracer, rx.positions[r], rx.normals[r], table, row, sc.trace);
            }
            // Shared counters every 16 receivers: a cache line bounced between the workers per
            // receiver would cost more than the progress is worth.
            if ((j & 15u) == 15u || j + 1 == count) {
                progress.add((j & 15u) + 1, local_rays);
                local_rays = 0;
            }
            if (!progress.poll()) return;
        }
        const double project_start = thread_cpu_seconds();
        float* C = whole ? sink.host_rows(first, count) : nullptr;
        if (C == nullptr) {
            if (sc.c.empty()) sc.c.resize(chunk * std::size_t(F));
            C = sc.c.data();
        }
        if (local) {
            if (sc.c_local.empty()) sc.c_local.resize(chunk * std::size_t(FL));
            if (tables.weight != 0.0f)  // the range's rows alone: each is its own sums
                project_visibility_rows(sc.w.data() + lead * S, count, S, S, Y.data(), FL,
                                        tables.sums.data(), tables.weight,
                                        sc.c_local.data() + lead * std::size_t(FL));
            else
                project_rows(sc.w.data(), height, S, Y.data(), FL, sc.c_local.data());
            apply_open_control(open_control, sc.c_local.data() + lead * std::size_t(FL), count);
            rotate_rows_to_world(rx.normals + first, count, KL, K, glossy,
                                 sc.c_local.data() + lead * std::size_t(FL),
                                 C + lead * std::size_t(F));
        } else {
            project_rows(sc.w.data(), height, S, Y.data(), F, C);
        }
        const double project_end = thread_cpu_seconds();
        sc.trace_seconds += project_start - trace_start;
        sc.project_seconds += project_end - project_start;
        sink.write(first, count, C + lead * std::size_t(F));
    };

    // A pass that goes on from kept rows (a session's round) knows each chunk's work: its rows
    // still over the target. Those chunks go first, the busiest first, so that the pass does not
    // end on one worker with a busy chunk while the others wait — rounds would pay that once
    // each. Which worker runs which chunk changes no bits.
    std::vector<std::size_t> order(chunk_count);
    std::iota(order.begin(), order.end(), std::size_t(0));
    if (bounded && kept.acc != nullptr) {
        std::vector<std::size_t> busy(chunk_count, 0);
        for (std::size_t c = 0; c < chunk_count; ++c) {
            const std::size_t first = (first_chunk + c) * chunk;
            const std::size_t end = std::min(first + chunk, rx.total);
            for (std::size_t j = first; j < end; ++j) busy[c] += kept.goes_on(j, cap) ? 1 : 0;
        }
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return busy[a] > busy[b]; });
    }

    const auto parallel_start = Clock::now();
    {
        const SingleThreadedBlas single_threaded_blas;
        // One task per chunk: the partition is fixed, the scheduler only decides which worker
        // runs which chunk.
        parallel_each(threads, chunk_count, [&](std::size_t i) { run_chunk(order[i]); });
    }
    const double parallel_seconds = seconds_between(parallel_start, Clock::now());
    SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled after {} of {} receivers",
                progress.receivers_done(), rx.count);
    sink.finish();

    // Split the parallel phase's wall time between tracing and projection in proportion to the
    // CPU time the workers spent in each (their sum is what the workers did; the wall time is
    // what the caller waited).
    double trace_acc = 0, project_acc = 0;
    std::size_t c_bytes = 0;
    for (const Scratch& sc : scratch) {
        trace_acc += sc.trace_seconds + sc.bound.trace_seconds;
        project_acc += sc.project_seconds + sc.bound.project_seconds;
        c_bytes += (sc.c.size() + sc.c_local.size()) * sizeof(float);
    }
    const double busy = trace_acc + project_acc;
    BakeStats& st = info.stats;
    st.seconds_bvh = seconds_bvh;
    st.seconds_trace = busy > 0 ? parallel_seconds * trace_acc / busy : 0;
    st.seconds_project = busy > 0 ? parallel_seconds * project_acc / busy : 0;
    st.seconds_total = seconds_bvh + seconds_between(start, Clock::now());
    st.rays_cast = progress.rays();
    const std::size_t workers = std::min<std::size_t>(std::size_t(threads), chunk_count);
    // The sink's own memory is the caller's (a HostSink holds the rows) and is added there.
    st.peak_bytes_host = tables.bytes() + (shared ? shared->bytes() : 0) +
                         workers * (chunk * S * sizeof(float) + TraceScratch::bytes(S)) + c_bytes +
                         (tracer ? tracer->memory_bytes() : 0);
    st.device_name = fmt::format("cpu: {} thread{}", threads, threads == 1 ? "" : "s");
    return info;
}

}  // namespace shprt::detail
