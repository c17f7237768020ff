// The GPU bake's host side (gpu.hpp): input checks, the flat BVH and the basis table on the host,
// the chunk plan, progress and statistics; the device work is src/cuda/gpu_bake_device.cpp.
// Built only with CUDA; gpu_fallback.cpp stands in otherwise.
//
// Sloan, Kautz & Snyder 2002 (PRT precompute), Green 2003 (Monte Carlo projection with a basis
// table); traversal after Aila & Laine 2009 (trace/flat_bvh.hpp).
#include "shprt/config.hpp"

#if SHPRT_HAS_CUDA

#include "bake/bake_internal.hpp"
#include "bake/progress.hpp"
#include "cuda/gpu_bake_device.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/bvh_build.hpp"

#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>

namespace shprt {
namespace {

// Fails with the one-line message bake() gives for a missing device.
void require_gpu(int device) {
    const GpuInfo gpu = query_gpu(device);
    SHPRT_CHECK(gpu.available, unsupported, "device 'cuda': {}", gpu.reason);
}

// Builds the flat BVH with Embree's TBB tasks limited to `threads` (0 = all), as the CPU bake does.
FlatBvh build_bvh(const Mesh& mesh, int threads) {
    FlatBvh bvh;
    const int n = threads > 0 ? threads : tbb::info::default_concurrency();
    tbb::task_arena(n).execute([&] { bvh = build_flat_bvh(mesh); });
    return bvh;
}

// The device's view of the occluders (`bvh`, null when unshadowed) and the receivers.
cuda::DeviceScene device_scene(const Receivers& receivers, const FlatBvh* bvh,
                               const DirectionSet& directions) {
    cuda::DeviceScene s;
    if (bvh) s.bvh = bvh->view();
    s.positions = receivers.positions;
    s.normals = receivers.normals;
    s.vertex_count = receivers.total;
    s.dirs = directions.dirs.data();
    s.weights = directions.weights.data();
    s.samples = directions.size();
    s.shadowed = bvh != nullptr;
    return s;
}

}  // namespace

namespace detail {

TransferInfo bake_gpu(const BakeJob& job, const BakeOptions& options,
                      const DirectionSet& directions) {
    const auto start = Clock::now();
    require_gpu(options.device_index);
    const cuda::DeviceState device = cuda::prepare_device(options.device_index);

    const Receivers& rx = job.receivers;
    const bool shadowed = options.transfer == TransferKind::shadowed;
    const std::size_t S = directions.size();
    const int K = options.K;
    FlatBvh bvh;
    double seconds_bvh = 0;
    if (shadowed) {  // unshadowed transfer casts no rays: no BVH
        const auto bvh_start = Clock::now();
        bvh = build_bvh(*job.occluders, options.threads);
        seconds_bvh = seconds_since(bvh_start);
    }
    const std::vector<float> Y = basis_table(K, directions);

    TransferInfo info = bake_info(options, rx, S);
    TransferSink& sink = *job.sink;
    sink.begin(info.layout, rx.first, rx.count);
    float* const device_output = sink.device_rows();

    ChunkPlanRequest request;
    request.vertices = rx.count;
    request.samples = S;
    request.K = K;
    request.free_device_bytes = device.free_bytes;
    request.fixed_device_bytes = gpu_bake_fixed_bytes(rx.total, S, K, shadowed ? bvh.bytes() : 0);
    request.device_output = device_output != nullptr;
    request.requested_chunk = options.chunk_receivers;
    const ChunkPlan plan = plan_chunks(request);

    BakeProgress progress(options.progress, shadowed, rx.count, S);
    cuda::DeviceBakeInput input;
    input.device = options.device_index;
    input.scene = device_scene(rx, shadowed ? &bvh : nullptr, directions);
    input.basis = Y.data();
    input.K = K;
    input.first = rx.first;
    input.count = rx.count;
    input.plan = plan;
    input.device_output = device_output;
    input.on_chunk_done = [&](std::size_t first, std::size_t count, const float* rows,
                              std::uint64_t rays) {
        sink.write(first, count, rows);
        progress.add(count, rays);
        return progress.poll();
    };
    const cuda::DeviceBakeResult result = cuda::run_device_bake(input);
    SHPRT_CHECK(!result.cancelled && progress.finish(), cancelled,
                "bake cancelled after {} of {} receivers", progress.receivers_done(), rx.count);
    sink.finish();

    BakeStats& st = info.stats;
    st.seconds_bvh = seconds_bvh;
    st.seconds_trace = result.seconds_trace;
    st.seconds_project = result.seconds_project;
    st.seconds_total = seconds_since(start);
    st.rays_cast = result.rays;
    st.peak_bytes_host =
        Y.size() * sizeof(float) + (shadowed ? bvh.bytes() : 0) + result.pinned_bytes;
    st.peak_bytes_device = result.peak_device_bytes;
    st.device_name = device.name;
    return info;
}

}  // namespace detail

std::vector<float> gpu_transfer_samples(const Mesh& mesh, TransferKind kind,
                                        const DirectionSet& directions, std::size_t first,
                                        std::size_t count, int device) {
    detail::validate_whole_mesh(mesh, kind, directions);
    require_gpu(device);
    const bool shadowed = kind == TransferKind::shadowed;
    FlatBvh bvh;
    if (shadowed) bvh = build_bvh(mesh, 0);
    return cuda::device_transfer_samples(
        device, device_scene(vertex_receivers(mesh), shadowed ? &bvh : nullptr, directions), first,
        count);
}

GpuTraversalResult measure_gpu_traversal(const Mesh& mesh, const DirectionSet& directions,
                                         int repeats, int device) {
    detail::validate_whole_mesh(mesh, TransferKind::shadowed, directions);
    require_gpu(device);
    const FlatBvh bvh = build_bvh(mesh, 0);
    return cuda::device_traversal_rate(
        device, device_scene(vertex_receivers(mesh), &bvh, directions), repeats);
}

}  // namespace shprt

#endif  // SHPRT_HAS_CUDA
