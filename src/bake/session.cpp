// A bake session (session.hpp): the checks, the set, the tables and the tracer once; the passes.
#include "shprt/bake/session.hpp"

#include "bake/bake_internal.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/memory.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace shprt {

struct BakeSession::Impl {
    const Mesh* occluders = nullptr;
    Receivers receivers;  // the session's: passes take ranges of its set
    BakeOptions options;  // checked; samples = the set's size
    Device backend = Device::cpu;
    bool whole_domain = false;  // the interreflected kind: its own stage
    std::optional<DirectionSet> own_directions;
    const DirectionSet* directions = nullptr;
    std::unique_ptr<Tracer> own_tracer;
    const Tracer* tracer = nullptr;
    double seconds_bvh = 0;  // counted by the first pass
    bool first_pass = true;
    std::unique_ptr<detail::CpuBakeTables> tables;        // the CPU's per-receiver kinds
    std::shared_ptr<detail::GpuOccluders> gpu_occluders;  // the GPU's BVH, host and device
    // bake_to's rows of the whole receiver set (error_bound.hpp, BoundRows), and its last cap.
    // acc is left uninitialised: a row's first pass (at prefix 0) writes its sums before
    // anything reads them (error_bound.cpp), on the worker that bakes it, so the first round
    // neither waits for 4·KL bytes a receiver to be zeroed nor faults their pages in on one thread.
    std::unique_ptr<float[]> acc;
    std::vector<float> error;
    std::vector<std::uint32_t> samples, visible, blocked;
    std::vector<std::uint8_t> more;
    std::uint32_t last_cap = 0;
    std::uint64_t rays = 0;

    TransferInfo run(const BakeJob& job, const BakeOptions& o, detail::BoundRows kept,
                     std::size_t cap);
    // bake_to's checks and body; no sink: the rows are only taken further (a round before the
    // last of bake_in_rounds).
    TransferInfo round(std::uint32_t cap, TransferSink* sink, ProgressFn progress);
    // The receivers whose estimate is still over the target at the last cap, below the set's
    // largest prefix: what the next round would trace.
    std::size_t still_over();
    // bake_to's rows, as the passes take them.
    detail::BoundRows rows() {
        return {acc.get(),      samples.data(), error.data(),
                visible.data(), blocked.data(), more.data()};
    }
};

std::vector<std::uint32_t> error_bound_rounds(const BakeOptions& options) {
    const std::uint32_t last = bake_set_size(options);
    if (options.target_error <= 0) return {last};
    std::vector<std::uint32_t> rounds;
    for (std::uint32_t s = 4 * kTargetFirstSamples; s < last; s *= 4) rounds.push_back(s);
    rounds.push_back(last);
    return rounds;
}

std::uint64_t round_rows_bytes(std::size_t receivers, const BakeOptions& options) {
    const std::uint64_t KL = std::uint64_t(detail::projected_coeffs(options));
    // acc (KL floats), samples, error, visible, blocked (4 bytes each), more (1 byte).
    return std::uint64_t(receivers) * (KL * sizeof(float) + 17);
}

BakeSession::BakeSession(const BakeJob& job, const BakeOptions& options)
    : m_impl(std::make_unique<Impl>()) {
    Impl& s = *m_impl;
    BakeOptions checked =
        job.directions ? detail::with_direction_set(options, *job.directions) : options;
    validate(checked);
    SHPRT_CHECK(checked.target_error <= 0 || job.directions == nullptr, unsupported,
                "target error: the error-bounded bake makes its own nested set (no caller's "
                "direction set)");
    // The error-bounded bake's set is max_samples long (the prefixes are taken from it).
    checked.samples = bake_set_size(checked);
    detail::validate_job(job, checked);
    s.backend = resolve_device(checked.device, checked.device_index);
    if (s.backend == Device::cuda && checked.target_error > 0) {
        if (checked.device == Device::automatic) {
            s.backend = Device::cpu;  // bake.hpp, gpu_target_error_refusal: auto keeps the CPU
        } else if (const char* why = gpu_target_error_refusal(checked)) {
            fail(ErrorCode::unsupported, "{}", why);
        }
    }
    s.occluders = job.occluders;
    s.receivers = job.receivers;
    s.options = checked;
    s.whole_domain = kind_row(checked.transfer).whole_domain;
    if (job.directions) {
        s.directions = job.directions;
    } else {
        s.directions = &s.own_directions.emplace(bake_direction_set(checked));
    }
    s.tracer = job.tracer;
    if (s.backend == Device::cuda) {
        SHPRT_CHECK(job.tracer == nullptr, unsupported,
                    "a caller-built tracer runs on the CPU only (device 'cuda' was asked for)");
        // The GPU bake builds its BVH and uploads it on the first pass that casts rays, and the
        // session keeps both (gpu_occluders) for the others; its tables go up per pass.
        return;
    }
    if (s.tracer == nullptr && kind_row(checked.transfer).traces_rays) {
        // Embree builds with TBB tasks in the caller's arena: limit it to the bake's threads.
        const auto start = Clock::now();
        const EmbreeTracerOptions quality = bake_tracer_options(job, checked, s.directions->size());
        in_arena(checked.threads,
                 [&] { s.own_tracer = make_embree_tracer(*job.occluders, quality); });
        s.tracer = s.own_tracer.get();
        s.seconds_bvh = seconds_since(start);
    }
    // The tables (the basis table is evaluated in parallel) on the bake's threads.
    if (!s.whole_domain)
        in_arena(checked.threads, [&] {
            s.tables = std::make_unique<detail::CpuBakeTables>(checked, *s.directions);
        });
}

BakeSession::~BakeSession() = default;

const BakeOptions& BakeSession::options() const { return m_impl->options; }
Device BakeSession::backend() const { return m_impl->backend; }
std::uint64_t BakeSession::rays_cast() const { return m_impl->rays; }

TransferInfo BakeSession::Impl::run(const BakeJob& job, const BakeOptions& o,
                                    detail::BoundRows kept, std::size_t cap) {
    const double bvh = first_pass ? seconds_bvh : 0.0;
    first_pass = false;
    TransferInfo info;
    if (backend == Device::cuda) {
        SHPRT_CHECK(!(whole_domain && job.probes), unsupported,
                    "--probes with interreflected transfer: the probes read the CPU bake's "
                    "bounce sources; bake on the CPU (--device cpu)");
        if (whole_domain) {
            info = detail::bake_interreflected_gpu(job, o, *directions);
        } else {
            info = detail::bake_gpu(job, o, *directions, &gpu_occluders);
            detail::bake_job_probes(job, o, *directions, nullptr, nullptr, info);
        }
    } else if (whole_domain) {
        // The interreflected bake bakes its probes itself (they need its bounce sources' light).
        info = detail::bake_interreflected(job, o, *directions, tracer, bvh);
    } else {
        info = detail::bake_cpu_pass(job, o, *tables, tracer, bvh, kept, cap);
        detail::bake_job_probes(job, o, *directions, tracer, nullptr, info);
    }
    rays += info.stats.rays_cast;
    return info;
}

TransferInfo BakeSession::bake(const BakeJob& part, ProgressFn progress) {
    Impl& s = *m_impl;
    SHPRT_CHECK(part.occluders == nullptr || part.occluders == s.occluders, invalid_argument,
                "a pass of a bake session must bake against the session's occluders");
    SHPRT_CHECK(part.sink != nullptr, invalid_argument, "a bake needs a sink for its rows");
    BakeJob job = part;
    job.occluders = s.occluders;
    job.directions = s.directions;
    job.tracer = s.tracer;
    detail::validate_job(job, s.options);
    BakeOptions o = s.options;
    if (progress) o.progress = std::move(progress);
    return s.run(job, o, {}, 0);
}

TransferInfo BakeSession::bake_to(std::uint32_t cap, TransferSink& sink, ProgressFn progress) {
    return m_impl->round(cap, &sink, std::move(progress));
}

TransferInfo BakeSession::Impl::round(std::uint32_t cap, TransferSink* sink, ProgressFn progress) {
    SHPRT_CHECK(options.target_error > 0 && tables != nullptr, invalid_argument,
                "bake_to: a session of an error-bounded bake on the CPU only");
    const std::uint32_t max = options.samples;
    SHPRT_CHECK(cap >= kTargetFirstSamples && cap <= max && (cap & (cap - 1)) == 0,
                invalid_argument, "bake_to: cap {} must be a power of two, {} to {}", cap,
                kTargetFirstSamples, max);
    SHPRT_CHECK(cap >= last_cap, invalid_argument,
                "bake_to: cap {} is below the last one, {} (a session only adds samples)", cap,
                last_cap);
    if (samples.empty()) {
        const std::size_t total = receivers.total;
        acc.reset(new float[total * std::size_t(tables->KL)]);
        advise_huge_pages(acc.get(), total * std::size_t(tables->KL) * sizeof(float));
        samples.assign(total, 0);
        error.assign(total, 0.0f);
        visible.assign(total, 0);
        blocked.assign(total, 0);
        more.assign(total, 0);
    }
    last_cap = cap;
    BakeJob job;
    job.occluders = occluders;
    job.receivers = receivers;
    job.sink = sink;
    job.directions = directions;
    job.tracer = tracer;
    BakeOptions o = options;
    if (progress) o.progress = std::move(progress);
    TransferInfo info = run(job, o, rows(), cap);
    info.samples = static_cast<int>(cap);  // as bake() with max_samples = cap records
    return info;
}

std::size_t BakeSession::Impl::still_over() {
    const detail::BoundRows kept = rows();
    std::size_t over = 0;
    for (std::size_t j = receivers.first; j < receivers.end(); ++j)
        over += kept.goes_on(j, options.samples) ? 1 : 0;
    return over;
}

TransferInfo BakeSession::bake_in_rounds(TransferSink& sink, ProgressFn progress) {
    Impl& s = *m_impl;
    SHPRT_CHECK(s.last_cap == 0, invalid_argument,
                "bake_in_rounds: the session has baked to {} already", s.last_cap);
    const std::vector<std::uint32_t> caps = error_bound_rounds(s.options);
    // The stages' names and what follows each, alive while its round reports.
    std::vector<std::string> stages, then;
    for (std::size_t r = 0; r < caps.size(); ++r) {
        stages.push_back(r == 0 ? "bake" : fmt::format("≤ {} samples", caps[r]));
        const std::size_t left = caps.size() - 1 - r;
        then.push_back(left == 0 ? "" : fmt::format("≤ {} round{}", left, left == 1 ? "" : "s"));
    }
    TransferInfo info;
    BakeStats sum;
    for (std::size_t r = 0; r < caps.size(); ++r) {
        const bool last = r + 1 == caps.size();
        // Nothing over the target at the last cap: the rounds between have nothing to trace, and
        // the last only hands over the rows, unreported.
        const bool idle = r > 0 && s.still_over() == 0;
        if (idle && !last) continue;
        ProgressFn report;
        if (progress && !idle)
            report = [&progress, stage = std::string_view(stages[r]),
                      next = std::string_view(then[r])](const ProgressInfo& p) {
                ProgressInfo named = p;
                named.stage = stage;
                named.then = next;
                return progress(named);
            };
        // A report as the round starts (a display times the round's stage from here), with the
        // round's work as far as it is known: its receivers' new samples (a sphere set casts
        // about half of them, those above the horizon). Never a total of 0: a caller divides.
        const bool rays = kind_row(s.options.transfer).traces_rays;
        std::uint64_t work = std::uint64_t(r == 0 ? s.receivers.count : s.still_over()) *
                             std::uint64_t(caps[r] - s.last_cap);
        if (rays && s.options.direction_frame != DirectionFrame::local) work /= 2;
        if (report && !report(ProgressInfo{"", 0, std::max<std::uint64_t>(work, 1),
                                           rays ? "rays" : "samples"}))
            fail(ErrorCode::cancelled, "bake cancelled before its round to {} samples", caps[r]);
        info = s.round(caps[r], last ? &sink : nullptr, std::move(report));
        add_stats(sum, info.stats);
    }
    sum.peak_bytes_host += round_rows_bytes(s.receivers.total, s.options);
    info.stats = sum;
    return info;
}

}  // namespace shprt
