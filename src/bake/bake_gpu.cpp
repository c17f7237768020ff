// The GPU bake's host side (gpu.hpp): input checks, the flat BVH and the basis table on the host,
// the chunk plan, progress and statistics; the device work is src/bake/cuda/gpu_bake_device.cpp.
// Built only with CUDA; gpu_fallback.cpp stands in otherwise.
//
// Sloan, Kautz & Snyder 2002 (PRT precompute), Green 2003 (Monte Carlo projection with a basis
// table); traversal after Aila & Laine 2009 (trace/flat_bvh.hpp).
#include "shprt/config.hpp"

#if SHPRT_HAS_CUDA

#include "bake/bake_internal.hpp"
#include "bake/bake_progress.hpp"
#include "bake/cuda/gpu_bake_device.hpp"
#include "bake/error_bound.hpp"
#include "bake/stages.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/bvh_build.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

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
    in_arena(threads, [&] { bvh = build_flat_bvh(mesh); });
    return bvh;
}

// The device's view of the occluders (`bvh`, null when unshadowed) and the receivers.
cuda::DeviceScene device_scene(const Receivers& receivers, const FlatBvh* bvh,
                               const DirectionSet& directions,
                               DirectionFrame frame = DirectionFrame::sphere) {
    cuda::DeviceScene s;
    if (bvh) s.bvh = bvh->view();
    s.positions = receivers.positions;
    s.normals = receivers.normals;
    s.vertex_count = receivers.total;
    s.dirs = directions.dirs.data();
    s.weights = directions.weights.data();
    s.samples = directions.size();
    s.shadowed = bvh != nullptr;
    s.local = frame == DirectionFrame::local;
    return s;
}

// The device memory a GPU bake plans with (BakeOptions::device_memory_budget): the budget, at
// most what is free, all of it usable; else what is free, 90% of it usable.
struct DeviceMemory {
    std::uint64_t bytes = 0;
    double usable_fraction = 0.9;
};

DeviceMemory device_memory(const BakeOptions& options, std::uint64_t free_bytes) {
    if (options.device_memory_budget == 0) return DeviceMemory{free_bytes, 0.9};
    return DeviceMemory{std::min(free_bytes, options.device_memory_budget), 1.0};
}

// A GPU bake's stats: the device's times and rays, the host's BVH build and rotation (local
// sets), and the host bytes it held besides the pinned staging.
void fill_gpu_stats(BakeStats& st, const cuda::DeviceBakeResult& result, double seconds_bvh,
                    double seconds_rotate, Clock::time_point start, std::uint64_t host_bytes,
                    const std::string& device_name) {
    st.seconds_bvh = seconds_bvh;
    st.seconds_trace = result.seconds_trace;
    st.seconds_project = result.seconds_project + seconds_rotate;
    st.seconds_total = seconds_since(start);
    st.rays_cast = result.rays;
    st.peak_bytes_host = host_bytes + result.pinned_bytes;
    st.peak_bytes_device = result.peak_device_bytes;
    st.device_name = device_name;
}

// T_0's rows and A from one pass of closest hits on the device: W projected by cuBLAS, and from
// the hits A's rows, one block per chunk, built on the device with the CPU builder's arithmetic
// (transport_build.hpp), so the same bits. Receivers must be the mesh's vertices.
struct DeviceTransportPass {
    std::vector<float> T0;  // V × K
    TransportOperator A;
    cuda::DeviceBakeResult result;
};

DeviceTransportPass trace_transport_on_device(const Mesh& mesh, const Receivers& rx,
                                              const FlatBvh& bvh, const DirectionSet& directions,
                                              const std::vector<float>& Y, int K,
                                              const cuda::DeviceState& device,
                                              const BakeOptions& options,
                                              detail::BakeProgress& progress) {
    const std::size_t V = rx.count, S = directions.size();
    ChunkPlanRequest request;
    request.vertices = V;
    request.samples = S;
    request.K = K;
    const DeviceMemory memory = device_memory(options, device.free_bytes);
    request.free_device_bytes = memory.bytes;
    request.usable_fraction = memory.usable_fraction;
    // The occluder mesh for A's entries: positions and albedo per vertex, three indices per
    // triangle.
    const std::uint64_t mesh_bytes =
        std::uint64_t(mesh.vertex_count()) * 2 * sizeof(Vec3f) +
        std::uint64_t(mesh.triangle_count()) * 3 * sizeof(std::uint32_t);
    request.fixed_device_bytes = gpu_bake_fixed_bytes(rx.total, S, K, bvh.bytes()) + mesh_bytes;
    request.closest_hits = true;
    request.requested_chunk = options.chunk_receivers;
    // A slot's build of A takes ~250 bytes per sample: chunks of the default 64 MiB would be ~250
    // vertices, too few rays per launch to fill a GPU. A GiB is ~4 000 vertices at S = 1024.
    request.max_slot_bytes = std::uint64_t(1) << 30;
    const ChunkPlan plan = plan_chunks(request);

    DeviceTransportPass pass;
    pass.T0.resize(V * std::size_t(K));
    pass.A.vertices = V;
    cuda::DeviceBakeInput input;
    input.device = options.device_index;
    input.scene = device_scene(rx, &bvh, directions);
    input.basis = Y.data();
    input.K = K;
    input.first = 0;
    input.count = V;
    input.plan = plan;
    input.closest_hits = true;
    input.mesh = transport_mesh_view(mesh);
    input.mesh_vertices = mesh.vertex_count();
    input.mesh_triangles = mesh.triangle_count();
    input.two_sided = options.two_sided;
    // The blocks past BakeOptions::memory_budget's share for A are spilled, as on the CPU.
    detail::TransportBlockStore store(detail::transport_memory_budget(mesh, options),
                                      options.spill_directory);
    input.on_transport_block = [&](TransportOperator::Block&& block) {
        pass.A.blocks.push_back(std::move(block));
        store.keep(pass.A.blocks.size() - 1, pass.A.blocks.back());
    };
    input.on_chunk_done = [&](std::size_t first, std::size_t count, const float* rows,
                              std::uint64_t rays) {
        std::copy_n(rows, count * std::size_t(K), pass.T0.data() + first * std::size_t(K));
        progress.add(count, rays);
        return progress.poll();
    };
    pass.result = cuda::run_device_bake(input);
    SHPRT_CHECK(!pass.result.cancelled && progress.finish(), cancelled,
                "bake cancelled after {} of {} receivers", progress.receivers_done(), V);
    pass.A.rays_cast = pass.result.rays;
    store.finish(pass.A);
    return pass;
}

}  // namespace

namespace detail {

struct GpuOccluders {
    FlatBvh bvh;                                          // on the host (the device's layout)
    std::shared_ptr<const cuda::DeviceOccluders> device;  // its copy on the device
};

namespace {

// The occluders of a bake that casts rays: the session's kept ones, else built and uploaded now
// (and kept, when the session asks). `seconds_bvh`: the host build's time, 0 when kept.
std::shared_ptr<GpuOccluders> gpu_occluders(const BakeJob& job, const BakeOptions& options,
                                            std::size_t samples,
                                            std::shared_ptr<GpuOccluders>* kept,
                                            double& seconds_bvh) {
    seconds_bvh = 0;
    if (kept && *kept) return *kept;
    const auto start = Clock::now();
    auto made = std::make_shared<GpuOccluders>();
    // Visibility only: the merged coplanar triangles where the bake casts enough rays to pay for
    // the merge, as the CPU's tracer (bake_tracer_options).
    if (bake_tracer_options(job, options, samples).merge_coplanar)
        made->bvh = build_bvh(merged_mesh(*job.occluders), options.threads);
    else
        made->bvh = build_bvh(*job.occluders, options.threads);
    seconds_bvh = seconds_since(start);
    made->device = cuda::upload_occluders(options.device_index, made->bvh.view());
    if (kept) *kept = made;
    return made;
}

// The error-bounded bake on the device (bake.hpp, gpu_target_error_refusal: shadowed or
// unshadowed vectors, a local set): the CPU's passes, estimates and guards
// (error_bound.hpp, bake_segments_to_error), each segment of the nested set baked for the rows
// still over the target by the device pipeline — those rows' positions and normals gathered, the
// segment's directions, weights and rows of Y — and the rows rotated and written on the host.
// The receivers go in blocks of kBoundBlock, so the host keeps a block's sums, not the range's;
// the BVH is uploaded once (cuda::upload_occluders) and kept on the device for every segment.
// Unverified on a GPU so far: the orchestration is tested on the CPU with the CPU's stages as the
// segments' backend (ErrorBound.SegmentsFromAnotherBackendStopWhereTheCpuBoundStops).
TransferInfo bake_gpu_bounded(const BakeJob& job, const BakeOptions& options,
                              const DirectionSet& directions, const cuda::DeviceState& device,
                              std::shared_ptr<GpuOccluders>* kept) {
    constexpr std::size_t kBoundBlock = std::size_t(1) << 16;
    const auto start = Clock::now();
    const Receivers& rx = job.receivers;
    const bool shadowed = kind_row(options.transfer).traces_rays;
    const std::size_t S = directions.size();
    const int K = options.K, KL = projected_coeffs(options);
    // The BVH goes to the device once and stays there for every segment of every block (and,
    // in a session, every pass).
    double seconds_bvh = 0;
    const std::shared_ptr<GpuOccluders> occluders =
        shadowed ? gpu_occluders(job, options, S, kept, seconds_bvh) : nullptr;
    const std::vector<float> Y = basis_table(KL, directions);
    const DirectionTable table =
        make_direction_table(directions, DirectionFrame::local, kTargetFirstSamples);
    const ErrorBound bound = make_error_bound(options, table, Y.data(), KL, shadowed);

    TransferInfo info = bake_info(options, rx, S);
    TransferSink& sink = *job.sink;
    sink.begin(info.layout, rx.first, rx.count);
    SHPRT_CHECK(sink.device_rows() == nullptr, unsupported,
                "a GPU bake with a local direction set rotates its rows on the host, so it cannot "
                "write into a device buffer; bake with the sphere set (--directions sphere)");
    sink.begin_estimates();
    BakeProgress progress(options.progress, shadowed, rx.count, S);
    const DeviceMemory memory = device_memory(options, device.free_bytes);

    std::size_t block_first = 0;  // the block's first receiver of the range
    std::vector<Vec3f> positions, normals;
    cuda::DeviceBakeResult total;
    // Directions [from, to) for the gathered rows, into `out` (m × KL).
    auto bake_rows = [&](std::size_t m, std::size_t from, std::size_t to, float* out) {
        cuda::DeviceBakeInput input;
        input.device = options.device_index;
        if (shadowed) {
            input.scene.bvh = occluders->bvh.view();
            input.occluders = occluders->device;
        }
        input.scene.positions = positions.data();
        input.scene.normals = normals.data();
        input.scene.vertex_count = m;
        input.scene.dirs = directions.dirs.data() + 3 * from;
        input.scene.weights = directions.weights.data() + from;
        input.scene.samples = to - from;
        input.scene.shadowed = shadowed;
        input.scene.local = true;
        input.basis = Y.data() + from * std::size_t(KL);
        input.K = KL;
        input.first = 0;
        input.count = m;
        ChunkPlanRequest request;
        request.vertices = m;
        request.samples = to - from;
        request.K = KL;
        request.free_device_bytes = memory.bytes;
        request.usable_fraction = memory.usable_fraction;
        request.fixed_device_bytes =
            gpu_bake_fixed_bytes(m, to - from, KL, shadowed ? occluders->bvh.bytes() : 0);
        request.requested_chunk = options.chunk_receivers;
        input.plan = plan_chunks(request);
        input.on_chunk_done = [&](std::size_t first, std::size_t count, const float* rows,
                                  std::uint64_t) {
            std::copy_n(rows, count * std::size_t(KL), out + first * std::size_t(KL));
            return progress.poll();
        };
        const cuda::DeviceBakeResult r = cuda::run_device_bake(input);
        total.seconds_trace += r.seconds_trace;
        total.seconds_project += r.seconds_project;
        total.rays += r.rays;
        total.peak_device_bytes = std::max(total.peak_device_bytes, r.peak_device_bytes);
        total.pinned_bytes = std::max(total.pinned_bytes, r.pinned_bytes);
        SHPRT_CHECK(!r.cancelled, cancelled, "bake cancelled after {} of {} receivers",
                    progress.receivers_done(), rx.count);
        return r.rays;
    };
    const SegmentBaker segment = [&](const std::uint32_t* ids, std::size_t m, std::size_t a,
                                     std::size_t b, float* G, float* halves) {
        positions.resize(m);
        normals.resize(m);
        for (std::size_t i = 0; i < m; ++i) {
            positions[i] = rx.positions[rx.first + block_first + ids[i]];
            normals[i] = rx.normals[rx.first + block_first + ids[i]];
        }
        std::uint64_t rays = 0;
        if (halves) {
            rays += bake_rows(m, a, (a + b) / 2, halves);
            rays += bake_rows(m, (a + b) / 2, b, G);
        } else {
            rays += bake_rows(m, a, b, G);
        }
        progress.add(0, rays);
        return rays;
    };
    ErrorBoundScratch scratch;
    std::vector<float> world;
    double seconds_rotate = 0;
    for (; block_first < rx.count; block_first += kBoundBlock) {
        const std::size_t n = std::min(kBoundBlock, rx.count - block_first);
        const BoundRows rows = scratch.fresh_rows(n, KL);
        bake_segments_to_error(bound, n, segment, rows, scratch, progress);
        SHPRT_CHECK(!progress.stopped(), cancelled, "bake cancelled after {} of {} receivers",
                    progress.receivers_done(), rx.count);
        const auto rotate_start = Clock::now();
        world.resize(n * std::size_t(K));
        rotate_rows_to_world(rx.normals + rx.first + block_first, n, KL, K, false,
                             scratch.out.data(), world.data());
        seconds_rotate += seconds_since(rotate_start);
        progress.add_errors(rows.error, n, options.target_error);
        progress.add(n, 0);
        sink.write(rx.first + block_first, n, world.data());
        sink.write_estimates(rx.first + block_first, n, rows.samples, rows.error);
    }
    SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled after {} of {} receivers",
                progress.receivers_done(), rx.count);
    sink.finish();

    fill_gpu_stats(info.stats, total, seconds_bvh, seconds_rotate, start,
                   (Y.size() + world.capacity() + scratch.acc.capacity()) * sizeof(float) +
                       table.bytes() + (shadowed ? occluders->bvh.bytes() : 0),
                   device.name);
    return info;
}

}  // namespace

TransferInfo bake_gpu(const BakeJob& job, const BakeOptions& options,
                      const DirectionSet& directions, std::shared_ptr<GpuOccluders>* kept) {
    const auto start = Clock::now();
    require_gpu(options.device_index);
    const cuda::DeviceState device = cuda::prepare_device(options.device_index);
    if (options.target_error > 0) return bake_gpu_bounded(job, options, directions, device, kept);

    const Receivers& rx = job.receivers;
    // Glossy matrices: W without the cosine, projected on the pair-product table (the CPU
    // bake's two changes, bake.hpp); the SGEMM then has K(K+1)/2 columns.
    const TransferKindRow& row = kind_row(options.transfer);
    const bool glossy = is_matrix(row);
    const bool shadowed = row.traces_rays;
    const std::size_t S = directions.size();
    const int K = options.K;
    const int F = glossy ? K * (K + 1) / 2 : K;
    // A local set (docs/sampling.md): the kernel turns each direction into its receiver's frame,
    // the SGEMM projects onto the KL ≥ K coefficients of the full bands in the frame (FL
    // columns), and the host rotates each chunk's rows to world space (rotate_rows_to_world, the
    // CPU bake's own code) before the sink takes them.
    const bool local = options.direction_frame == DirectionFrame::local;
    const int KL = projected_coeffs(options);
    const int FL = glossy ? KL * (KL + 1) / 2 : KL;
    double seconds_bvh = 0;  // unshadowed transfer casts no rays: no BVH
    const std::shared_ptr<GpuOccluders> occluders =
        shadowed ? gpu_occluders(job, options, S, kept, seconds_bvh) : nullptr;
    std::vector<float> Y = basis_table(KL, directions);
    if (glossy) Y = pair_product_table(Y, S, KL);

    TransferInfo info = bake_info(options, rx, S);
    TransferSink& sink = *job.sink;
    sink.begin(info.layout, rx.first, rx.count);
    float* const device_output = sink.device_rows();
    SHPRT_CHECK(!(local && device_output), unsupported,
                "a GPU bake with a local direction set rotates its rows on the host, so it cannot "
                "write into a device buffer; bake with the sphere set (--directions sphere)");

    ChunkPlanRequest request;
    request.vertices = rx.count;
    request.samples = S;
    request.K = FL;
    const DeviceMemory memory = device_memory(options, device.free_bytes);
    request.free_device_bytes = memory.bytes;
    request.usable_fraction = memory.usable_fraction;
    request.fixed_device_bytes =
        gpu_bake_fixed_bytes(rx.total, S, FL, shadowed ? occluders->bvh.bytes() : 0);
    request.device_output = device_output != nullptr;
    request.requested_chunk = options.chunk_receivers;
    const ChunkPlan plan = plan_chunks(request);

    BakeProgress progress(options.progress, shadowed, rx.count, S);
    cuda::DeviceBakeInput input;
    input.device = options.device_index;
    input.scene =
        device_scene(rx, shadowed ? &occluders->bvh : nullptr, directions, options.direction_frame);
    if (shadowed) input.occluders = occluders->device;
    input.scene.hemisphere = !row.cosine;
    input.basis = Y.data();
    input.K = FL;
    input.first = rx.first;
    input.count = rx.count;
    input.plan = plan;
    input.device_output = device_output;
    // A local set's rows get the open part exactly (stages.hpp, OpenControl) before the rotation.
    const OpenControl open_control =
        local && options.open_control
            ? make_open_control(directions.weights.data(), Y.data(), S, 1.0, KL, glossy)
            : OpenControl{};
    std::vector<float> controlled;  // a local set's rows, corrected (count × FL)
    std::vector<float> world;       // and rotated (count × F)
    double seconds_rotate = 0;
    input.on_chunk_done = [&](std::size_t first, std::size_t count, const float* rows,
                              std::uint64_t rays) {
        if (local) {
            const auto rotate_start = Clock::now();
            if (!open_control.delta.empty()) {
                controlled.assign(rows, rows + count * std::size_t(FL));
                apply_open_control(open_control, controlled.data(), count);
                rows = controlled.data();
            }
            world.resize(count * std::size_t(F));
            rotate_rows_to_world(rx.normals + first, count, KL, K, glossy, rows, world.data());
            rows = world.data();
            seconds_rotate += seconds_since(rotate_start);
        }
        sink.write(first, count, rows);
        progress.add(count, rays);
        return progress.poll();
    };
    const cuda::DeviceBakeResult result = cuda::run_device_bake(input);
    SHPRT_CHECK(!result.cancelled && progress.finish(), cancelled,
                "bake cancelled after {} of {} receivers", progress.receivers_done(), rx.count);
    sink.finish();

    fill_gpu_stats(
        info.stats, result, seconds_bvh, seconds_rotate, start,
        (Y.size() + world.capacity()) * sizeof(float) + (shadowed ? occluders->bvh.bytes() : 0),
        device.name);
    return info;
}

TransferInfo bake_interreflected_gpu(const BakeJob& job, const BakeOptions& options,
                                     const DirectionSet& directions) {
    const auto start = Clock::now();
    check_interreflected_job(job);
    const int wanted = options.converge ? options.max_bounces : options.bounces;
    // T_0: the shadowed GPU bake itself, with every direction.
    BakeOptions direct_options = direct_stage_options(options);
    HostSink direct_sink;
    BakeJob direct_job = job;
    direct_job.sink = &direct_sink;
    TransferInfo info = bake_gpu(direct_job, direct_options, directions);
    if (wanted == 0)
        return finish_interreflected(job, options, std::move(info), direct_sink.take_rows(), {},
                                     BounceSourceRays{}, TransportOperator{}, {}, 0,
                                     seconds_since(start));
    // The operator over the bounce sources: traced on the host by the CPU's code over the flat
    // BVH (the device build of A, trace_transport_on_device, reads the vertex mesh only and returns
    // no validity counts; docs/interreflection.md "Not done"), then the bounces on the device.
    const Mesh& mesh = *job.occluders;
    const int K = options.K;
    const auto bvh_start = Clock::now();
    // The flat BVH's traversal, the device's own (SHPRT_HD): the hits the device would find.
    const auto tracer = make_flat_bvh_tracer(mesh);
    info.stats.seconds_bvh += seconds_since(bvh_start);
    SourceOperator op = trace_source_operator(mesh, options, directions, *tracer, info.stats);
    const TransportOperator& A = op.A;
    const std::size_t N = A.vertices;

    // The bounces keep on the device what fits of A; the rest is copied in per bounce.
    std::vector<std::uint64_t> block_bytes;
    for (const TransportOperator::Block& b : A.blocks) block_bytes.push_back(b.bytes());
    const DeviceMemory memory =
        device_memory(options, cuda::prepare_device(options.device_index).free_bytes);
    const TransportResidency residency =
        plan_transport_residency(block_bytes, 2 * std::uint64_t(N) * 3 * K * sizeof(float),
                                 memory.bytes, memory.usable_fraction);
    if (residency.streamed_bytes > 0)
        log_info(
            "GPU bounces: {:.1f} of A's {:.1f} MiB do not fit the device's memory and are "
            "copied in per bounce",
            double(residency.streamed_bytes) / double(1 << 20),
            double(A.bytes()) / double(1 << 20));
    cuda::DeviceTransport transport(options.device_index, A, K, residency.resident_blocks);
    info.stats.peak_bytes_device = std::max(info.stats.peak_bytes_device, transport.device_bytes());
    const double seconds = seconds_since(start);
    return finish_interreflected(
        job, options, std::move(info), direct_sink.take_rows(), std::move(op.T0_sources), op.rays,
        A,
        [&, in3 = std::vector<float>(), out3 = std::vector<float>()](const BounceRows& p,
                                                                     BakeProgress& rows) mutable {
            // The device computes every row and column of A·in (cuSPARSE's product of each block),
            // once per bounce — at the bounce's first call, rows from 0 —, in the 3 × K layout;
            // each call copies out what it asks for (the same sums: the same bits).
            const std::size_t row = 3 * std::size_t(K);
            if (p.first == 0) {
                in3.resize(N * row);
                for (std::size_t q = 0; q < N; ++q)
                    for (int c = 0; c < 3; ++c)
                        std::copy_n(p.in + q * std::size_t(p.in_channels * p.in_K) +
                                        (p.in_channels == 3 ? std::size_t(c * p.in_K) : 0),
                                    p.in_K, in3.data() + q * row + std::size_t(c) * K);
                out3.resize(N * row);
                transport.apply(in3.data(), out3.data());
            }
            for (std::size_t q = p.first; q < p.end; ++q)
                for (int c = 0; c < 3; ++c)
                    std::copy_n(out3.data() + q * row + std::size_t(c) * K, p.columns,
                                p.out + (q - p.first) * 3 * std::size_t(p.out_K) +
                                    std::size_t(c) * std::size_t(p.out_K));
            rows.add(p.end - p.first, 0);
            rows.poll();
        },
        op.pass_bytes + tracer->memory_bytes(), seconds);
}

}  // namespace detail

std::vector<float> gpu_transfer_samples(const Mesh& mesh, TransferKind kind,
                                        const DirectionSet& directions, std::size_t first,
                                        std::size_t count, DirectionFrame frame, int device) {
    detail::validate_whole_mesh(mesh, kind, directions);
    require_gpu(device);
    const bool shadowed = kind == TransferKind::shadowed;
    FlatBvh bvh;
    if (shadowed) bvh = build_bvh(mesh, 0);
    return cuda::device_transfer_samples(
        device, device_scene(vertex_receivers(mesh), shadowed ? &bvh : nullptr, directions, frame),
        first, count);
}

TransportOperator gpu_transport_operator(const Mesh& mesh, const DirectionSet& directions,
                                         bool two_sided, std::size_t chunk, int device) {
    detail::validate_whole_mesh(mesh, TransferKind::interreflected, directions);
    SHPRT_CHECK(!two_sided, unsupported,
                "the device build of A is one-sided over the vertices (two-sided sources have "
                "back copies the device does not take yet)");
    SHPRT_CHECK(mesh.albedo.size() == mesh.vertex_count(), invalid_argument,
                "interreflected transfer needs an albedo per vertex ({} vertices, {} values)",
                mesh.vertex_count(), mesh.albedo.size());
    require_gpu(device);
    const cuda::DeviceState state = cuda::prepare_device(device);
    const FlatBvh bvh = build_bvh(mesh, 0);
    BakeOptions options;
    options.device_index = device;
    options.chunk_receivers = chunk;
    options.two_sided = two_sided;
    detail::BakeProgress progress({}, true, mesh.vertex_count(), directions.size());
    return trace_transport_on_device(mesh, vertex_receivers(mesh), bvh, directions,
                                     basis_table(1, directions), 1, state, options, progress)
        .A;
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
