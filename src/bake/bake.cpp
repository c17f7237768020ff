// Diffuse transfer precompute: the boundary (option and job checks), the one choice of backend,
// the convenience entry points, and the slow reference.
//
// Implements the precompute of P.-P. Sloan, J. Kautz, J. Snyder, "Precomputed Radiance Transfer
// for Real-Time Rendering in Dynamic, Low-Frequency Lighting Environments", SIGGRAPH 2002, with
// the Monte Carlo projection of R. Green, "Spherical Harmonic Lighting: The Gritty Details", GDC
// 2003. The fast CPU path is bake_cpu.cpp, the GPU path bake_gpu.cpp.
#include "shprt/bake/bake.hpp"

#include "bake/bake_internal.hpp"
#include "bake/stages.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/bake/session.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/names.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace shprt {
namespace detail {

void validate_direction_set(const DirectionSet& directions) {
    SHPRT_CHECK(directions.size() >= 1, invalid_argument, "the direction set is empty");
    SHPRT_CHECK(directions.dirs.size() == 3 * directions.size(), invalid_argument,
                "the direction set has {} coordinates for {} weights (expected 3 per direction)",
                directions.dirs.size(), directions.size());
    SHPRT_CHECK(directions.size() <= kMaxBakeSamples, invalid_argument,
                "the direction set has {} directions (at most {})", directions.size(),
                kMaxBakeSamples);
}

BakeOptions with_direction_set(BakeOptions options, const DirectionSet& directions) {
    validate_direction_set(directions);
    options.samples = static_cast<std::uint32_t>(directions.size());
    options.direction_frame = directions.frame;
    return options;
}

void validate_job(const BakeJob& job, const BakeOptions&) {
    SHPRT_CHECK(job.occluders != nullptr, invalid_argument, "a bake needs occluders (a mesh)");
    const Mesh& mesh = *job.occluders;
    const std::string name = mesh.source.empty() ? std::string("mesh") : mesh.source;
    SHPRT_CHECK(mesh.vertex_count() > 0, invalid_argument, "{} is empty: it has no vertices", name);
    SHPRT_CHECK(mesh.triangle_count() > 0, invalid_argument, "{} is empty: it has no triangles",
                name);
    const Receivers& rx = job.receivers;
    SHPRT_CHECK(rx.positions != nullptr && rx.normals != nullptr, invalid_argument,
                "the receivers have no positions or normals");
    SHPRT_CHECK(rx.total <= std::numeric_limits<std::uint32_t>::max(), invalid_argument,
                "{} has {} receivers, more than a bake supports (2^32 - 1)", name, rx.total);
    SHPRT_CHECK(rx.count >= 1 && rx.first <= rx.total && rx.count <= rx.total - rx.first,
                invalid_argument, "receiver range [{}, {}) is empty or outside the {} receivers",
                rx.first, rx.first + rx.count, rx.total);
}

void validate_whole_mesh(const Mesh& mesh, TransferKind kind, const DirectionSet& directions) {
    validate_direction_set(directions);
    BakeOptions checked;
    checked.transfer = kind;
    checked.samples = static_cast<std::uint32_t>(directions.size());
    validate(checked);
    validate_job(BakeJob{&mesh, vertex_receivers(mesh), nullptr, nullptr, nullptr}, checked);
}

TransferInfo bake_info(const BakeOptions& options, Receivers receivers, std::size_t samples) {
    TransferInfo info = bake_description(options);
    info.layout.domain = receivers.domain;
    info.samples = static_cast<int>(samples);
    return info;
}

}  // namespace detail

namespace {

// A bake into host memory: the convenience entry points' body.
TransferSet bake_to_host(const Mesh& mesh, const Receivers& receivers, const BakeOptions& options,
                         const DirectionSet* directions, const Tracer* tracer) {
    HostSink sink;
    BakeJob job;
    job.occluders = &mesh;
    job.receivers = receivers;
    job.sink = &sink;
    job.directions = directions;
    job.tracer = tracer;
    HostSink direct;
    job.direct = kind_row(options.transfer).direct_part ? &direct : nullptr;
    TransferSet out;
    static_cast<TransferInfo&>(out) = bake(job, options);
    out.coeffs = sink.take_rows();
    out.direct = direct.take_rows();
    sink.take_estimates(out);
    out.stats.peak_bytes_host += out.coeffs.size() * sizeof(float);
    return out;
}

}  // namespace

namespace {
constexpr Named<Device> kDeviceNames[] = {
    {Device::cpu, "cpu"}, {Device::cuda, "cuda"}, {Device::automatic, "auto"}};
}  // namespace

const char* to_string(Device device) { return name_of(kDeviceNames, device); }
Device parse_device(const std::string& name) { return parse_named(kDeviceNames, name, "device"); }

TransferInfo bake_description(const BakeOptions& options) {
    TransferInfo info;
    info.kind = options.transfer;
    info.layout = layout_for(options.transfer, options.K);
    info.sampler = options.sampler;
    info.direction_frame = options.direction_frame;
    info.samples = static_cast<int>(bake_set_size(options));
    info.seed = options.seed;
    info.target_error = options.target_error;
    return info;
}

std::uint64_t estimate_bake_peak_bytes(std::size_t triangles, std::size_t receivers,
                                       const BakeOptions& options, bool rows_in_memory,
                                       std::size_t bounce_sources) {
    const std::uint64_t S = bake_set_size(options), K = std::uint64_t(std::max(options.K, 0));
    const std::uint64_t V = receivers;
    const std::uint64_t chunk = options.chunk_receivers > 0
                                    ? options.chunk_receivers
                                    : auto_chunk_receivers(std::max<std::size_t>(receivers, 1), S);
    const std::uint64_t threads = static_cast<std::uint64_t>(thread_count(options.threads));
    const std::uint64_t chunks = (V + chunk - 1) / std::max<std::uint64_t>(chunk, 1);
    const std::uint64_t workers = std::max<std::uint64_t>(1, std::min(threads, chunks));
    // Every kind by one rule, from its layout: a receiver's row is channels × F floats, and the
    // product's table has F columns (F = K for vectors, K(K+1)/2 for glossy's packed matrices:
    // its pair-product table, built from the K-column basis table, which lives beside it then).
    const TransferLayout layout = bake_description(options).layout;
    const std::uint64_t F = layout.floats_per_channel(), row = layout.floats_per_receiver();
    std::uint64_t bytes = triangles * kBvhBytesPerTriangle;
    // A local set projects onto KL ≥ K coefficients (the full bands) in the frame, into a
    // buffer of its own per worker, and rotates into the rows.
    const bool local = options.direction_frame == DirectionFrame::local;
    const std::uint64_t KL = std::uint64_t(detail::projected_coeffs(options));
    const std::uint64_t FL = F == K ? KL : KL * (KL + 1) / 2;
    bytes += S * FL * sizeof(float);                                           // Y (or P)
    if (FL != KL) bytes += S * KL * sizeof(float);                             // Y for P
    if (local) bytes += workers * chunk * FL * sizeof(float);                  // C in the frame
    bytes += S * detail::DirectionTable::kBytesPerDirection;                   // direction table
    bytes += workers * (chunk * S * sizeof(float) +                            // W
                        S * (3 * sizeof(float) + sizeof(std::uint32_t) + 1) +  // rays
                        chunk * F * sizeof(float));                            // C
    if (rows_in_memory) bytes += V * row * sizeof(float);
    // Interreflected: the sum of V rows and two bounce buffers of N rows (N bounce sources), T_0
    // of the receivers and of the sources (V + N rows of K), the sources' points and what their
    // rays met (41 bytes each), every worker's dense row accumulator (25 bytes per source), and
    // the operator's direction and basis tables (at most S directions).
    if (kind_row(options.transfer).interreflection) {
        const std::uint64_t N = bounce_sources > 0 ? bounce_sources : V;
        bytes += V * row * sizeof(float) + 2 * N * row * sizeof(float) +
                 (V + N) * K * sizeof(float) + N * 41 + workers * 25 * N +
                 S * (K * sizeof(float) + detail::DirectionTable::kBytesPerDirection);
    }
    return bytes;
}

const char* gpu_target_error_refusal(const BakeOptions& options) {
    if (options.target_error <= 0) return nullptr;
    if (kind_row(options.transfer).whole_domain)  // interreflected: its own stage
        return "--target-error with interreflected transfer bakes on the CPU (--device cpu)";
    if (options.direction_frame != DirectionFrame::local)
        return "--target-error on the GPU takes a local direction set (--directions local: each "
               "receiver's visible rays are read from its first coefficient); or bake on the CPU "
               "(--device cpu)";
    return nullptr;
}

void set_error_bound(BakeOptions& options, double target_error, long long max_samples,
                     std::string_view target_name, std::string_view max_name) {
    // The names come with their front end's separator ("--max-samples ", "max_samples="); the
    // option alone is the name without it.
    const auto bare = [](std::string_view name) {
        while (!name.empty() && (name.back() == ' ' || name.back() == '=')) name.remove_suffix(1);
        return name;
    };
    SHPRT_CHECK(target_error >= 0 && target_error <= 1, invalid_argument,
                "{}{}: must be 0 (off) or a relative error above 0, at most 1 (e.g. 0.01)",
                target_name, target_error);
    const auto max = static_cast<unsigned long long>(max_samples);
    SHPRT_CHECK(max_samples == 0 || (max_samples >= kTargetFirstSamples &&
                                     max_samples <= kMaxBakeSamples && (max & (max - 1)) == 0),
                invalid_argument, "{}{}: must be a power of two, {} to {} (0: {})", max_name,
                max_samples, kTargetFirstSamples, kMaxBakeSamples, kDefaultMaxSamples);
    SHPRT_CHECK(max_samples == 0 || target_error > 0, invalid_argument, "{} needs {}",
                bare(max_name), bare(target_name));
    options.target_error = target_error;
    options.max_samples = static_cast<std::uint32_t>(max_samples);
}

std::uint32_t bake_set_size(const BakeOptions& options) {
    if (options.target_error <= 0) return options.samples;
    return options.max_samples > 0 ? options.max_samples : kDefaultMaxSamples;
}

int default_coeffs(TransferKind kind) { return kind_row(kind).default_K; }

void validate(const BakeOptions& options) {
    SHPRT_CHECK(options.K >= 1 && options.K <= kMaxBakeCoeffs, invalid_argument,
                "basis size K = {} is out of range (1 to {} coefficients, i.e. up to 32 bands)",
                options.K, kMaxBakeCoeffs);
    SHPRT_CHECK(!is_matrix(kind_row(options.transfer)) || options.K <= kMaxGlossyCoeffs,
                invalid_argument,
                "{} transfer: K = {} is too large (at most {}, i.e. 8 bands: a K×K matrix per "
                "receiver)",
                to_string(options.transfer), options.K, kMaxGlossyCoeffs);
    SHPRT_CHECK(options.samples >= 1, invalid_argument,
                "samples = 0: a bake needs at least one direction");
    SHPRT_CHECK(options.samples <= kMaxBakeSamples, invalid_argument,
                "samples = {} is too many (at most {})", options.samples, kMaxBakeSamples);
    SHPRT_CHECK(options.threads >= 0 && options.threads <= kMaxBakeThreads, invalid_argument,
                "threads = {} must be 0 (all) to {}", options.threads, kMaxBakeThreads);
    SHPRT_CHECK(options.device_index >= 0, invalid_argument, "device index {} must be ≥ 0",
                options.device_index);
    SHPRT_CHECK(options.bounces >= 0 && options.bounces <= kMaxBounces, invalid_argument,
                "bounces = {} must be 0 to {}", options.bounces, kMaxBounces);
    SHPRT_CHECK(options.tolerance > 0 && options.tolerance < 1, invalid_argument,
                "tolerance = {} must be between 0 and 1 (a relative change)", options.tolerance);
    SHPRT_CHECK(options.max_bounces >= 1 && options.max_bounces <= kMaxBounces, invalid_argument,
                "max_bounces = {} must be 1 to {}", options.max_bounces, kMaxBounces);
    SHPRT_CHECK(options.indirect_samples <= kMaxBakeSamples, invalid_argument,
                "indirect samples = {} is too many (at most {})", options.indirect_samples,
                kMaxBakeSamples);
    SHPRT_CHECK(options.bounce_coeffs >= 0 && options.bounce_coeffs <= options.K, invalid_argument,
                "bounce coefficients = {} must be 0 (automatic) to K = {} (the bake's basis size)",
                options.bounce_coeffs, options.K);
    SHPRT_CHECK(options.target_error >= 0 && options.target_error <= 1, invalid_argument,
                "target error = {} must be 0 (off) or a relative error above 0, at most 1",
                options.target_error);
    const std::uint32_t max = options.max_samples;
    SHPRT_CHECK(max == 0 || options.target_error > 0, invalid_argument,
                "max samples = {} needs a target error (an error-bounded bake)", max);
    SHPRT_CHECK(max == 0 || (max >= kTargetFirstSamples && max <= kMaxBakeSamples &&
                             (max & (max - 1)) == 0),
                invalid_argument, "max samples = {} must be a power of two, {} to {}", max,
                kTargetFirstSamples, kMaxBakeSamples);
    if (options.target_error > 0) {
        SHPRT_CHECK(
            options.sampler == SamplerKind::sobol || options.sampler == SamplerKind::uniform,
            invalid_argument,
            "target error: sampler '{}' has no nested prefixes (use sobol or uniform)",
            to_string(options.sampler));
        SHPRT_CHECK(kind_row(options.transfer).error_bounded, unsupported,
                    "target error: {} transfer has no error-bounded bake yet (unshadowed, "
                    "shadowed or interreflected only)",
                    to_string(options.transfer));
    }
    SHPRT_CHECK(options.source_spacing >= 0 && !std::isnan(options.source_spacing),
                invalid_argument,
                "source spacing = {} must be 0 (automatic), a positive number of metres or inf",
                options.source_spacing);
}

Device resolve_device(Device requested, int device_index) {
    switch (requested) {
        case Device::cpu:
            return Device::cpu;
        case Device::automatic:
            return query_gpu(device_index).available ? Device::cuda : Device::cpu;
        case Device::cuda:
            break;
    }
    const GpuInfo gpu = query_gpu(device_index);
    if (gpu.available) return Device::cuda;
    fail(ErrorCode::unsupported, "device 'cuda': {}", gpu.reason);
}

EmbreeTracerOptions bake_tracer_options(const BakeJob& job, const BakeOptions& options,
                                        std::size_t samples) {
    // About S rays per receiver for a local set, S/2 for the sphere set (those above the
    // horizon), over the whole receiver set: a shard, a resumed gap and an MPI rank build the
    // whole bake's scene.
    const double rays = double(job.receivers.total) * double(samples) *
                        (options.direction_frame == DirectionFrame::local ? 1.0 : 0.5);
    EmbreeTracerOptions tracer =
        EmbreeTracerOptions::for_rays(rays, job.occluders->triangle_count());
    // Interreflected transfer casts closest-hit rays only (its direct part comes from their hits),
    // and so do probes (bake/probe_bake.hpp); the receivers of the other kinds cast visibility
    // rays only. Each bake gets the scenes it traces.
    const bool hits = kind_row(options.transfer).interreflection || job.probes != nullptr;
    const bool visibility = !kind_row(options.transfer).interreflection;
    tracer.closest_hits = hits;
    tracer.merge_coplanar = tracer.merge_coplanar && visibility;
    tracer.blocker_cones = tracer.merge_coplanar;
    return tracer;
}

std::size_t auto_chunk_receivers(std::size_t receivers, std::size_t samples) {
    constexpr std::size_t kRowBlock = 16;           // OpenBLAS SGEMM kernel row blocking
    constexpr std::size_t kTargetBytes = 1u << 20;  // W buffer per thread ~ 1 MiB (L2-sized)
    constexpr std::size_t kMinChunks = 64;          // load balance on many-core machines
    constexpr std::size_t kMaxChunk = 1024;
    const std::size_t by_memory = std::max<std::size_t>(
        1, kTargetBytes / (sizeof(float) * std::max<std::size_t>(samples, 1)));
    const std::size_t by_count =
        std::max<std::size_t>(1, (receivers + kMinChunks - 1) / kMinChunks);
    std::size_t chunk = std::min(by_memory, by_count);
    // Whole row blocks where they fit; below one block (huge S or a tiny mesh) memory wins.
    if (chunk >= kRowBlock) chunk = (chunk + kRowBlock - 1) / kRowBlock * kRowBlock;
    return std::min(chunk, kMaxChunk);
}

TransferInfo bake(const BakeJob& job, const BakeOptions& options) {
    BakeSession session(job, options);
    return session.bake(job);
}

TransferSet bake(const Mesh& mesh, const BakeOptions& options) {
    return bake_to_host(mesh, vertex_receivers(mesh), options, nullptr, nullptr);
}

TransferSet bake(const Mesh& mesh, const Receivers& receivers, const BakeOptions& options) {
    return bake_to_host(mesh, receivers, options, nullptr, nullptr);
}

TransferSet bake(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions) {
    return bake_to_host(mesh, vertex_receivers(mesh), options, &directions, nullptr);
}

TransferSet bake_with_tracer(const Mesh& mesh, const BakeOptions& options,
                             const DirectionSet& directions, const Tracer& tracer) {
    SHPRT_CHECK(options.device != Device::cuda, unsupported,
                "bake_with_tracer runs on the CPU only (device 'cuda' was asked for)");
    BakeOptions cpu = options;
    cpu.device = Device::cpu;
    return bake_to_host(mesh, vertex_receivers(mesh), cpu, &directions, &tracer);
}

TransferSet bake_reference(const Mesh& mesh, const BakeOptions& options,
                           const DirectionSet& directions, const Tracer& tracer) {
    const BakeOptions checked = detail::with_direction_set(options, directions);
    validate(checked);
    const Receivers receivers = vertex_receivers(mesh);
    detail::validate_job(BakeJob{&mesh, receivers, nullptr, nullptr, nullptr}, checked);
    const auto start = Clock::now();
    const int K = options.K;
    const std::size_t S = directions.size();
    // One channel of the kind's shape, traced or not; the bounces have no reference here.
    const TransferKindRow& row = kind_row(options.transfer);
    SHPRT_CHECK(!row.interreflection, unsupported,
                "bake_reference: {} transfer has no slow reference here (its bounces: "
                "path_trace_irradiance)",
                row.name);
    const bool glossy = is_matrix(row);
    const bool shadowed = row.traces_rays;
    const bool local = checked.direction_frame == DirectionFrame::local;
    constexpr float kInf = std::numeric_limits<float>::infinity();

    TransferSet out =
        TransferSet::zeros(detail::bake_info(checked, receivers, S), mesh.vertex_count());

    // Glossy: the packed upper triangle of Σ_s weight_s V y yᵀ (no cosine).
    const std::size_t F = out.layout.floats_per_channel();
    std::vector<double> y(K), sum(F);
    std::uint64_t rays = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const Vec3f nf = mesh.normals[v];
        const Vec3d n = cast<double>(nf);
        const Vec3f origin = offset_ray_origin(mesh.positions[v], nf);
        const LocalFrame frame = local_frame(nf);
        std::fill(sum.begin(), sum.end(), 0.0);
        for (std::size_t s = 0; s < S; ++s) {
            Vec3f wf{directions.dirs[3 * s], directions.dirs[3 * s + 1],
                     directions.dirs[3 * s + 2]};
            // A local set: the direction turned into the frame, the basis evaluated there in
            // world space (no SH rotation: what the fast path's rotation must reproduce), and
            // the weight taken whole (the density is in it).
            if (local) wf = to_world(frame, wf);
            const Vec3d w = cast<double>(wf);
            const double cosine = local ? 1.0 : dot(n, w);
            if (cosine <= 0) continue;  // below the horizon: T = 0, no ray
            if (shadowed) {
                std::uint8_t occluded = 0;
                tracer.occluded(origin, &wf, 1, 0.0f, kInf, &occluded);
                ++rays;
                if (occluded) continue;
            }
            sh_eval_k<double>(K, w.x, w.y, w.z, y.data());
            if (glossy) {
                const double t = double(directions.weights[s]);
                std::size_t p = 0;
                for (int i = 0; i < K; ++i)
                    for (int j = i; j < K; ++j) sum[p++] += t * y[i] * y[j];
                continue;
            }
            const double t = cosine * double(directions.weights[s]);
            for (int i = 0; i < K; ++i) sum[i] += t * y[i];
        }
        float* dst = out.receiver(v);
        for (std::size_t i = 0; i < F; ++i) dst[i] = static_cast<float>(sum[i]);
    }
    out.stats.rays_cast = rays;
    out.stats.seconds_total = out.stats.seconds_trace = seconds_since(start);
    out.stats.peak_bytes_host = out.coeffs.size() * sizeof(float);
    out.stats.device_name = "cpu: reference, 1 thread";
    return out;
}

}  // namespace shprt
