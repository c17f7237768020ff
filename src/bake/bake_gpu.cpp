// The GPU bake's host side (gpu.hpp): input checks, the flat BVH and the basis table on the host,
// the chunk plan, progress and statistics; the device work is src/cuda/gpu_bake_device.cpp.
// Built only with CUDA; gpu_fallback.cpp stands in otherwise.
//
// Sloan, Kautz & Snyder 2002 (PRT precompute), Green 2003 (Monte Carlo projection with a basis
// table); traversal after Aila & Laine 2009 (trace/flat_bvh.hpp).
#include "shprt/config.hpp"

#if SHPRT_HAS_CUDA

#include "bake/bake_internal.hpp"
#include "cuda/gpu_bake_device.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/bvh_build.hpp"

#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>

namespace shprt {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Fails with the one-line message bake() gives for a missing device.
void require_gpu() {
    const GpuInfo gpu = query_gpu();
    SHPRT_CHECK(gpu.available, unsupported, "device 'cuda': {}", gpu.reason);
}

// Builds the flat BVH with Embree's TBB tasks limited to `threads` (0 = all), as the CPU bake does.
FlatBvh build_bvh(const Mesh& mesh, int threads) {
    FlatBvh bvh;
    const int n = threads > 0 ? threads : tbb::info::default_concurrency();
    tbb::task_arena(n).execute([&] { bvh = build_flat_bvh(mesh); });
    return bvh;
}

cuda::DeviceScene device_scene(const Mesh& mesh, const FlatBvh* bvh,
                               const DirectionSet& directions) {
    cuda::DeviceScene s;
    if (bvh) s.bvh = bvh->view();
    s.positions = mesh.positions.data();
    s.normals = mesh.normals.data();
    s.vertex_count = mesh.vertex_count();
    s.dirs = directions.dirs.data();
    s.weights = directions.weights.data();
    s.samples = directions.size();
    s.shadowed = bvh != nullptr;
    return s;
}

}  // namespace

TransferSet bake_gpu(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions,
                     float* device_output) {
    const auto start = Clock::now();
    BakeOptions checked = options;
    checked.samples = static_cast<std::uint32_t>(std::max<std::size_t>(directions.size(), 1));
    detail::validate_direction_set(directions);
    detail::validate_bake_inputs(mesh, checked);
    require_gpu();
    const cuda::DeviceState device = cuda::prepare_device();

    const bool shadowed = options.transfer == TransferKind::shadowed;
    const std::size_t V = mesh.vertex_count(), S = directions.size();
    const int K = options.K;
    FlatBvh bvh;
    double seconds_bvh = 0;
    if (shadowed) {  // unshadowed transfer casts no rays: no BVH
        const auto bvh_start = Clock::now();
        bvh = build_bvh(mesh, options.threads);
        seconds_bvh = seconds_since(bvh_start);
    }
    const std::vector<float> Y = basis_table(K, directions);

    ChunkPlanRequest request;
    request.vertices = V;
    request.samples = S;
    request.K = K;
    request.free_device_bytes = device.free_bytes;
    request.fixed_device_bytes = gpu_bake_fixed_bytes(V, S, K, shadowed ? bvh.bytes() : 0);
    request.device_output = device_output != nullptr;
    request.requested_chunk = options.chunk_vertices;
    const ChunkPlan plan = plan_chunks(request);

    TransferSet out = detail::empty_transfer(options, S);
    if (!device_output) out.coeffs.assign(V * std::size_t(K), 0.0f);

    // Progress as the CPU bake reports it: rays (estimated total from the rays per vertex so far)
    // for shadowed transfer, samples for unshadowed; at most ~20 reports a second and one at the
    // end.
    std::uint64_t rays_done = 0, vertices_done = 0;
    auto last_report = Clock::now();
    constexpr auto kReportInterval = std::chrono::milliseconds(50);
    auto report = [&](bool final) {
        if (!shadowed)
            return options.progress(
                ProgressInfo{"bake", vertices_done * S, std::uint64_t(V) * S, "samples"});
        const double per_vertex =
            vertices_done > 0 ? double(rays_done) / double(vertices_done) : double(S) / 2;
        const std::uint64_t total =
            final ? rays_done
                  : rays_done + std::uint64_t(per_vertex * double(V - vertices_done) + 0.5);
        return options.progress(
            ProgressInfo{"bake", rays_done, std::max(total, rays_done), "rays"});
    };

    const cuda::DeviceScene scene = device_scene(mesh, shadowed ? &bvh : nullptr, directions);
    cuda::DeviceBakeInput input;
    input.scene = scene;
    input.basis = Y.data();
    input.K = K;
    input.plan = plan;
    input.host_output = device_output ? nullptr : out.coeffs.data();
    input.device_output = device_output;
    input.on_chunk_done = [&](std::size_t first, std::size_t count, const float* coeffs,
                              std::uint64_t rays) {
        rays_done += rays;
        vertices_done += count;
        if (options.on_chunk) options.on_chunk(first, count, coeffs);
        if (!options.progress || vertices_done == V) return true;
        const auto now = Clock::now();
        if (now - last_report < kReportInterval) return true;
        last_report = now;
        return report(false);
    };
    const cuda::DeviceBakeResult result = cuda::run_device_bake(input);
    bool stopped = result.cancelled;
    if (!stopped && options.progress && !report(true)) stopped = true;
    SHPRT_CHECK(!stopped, cancelled, "bake cancelled after {} of {} vertices", vertices_done, V);

    BakeStats& st = out.stats;
    st.seconds_bvh = seconds_bvh;
    st.seconds_trace = result.seconds_trace;
    st.seconds_project = result.seconds_project;
    st.seconds_total = seconds_since(start);
    st.rays_cast = result.rays;
    st.peak_bytes_host = out.coeffs.size() * sizeof(float) + Y.size() * sizeof(float) +
                         (shadowed ? bvh.bytes() : 0) + result.pinned_bytes;
    st.peak_bytes_device = result.peak_device_bytes;
    st.device_name = device.name;
    return out;
}

std::vector<float> gpu_transfer_samples(const Mesh& mesh, TransferKind kind,
                                        const DirectionSet& directions, std::size_t first,
                                        std::size_t count) {
    BakeOptions checked;
    checked.transfer = kind;
    checked.samples = static_cast<std::uint32_t>(std::max<std::size_t>(directions.size(), 1));
    detail::validate_direction_set(directions);
    detail::validate_bake_inputs(mesh, checked);
    require_gpu();
    const bool shadowed = kind == TransferKind::shadowed;
    FlatBvh bvh;
    if (shadowed) bvh = build_bvh(mesh, 0);
    return cuda::device_transfer_samples(device_scene(mesh, shadowed ? &bvh : nullptr, directions),
                                         first, count);
}

GpuTraversalResult measure_gpu_traversal(const Mesh& mesh, const DirectionSet& directions,
                                         int repeats) {
    BakeOptions checked;
    checked.samples = static_cast<std::uint32_t>(std::max<std::size_t>(directions.size(), 1));
    detail::validate_direction_set(directions);
    detail::validate_bake_inputs(mesh, checked);
    require_gpu();
    const FlatBvh bvh = build_bvh(mesh, 0);
    return cuda::device_traversal_rate(device_scene(mesh, &bvh, directions), repeats);
}

}  // namespace shprt

#endif  // SHPRT_HAS_CUDA
