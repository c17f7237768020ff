// Diffuse transfer precompute: input checks, the choice of backend, and the slow reference.
//
// Implements the precompute of P.-P. Sloan, J. Kautz, J. Snyder, "Precomputed Radiance Transfer
// for Real-Time Rendering in Dynamic, Low-Frequency Lighting Environments", SIGGRAPH 2002, with
// the Monte Carlo projection of R. Green, "Spherical Harmonic Lighting: The Gritty Details", GDC
// 2003. The fast CPU path is bake_cpu.cpp.
#include "shprt/bake/bake.hpp"

#include "bake/bake_internal.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace shprt {
namespace detail {

// Directions a bake accepts: W[chunk×S] must stay a sensible per-thread buffer.
constexpr std::uint64_t kMaxBakeSamples = std::uint64_t(1) << 24;

void validate_bake_inputs(const Mesh& mesh, const BakeOptions& options) {
    SHPRT_CHECK(options.K >= 1 && options.K <= kMaxBakeCoeffs, invalid_argument,
                "basis size K = {} is out of range (1 to {} coefficients, i.e. up to 32 bands)",
                options.K, kMaxBakeCoeffs);
    SHPRT_CHECK(options.samples >= 1, invalid_argument,
                "samples = 0: a bake needs at least one direction");
    SHPRT_CHECK(options.samples <= kMaxBakeSamples, invalid_argument,
                "samples = {} is too many (at most {})", options.samples, kMaxBakeSamples);
    SHPRT_CHECK(options.threads >= 0, invalid_argument, "threads = {} must be ≥ 0 (0 = all)",
                options.threads);
    const std::string name = mesh.source.empty() ? std::string("mesh") : mesh.source;
    SHPRT_CHECK(mesh.vertex_count() > 0, invalid_argument, "{} is empty: it has no vertices", name);
    SHPRT_CHECK(mesh.triangle_count() > 0, invalid_argument, "{} is empty: it has no triangles",
                name);
    SHPRT_CHECK(mesh.normals.size() == mesh.vertex_count(), invalid_argument,
                "{} has {} normals for {} vertices", name, mesh.normals.size(),
                mesh.vertex_count());
    SHPRT_CHECK(mesh.vertex_count() <= std::numeric_limits<std::uint32_t>::max(), invalid_argument,
                "{} has {} vertices, more than a bake supports (2^32 - 1)", name,
                mesh.vertex_count());
}

void validate_direction_set(const DirectionSet& directions) {
    SHPRT_CHECK(directions.size() >= 1, invalid_argument, "the direction set is empty");
    SHPRT_CHECK(directions.dirs.size() == 3 * directions.size(), invalid_argument,
                "the direction set has {} coordinates for {} weights (expected 3 per direction)",
                directions.dirs.size(), directions.size());
    SHPRT_CHECK(directions.size() <= kMaxBakeSamples, invalid_argument,
                "the direction set has {} directions (at most {})", directions.size(),
                kMaxBakeSamples);
}

BakeOptions checked_options(const Mesh& mesh, const BakeOptions& options,
                            const DirectionSet& directions) {
    BakeOptions checked = options;
    checked.samples = static_cast<std::uint32_t>(std::max<std::size_t>(directions.size(), 1));
    validate_direction_set(directions);
    validate_bake_inputs(mesh, checked);
    return checked;
}

TransferSet empty_transfer(const BakeOptions& options, std::size_t samples) {
    TransferSet out;
    out.kind = options.transfer;
    out.K = options.K;
    out.channels = 1;
    out.sampler = options.sampler;
    out.samples = static_cast<int>(samples);
    out.seed = options.seed;
    return out;
}

}  // namespace detail

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// The one place where a bake picks its backend: Device::cuda runs the GPU bake (gpu.hpp) or fails
// with query_gpu()'s one-line reason; Device::automatic takes the GPU when there is one.
enum class Backend { cpu, cuda };

Backend choose_backend(Device device) {
    switch (device) {
        case Device::cpu:
            return Backend::cpu;
        case Device::automatic:
            return query_gpu().available ? Backend::cuda : Backend::cpu;
        case Device::cuda:
            break;
    }
    const GpuInfo gpu = query_gpu();
    if (gpu.available) return Backend::cuda;
    fail(ErrorCode::unsupported, "device 'cuda': {}", gpu.reason);
}

TransferSet run_bake(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions) {
    switch (choose_backend(options.device)) {
        case Backend::cuda:
            return bake_gpu(mesh, options, directions);
        case Backend::cpu:
            break;
    }
    // Unshadowed transfer casts no rays: no BVH.
    std::unique_ptr<Tracer> tracer;
    double seconds_bvh = 0;
    if (options.transfer == TransferKind::shadowed) {
        // Embree builds with TBB tasks in the caller's arena: limit it to the bake's threads.
        const int threads =
            options.threads > 0 ? options.threads : tbb::info::default_concurrency();
        const auto start = Clock::now();
        tbb::task_arena(threads).execute([&] { tracer = make_embree_tracer(mesh); });
        seconds_bvh = seconds_since(start);
    }
    return detail::bake_cpu(mesh, options, directions, tracer.get(), seconds_bvh);
}

}  // namespace

std::size_t auto_chunk_vertices(std::size_t vertex_count, std::size_t samples) {
    constexpr std::size_t kRowBlock = 16;           // OpenBLAS SGEMM kernel row blocking
    constexpr std::size_t kTargetBytes = 1u << 20;  // W buffer per thread ~ 1 MiB (L2-sized)
    constexpr std::size_t kMinChunks = 64;          // load balance on many-core machines
    constexpr std::size_t kMaxChunk = 1024;
    const std::size_t by_memory = std::max<std::size_t>(
        1, kTargetBytes / (sizeof(float) * std::max<std::size_t>(samples, 1)));
    const std::size_t by_count =
        std::max<std::size_t>(1, (vertex_count + kMinChunks - 1) / kMinChunks);
    std::size_t chunk = std::min(by_memory, by_count);
    // Whole row blocks where they fit; below one block (huge S or a tiny mesh) memory wins.
    if (chunk >= kRowBlock) chunk = (chunk + kRowBlock - 1) / kRowBlock * kRowBlock;
    return std::min(chunk, kMaxChunk);
}

TransferSet bake(const Mesh& mesh, const BakeOptions& options) {
    detail::validate_bake_inputs(mesh, options);
    choose_backend(options.device);  // fail before generating directions
    const DirectionSet directions =
        make_direction_set(options.sampler, options.seed, options.samples);
    return run_bake(mesh, options, directions);
}

TransferSet bake(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions) {
    const BakeOptions checked = detail::checked_options(mesh, options, directions);
    return run_bake(mesh, checked, directions);
}

TransferSet bake_with_tracer(const Mesh& mesh, const BakeOptions& options,
                             const DirectionSet& directions, const Tracer& tracer) {
    const BakeOptions checked = detail::checked_options(mesh, options, directions);
    SHPRT_CHECK(options.device != Device::cuda, unsupported,
                "bake_with_tracer runs on the CPU only (device 'cuda' was asked for)");
    return detail::bake_cpu(mesh, checked, directions, &tracer, 0.0);
}

TransferSet bake_reference(const Mesh& mesh, const BakeOptions& options,
                           const DirectionSet& directions, const Tracer& tracer) {
    const BakeOptions checked = detail::checked_options(mesh, options, directions);
    const auto start = Clock::now();
    const int K = options.K;
    const std::size_t S = directions.size();
    const bool shadowed = options.transfer == TransferKind::shadowed;
    constexpr float kInf = std::numeric_limits<float>::infinity();

    TransferSet out = detail::empty_transfer(checked, S);
    out.coeffs.assign(mesh.vertex_count() * K, 0.0f);

    std::vector<double> y(K), sum(K);
    std::uint64_t rays = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const Vec3f nf = mesh.normals[v];
        const Vec3d n = cast<double>(nf);
        const Vec3f origin = offset_ray_origin(mesh.positions[v], nf);
        std::fill(sum.begin(), sum.end(), 0.0);
        for (std::size_t s = 0; s < S; ++s) {
            const Vec3f wf{directions.dirs[3 * s], directions.dirs[3 * s + 1],
                           directions.dirs[3 * s + 2]};
            const Vec3d w = cast<double>(wf);
            const double cosine = dot(n, w);
            if (cosine <= 0) continue;  // below the horizon: T = 0, no ray
            if (shadowed) {
                std::uint8_t occluded = 0;
                tracer.occluded(origin, &wf, 1, 0.0f, kInf, &occluded);
                ++rays;
                if (occluded) continue;
            }
            sh_eval_k<double>(K, w.x, w.y, w.z, y.data());
            const double t = cosine * double(directions.weights[s]);
            for (int i = 0; i < K; ++i) sum[i] += t * y[i];
        }
        for (int i = 0; i < K; ++i) out.coeffs[v * K + i] = static_cast<float>(sum[i]);
    }
    out.stats.rays_cast = rays;
    out.stats.seconds_total = out.stats.seconds_trace = seconds_since(start);
    out.stats.peak_bytes_host = out.coeffs.size() * sizeof(float);
    out.stats.device_name = "cpu: reference, 1 thread";
    return out;
}

}  // namespace shprt
