// A bake session (session.hpp): the checks, the set, the tables and the tracer once; the passes.
#include "shprt/bake/session.hpp"

#include "bake/bake_internal.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <optional>
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
    std::vector<float> acc, error;
    std::vector<std::uint32_t> samples, visible, blocked;
    std::vector<std::uint8_t> more;
    std::uint32_t last_cap = 0;
    std::uint64_t rays = 0;

    TransferInfo run(const BakeJob& job, const BakeOptions& o, detail::BoundRows kept,
                     std::size_t cap);
};

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
    if (!s.whole_domain) s.tables = std::make_unique<detail::CpuBakeTables>(checked, *s.directions);
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
    Impl& s = *m_impl;
    SHPRT_CHECK(s.options.target_error > 0 && s.tables != nullptr, invalid_argument,
                "bake_to: a session of an error-bounded bake on the CPU only");
    const std::uint32_t max = s.options.samples;
    SHPRT_CHECK(cap >= kTargetFirstSamples && cap <= max && (cap & (cap - 1)) == 0,
                invalid_argument, "bake_to: cap {} must be a power of two, {} to {}", cap,
                kTargetFirstSamples, max);
    SHPRT_CHECK(cap >= s.last_cap, invalid_argument,
                "bake_to: cap {} is below the last one, {} (a session only adds samples)", cap,
                s.last_cap);
    if (s.samples.empty()) {
        const std::size_t total = s.receivers.total;
        s.acc.assign(total * std::size_t(s.tables->KL), 0.0f);
        s.samples.assign(total, 0);
        s.error.assign(total, 0.0f);
        s.visible.assign(total, 0);
        s.blocked.assign(total, 0);
        s.more.assign(total, 0);
    }
    s.last_cap = cap;
    BakeJob job;
    job.occluders = s.occluders;
    job.receivers = s.receivers;
    job.sink = &sink;
    job.directions = s.directions;
    job.tracer = s.tracer;
    BakeOptions o = s.options;
    if (progress) o.progress = std::move(progress);
    TransferInfo info = s.run(job, o,
                              {s.acc.data(), s.samples.data(), s.error.data(), s.visible.data(),
                               s.blocked.data(), s.more.data()},
                              cap);
    info.samples = static_cast<int>(cap);  // as bake() with max_samples = cap records
    return info;
}

}  // namespace shprt
