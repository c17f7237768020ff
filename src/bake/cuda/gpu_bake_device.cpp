// The device side of the GPU bake: uploads, the double-buffered chunk pipeline (transfer kernel,
// then cuBLAS SGEMM, then the copy back, on alternating streams), the test hook that returns the
// kernel's W, and the trace-only rate measurement.
//
// Sloan, Kautz & Snyder 2002 with Green 2003's Monte Carlo projection: per chunk of vertices the
// projection is the matrix product C[chunk×K] = W[chunk×S]·Y[S×K] (DESIGN.md "The compute path").
//
// Row-major products on a column-major BLAS (note 1). The kernel writes W transposed, as
// Wt[S×count] row-major (= W column-major, leading dimension count), so that a warp's 32 lanes
// (32 vertices, one direction) store to consecutive addresses. Y[S×K] row-major is Yᵀ column-major
// (K×S, ld K), and the row-major result C[count×K] is Cᵀ column-major (K×count, ld K). So
//   Cᵀ = Yᵀ · Wᵀ  is  cublasSgemm(N, T, m = K, n = count, k = S, Y, ld K, Wt, ld count, C, ld K).
#include "bake/cuda/gpu_bake_device.hpp"

#include "bake/cuda/cublas_loader.hpp"
#include "bake/cuda/device_buffer.hpp"
#include "bake/cuda/gpu_context.hpp"
#include "bake/cuda/transfer_kernels.hpp"
#include "bake/cuda/transport_kernels.hpp"
#include "shprt/core/error.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <memory>

namespace shprt::cuda {
namespace {

constexpr std::uint64_t kMaxThreads = 0x7FFFFFFFull;  // the kernels' 32-bit thread index

}  // namespace

class DeviceOccluders {
public:
    DeviceOccluders(int device, const FlatBvhView& bvh)
        : m_device(device),
          m_nodes(bvh.node_count),
          m_tri_verts(std::size_t(bvh.tri_count) * kFlatBvhTriStride),
          m_tri_ids(bvh.tri_count),
          m_node_count(bvh.node_count),
          m_tri_count(bvh.tri_count) {
        m_nodes.upload(bvh.nodes, m_nodes.size());
        m_tri_verts.upload(bvh.tri_verts, m_tri_verts.size());
        m_tri_ids.upload(bvh.tri_ids, m_tri_ids.size());
    }
    int device() const { return m_device; }
    std::uint64_t bytes() const {
        return m_nodes.bytes() + m_tri_verts.bytes() + m_tri_ids.bytes();
    }
    FlatBvhView view() const {
        return FlatBvhView{m_nodes.data(), m_tri_verts.data(), m_tri_ids.data(), m_node_count,
                           m_tri_count};
    }

private:
    int m_device;
    DeviceBuffer<FlatBvhNode> m_nodes;
    DeviceBuffer<float> m_tri_verts;
    DeviceBuffer<std::uint32_t> m_tri_ids;
    std::uint32_t m_node_count, m_tri_count;
};

std::shared_ptr<const DeviceOccluders> upload_occluders(int device, const FlatBvhView& bvh) {
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    GpuContext& context = gpu_context(device);
    SHPRT_CUDA_CHECK(cudaSetDevice(context.device));
    // The buffers are freed where they were made: on that device, under the lock.
    return std::shared_ptr<const DeviceOccluders>(
        new DeviceOccluders(device, bvh), [](const DeviceOccluders* o) {
            const std::lock_guard<std::mutex> held(gpu_mutex());
            cudaSetDevice(gpu_context(o->device()).device);
            delete o;
        });
}

namespace {

// The scene's arrays on the device, uploaded on construction; the BVH's taken from `kept`
// instead when it is given (DeviceBakeInput::occluders), counted in the tally all the same.
struct SceneBuffers {
    DeviceBuffer<FlatBvhNode> nodes;
    DeviceBuffer<float> tri_verts;
    DeviceBuffer<std::uint32_t> tri_ids;
    DeviceBuffer<Vec3f> positions, normals;
    DeviceBuffer<float> dirs, weights;
    std::uint32_t node_count = 0, tri_count = 0, samples = 0;
    bool shadowed = true, hemisphere = false, local = false;
    const DeviceOccluders* kept = nullptr;

    SceneBuffers(const DeviceScene& s, MemoryTally* tally,
                 const DeviceOccluders* kept_bvh = nullptr)
        : nodes(kept_bvh ? 0 : s.bvh.node_count, tally),
          tri_verts(kept_bvh ? 0 : std::size_t(s.bvh.tri_count) * kFlatBvhTriStride, tally),
          tri_ids(kept_bvh ? 0 : s.bvh.tri_count, tally),
          positions(s.vertex_count, tally),
          normals(s.vertex_count, tally),
          dirs(3 * s.samples, tally),
          weights(s.samples, tally),
          node_count(s.bvh.node_count),
          tri_count(s.bvh.tri_count),
          samples(static_cast<std::uint32_t>(s.samples)),
          shadowed(s.shadowed),
          hemisphere(s.hemisphere),
          local(s.local),
          kept(kept_bvh) {
        if (kept && tally) tally->add(kept->bytes());
        nodes.upload(s.bvh.nodes, nodes.size());
        tri_verts.upload(s.bvh.tri_verts, tri_verts.size());
        tri_ids.upload(s.bvh.tri_ids, tri_ids.size());
        positions.upload(s.positions, positions.size());
        normals.upload(s.normals, normals.size());
        dirs.upload(s.dirs, dirs.size());
        weights.upload(s.weights, weights.size());
    }

    TransferLaunch launch(std::size_t first, std::size_t count) const {
        TransferLaunch l;
        l.bvh = kept ? kept->view()
                     : FlatBvhView{nodes.data(), tri_verts.data(), tri_ids.data(), node_count,
                                   tri_count};
        l.positions = positions.data();
        l.normals = normals.data();
        l.dirs = dirs.data();
        l.weights = weights.data();
        l.first = static_cast<std::uint32_t>(first);
        l.count = static_cast<std::uint32_t>(count);
        l.samples = samples;
        l.shadowed = shadowed;
        l.hemisphere = hemisphere;
        l.local = local;
        return l;
    }
};

// The occluder mesh as A's entries read it, on the device (interreflected transfer only).
struct TransportMeshBuffers {
    DeviceBuffer<Vec3f> positions, albedo;
    DeviceBuffer<std::uint32_t> triangles;

    TransportMeshBuffers(const DeviceBakeInput& in, MemoryTally* tally)
        : positions(in.closest_hits ? in.mesh_vertices : 0, tally),
          albedo(positions.size(), tally),
          triangles(in.closest_hits ? 3 * in.mesh_triangles : 0, tally) {
        if (!in.closest_hits) return;
        positions.upload(in.mesh.positions, positions.size());
        albedo.upload(in.mesh.albedo, albedo.size());
        triangles.upload(in.mesh.triangles, triangles.size());
    }
    TransportMeshView view() const {
        return TransportMeshView{positions.data(), triangles.data(), albedo.data()};
    }
};

// One slot's buffers for the build of its chunk's block of A (transport_kernels.hpp): 80 bytes
// per entry, three entries per sample, the row starts and cub's storage (gpu.hpp's
// gpu_bake_bytes_per_vertex budgets them).
struct TransportSlot {
    DeviceBuffer<std::uint64_t> keys[2], out_keys;
    DeviceBuffer<std::uint32_t> order[2], kept, slot, nnz;
    DeviceBuffer<float> values, sums, value[3];
    DeviceBuffer<std::int32_t> row_start, column;
    DeviceBuffer<unsigned char> temp;
    PinnedBuffer<std::uint32_t> host_nnz;

    TransportSlot(std::size_t chunk, std::size_t samples, MemoryTally* tally) {
        const std::size_t n = 3 * chunk * samples;
        for (int b = 0; b < 2; ++b) {
            keys[b] = DeviceBuffer<std::uint64_t>(n, tally);
            order[b] = DeviceBuffer<std::uint32_t>(n, tally);
        }
        out_keys = DeviceBuffer<std::uint64_t>(n, tally);
        kept = DeviceBuffer<std::uint32_t>(n, tally);
        slot = DeviceBuffer<std::uint32_t>(n, tally);
        nnz = DeviceBuffer<std::uint32_t>(1, tally);
        values = DeviceBuffer<float>(3 * n, tally);
        sums = DeviceBuffer<float>(3 * n, tally);
        for (auto& v : value) v = DeviceBuffer<float>(n, tally);
        row_start = DeviceBuffer<std::int32_t>(chunk + 1, tally);
        column = DeviceBuffer<std::int32_t>(n, tally);
        std::size_t temp_bytes = 0;
        SHPRT_CUDA_CHECK(transport_build_temp_bytes(n, temp_bytes));
        temp = DeviceBuffer<unsigned char>(std::max<std::size_t>(1, temp_bytes), tally);
        host_nnz = PinnedBuffer<std::uint32_t>(1);
    }

    TransportBuildLaunch launch(const TransportBuildView& view) {
        TransportBuildLaunch l;
        l.view = view;
        for (int b = 0; b < 2; ++b) {
            l.keys[b] = keys[b].data();
            l.order[b] = order[b].data();
        }
        l.values = values.data();
        l.sums = sums.data();
        l.kept = kept.data();
        l.slot = slot.data();
        l.out_keys = out_keys.data();
        l.row_start = row_start.data();
        l.column = column.data();
        for (int c = 0; c < 3; ++c) l.value[c] = value[c].data();
        l.nnz = nnz.data();
        l.temp = temp.data();
        l.temp_bytes = temp.size();
        return l;
    }

    // The block of rows [first, first + count) once the build has run: its arrays copied back on
    // `stream` (waited for).
    TransportOperator::Block download(std::size_t first, std::size_t count, cudaStream_t stream) {
        const std::size_t n = host_nnz.data()[0];
        TransportOperator::Block block;
        block.first = first;
        block.row_start.resize(count + 1);
        block.column.resize(n);
        const auto get = [&](void* host, const void* device, std::size_t bytes) {
            if (bytes)
                SHPRT_CUDA_CHECK(
                    cudaMemcpyAsync(host, device, bytes, cudaMemcpyDeviceToHost, stream));
        };
        get(block.row_start.data(), row_start.data(), (count + 1) * sizeof(std::int32_t));
        get(block.column.data(), column.data(), n * sizeof(std::int32_t));
        for (int c = 0; c < 3; ++c) {
            block.values[std::size_t(c)].resize(n);
            get(block.values[std::size_t(c)].data(), value[c].data(), n * sizeof(float));
        }
        SHPRT_CUDA_CHECK(cudaStreamSynchronize(stream));
        return block;
    }
};

// Waits for the context's streams when the scope ends (normally or by an exception), so that no
// buffer is freed while work that uses it may still run. Errors are ignored: it runs in unwinding.
class StreamDrain {
public:
    explicit StreamDrain(const GpuContext& context) : m_context(context) {}
    ~StreamDrain() {
        for (cudaStream_t s : m_context.streams) cudaStreamSynchronize(s);
    }
    StreamDrain(const StreamDrain&) = delete;
    StreamDrain& operator=(const StreamDrain&) = delete;

private:
    const GpuContext& m_context;
};

// One chunk buffer of the pipeline with the events that time and fence its work.
struct Slot {
    DeviceBuffer<float> w;                     // Wt[S×chunk]
    DeviceBuffer<float> c;                     // C[chunk×K] (empty with device output)
    DeviceBuffer<unsigned long long> rays;     // rays cast by the chunk
    DeviceBuffer<SampleHit> hits;              // closest hits: S × chunk (interreflected only)
    std::unique_ptr<TransportSlot> transport;  // the build of A's block (interreflected only)
    PinnedBuffer<float> host_c;                // staging for the copy back
    PinnedBuffer<unsigned long long> host_rays;
    Event start, traced, projected, merged, done;
    cudaStream_t stream = nullptr;
    std::size_t first = 0, count = 0;
    bool busy = false;  // work enqueued and not yet finished on the host
};

}  // namespace

DeviceState prepare_device(int device) {
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    GpuContext& context = gpu_context(device);
    SHPRT_CUDA_CHECK(cudaSetDevice(context.device));
    std::size_t free_bytes = 0, total_bytes = 0;
    SHPRT_CUDA_CHECK(cudaMemGetInfo(&free_bytes, &total_bytes));
    return DeviceState{context.name, free_bytes, total_bytes, context.workspace_bytes * kStreams};
}

DeviceBakeResult run_device_bake(const DeviceBakeInput& in) {
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    GpuContext& context = gpu_context(in.device);
    SHPRT_CUDA_CHECK(cudaSetDevice(context.device));
    const ChunkPlan& plan = in.plan;
    const std::size_t S = in.scene.samples;
    const std::size_t K = static_cast<std::size_t>(in.K);
    const std::size_t range_end = in.first + in.count;
    SHPRT_CHECK(plan.slots >= 1 && plan.slots <= kStreams && plan.chunk_vertices >= 1 &&
                    std::uint64_t(plan.chunk_vertices) * S <= kMaxThreads,
                invalid_argument, "GPU bake: invalid chunk plan ({} vertices, {} slots)",
                plan.chunk_vertices, plan.slots);
    SHPRT_CHECK(in.first <= in.scene.vertex_count && in.count <= in.scene.vertex_count - in.first,
                invalid_argument, "GPU bake: receivers [{}, {}) outside the scene's {}", in.first,
                range_end, in.scene.vertex_count);
    const bool device_output = in.device_output != nullptr;
    SHPRT_CHECK(!in.closest_hits ||
                    (in.mesh_vertices == in.scene.vertex_count &&
                     in.mesh_vertices <= std::size_t(std::numeric_limits<std::int32_t>::max()) &&
                     3 * std::uint64_t(plan.chunk_vertices) * S <= kMaxThreads),
                invalid_argument,
                "GPU bake: interreflected transfer needs the mesh's {} vertices as receivers ({} "
                "given, at most 2^31 - 1) and chunks of under 2^31 / 3 entries ({} × {})",
                in.mesh_vertices, in.scene.vertex_count, plan.chunk_vertices, S);

    SHPRT_CHECK(!(in.closest_hits && in.scene.local), unsupported,
                "GPU bake: the closest-hit pass of interreflected transfer takes a sphere set");

    MemoryTally tally;
    SHPRT_CHECK(!in.occluders || in.occluders->device() == in.device, invalid_argument,
                "GPU bake: the kept occluders are on device {}, the bake on device {}",
                in.occluders ? in.occluders->device() : -1, in.device);
    const SceneBuffers scene(in.scene, &tally, in.occluders.get());
    const TransportMeshBuffers transport_mesh(in, &tally);
    DeviceBuffer<float> basis(S * K, &tally);
    basis.upload(in.basis, basis.size());
    std::vector<std::unique_ptr<Slot>> slots;
    DeviceBakeResult result;
    for (int b = 0; b < plan.slots; ++b) {
        auto slot = std::make_unique<Slot>();
        slot->w = DeviceBuffer<float>(plan.chunk_vertices * S, &tally);
        slot->rays = DeviceBuffer<unsigned long long>(1, &tally);
        slot->host_rays = PinnedBuffer<unsigned long long>(1);
        if (in.closest_hits) {
            slot->hits = DeviceBuffer<SampleHit>(plan.chunk_vertices * S, &tally);
            slot->transport = std::make_unique<TransportSlot>(plan.chunk_vertices, S, &tally);
            result.pinned_bytes += slot->transport->host_nnz.bytes();
        }
        if (!device_output) {
            slot->c = DeviceBuffer<float>(plan.chunk_vertices * K, &tally);
            slot->host_c = PinnedBuffer<float>(plan.chunk_vertices * K);
        }
        result.pinned_bytes += slot->host_c.bytes() + slot->host_rays.bytes();
        slots.push_back(std::move(slot));
    }
    const StreamDrain drain(context);  // destroyed before the buffers above

    const float one = 1.0f, zero = 0.0f;
    auto enqueue = [&](std::size_t chunk) {
        const int index = static_cast<int>(chunk % std::size_t(plan.slots));
        Slot& slot = *slots[std::size_t(index)];
        const cudaStream_t stream = context.streams[index];
        slot.stream = stream;
        slot.first = in.first + chunk * plan.chunk_vertices;
        slot.count = std::min(plan.chunk_vertices, range_end - slot.first);
        SHPRT_CUDA_CHECK(cudaMemsetAsync(slot.rays.data(), 0, sizeof(unsigned long long), stream));
        slot.start.record(stream);
        TransferLaunch launch = scene.launch(slot.first, slot.count);
        launch.w_t = slot.w.data();
        launch.rays = slot.rays.data();
        if (in.closest_hits) {
            launch.hits = slot.hits.data();
            SHPRT_CUDA_CHECK(launch_closest_hits(launch, stream));
        } else {
            SHPRT_CUDA_CHECK(launch_transfer(launch, stream));
        }
        slot.traced.record(stream);
        float* C = device_output ? in.device_output + (slot.first - in.first) * K : slot.c.data();
        const int m = in.K, n = static_cast<int>(slot.count), k = static_cast<int>(S);
        SHPRT_CUDA_CHECK(cublas().sgemm(context.blas[index], CUBLAS_OP_N, CUBLAS_OP_T, m, n, k,
                                        &one, basis.data(), m, slot.w.data(), n, &zero, C, m));
        slot.projected.record(stream);
        if (in.closest_hits) {
            TransportBuildView view;
            view.mesh = transport_mesh.view();
            view.normals = scene.normals.data();
            view.dirs = scene.dirs.data();
            view.weights = scene.weights.data();
            view.hits = slot.hits.data();
            view.first = static_cast<std::uint32_t>(slot.first);
            view.count = static_cast<std::uint32_t>(slot.count);
            view.samples = static_cast<std::uint32_t>(S);
            view.vertices = static_cast<std::uint32_t>(in.mesh_vertices);
            view.two_sided = in.two_sided;
            TransportSlot& t = *slot.transport;
            SHPRT_CUDA_CHECK(launch_transport_build(t.launch(view), stream));
            SHPRT_CUDA_CHECK(cudaMemcpyAsync(t.host_nnz.data(), t.nnz.data(), sizeof(std::uint32_t),
                                             cudaMemcpyDeviceToHost, stream));
        }
        slot.merged.record(stream);
        if (!device_output)
            SHPRT_CUDA_CHECK(cudaMemcpyAsync(slot.host_c.data(), C, slot.count * K * sizeof(float),
                                             cudaMemcpyDeviceToHost, stream));
        SHPRT_CUDA_CHECK(cudaMemcpyAsync(slot.host_rays.data(), slot.rays.data(),
                                         sizeof(unsigned long long), cudaMemcpyDeviceToHost,
                                         stream));
        slot.done.record(stream);
        slot.busy = true;
    };
    // Waits for a slot's chunk, books its times and rays, hands its rows to the callback. Returns
    // the callback's answer (false = cancel).
    auto finish = [&](Slot& slot) {
        SHPRT_CUDA_CHECK(cudaEventSynchronize(slot.done.get()));
        slot.busy = false;
        result.seconds_trace += elapsed_seconds(slot.start, slot.traced);
        result.seconds_project += elapsed_seconds(slot.traced, slot.projected);
        result.seconds_operator += elapsed_seconds(slot.projected, slot.merged);
        const std::uint64_t rays = slot.host_rays.data()[0];
        result.rays += rays;
        const float* rows = device_output ? nullptr : slot.host_c.data();
        if (in.closest_hits) {
            TransportOperator::Block block =
                slot.transport->download(slot.first, slot.count, slot.stream);
            if (in.on_transport_block) in.on_transport_block(std::move(block));
        }
        return in.on_chunk_done ? in.on_chunk_done(slot.first, slot.count, rows, rays) : true;
    };

    // Chunk c runs in slot c mod slots; before reusing a slot, the chunk that last used it is
    // finished on the host while the GPU works on the chunk in the other slot.
    std::size_t enqueued = 0;
    bool go = true;
    for (; enqueued < plan.chunk_count && go; ++enqueued) {
        Slot& slot = *slots[enqueued % std::size_t(plan.slots)];
        if (slot.busy && !finish(slot)) {
            go = false;
            break;
        }
        enqueue(enqueued);
    }
    const std::size_t first_open = enqueued > std::size_t(plan.slots) ? enqueued - plan.slots : 0;
    for (std::size_t c = first_open; c < enqueued && go; ++c) {
        Slot& slot = *slots[c % std::size_t(plan.slots)];
        if (slot.busy && !finish(slot)) go = false;
    }
    result.cancelled = !go;
    result.peak_device_bytes = tally.peak + context.workspace_bytes * kStreams;
    return result;
}

std::vector<float> device_transfer_samples(int device, const DeviceScene& s, std::size_t first,
                                           std::size_t count) {
    const std::size_t S = s.samples;
    SHPRT_CHECK(first <= s.vertex_count && count <= s.vertex_count - first, invalid_argument,
                "vertex range [{}, {}) is outside the mesh's {} vertices", first, first + count,
                s.vertex_count);
    SHPRT_CHECK(std::uint64_t(count) * S <= kMaxThreads, invalid_argument,
                "{} vertices × {} samples is too many for one launch", count, S);
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    GpuContext& context = gpu_context(device);
    SHPRT_CUDA_CHECK(cudaSetDevice(context.device));
    const SceneBuffers scene(s, nullptr);
    DeviceBuffer<float> w(count * S);
    DeviceBuffer<unsigned long long> rays(1);
    const cudaStream_t stream = context.streams[0];
    SHPRT_CUDA_CHECK(cudaMemsetAsync(rays.data(), 0, sizeof(unsigned long long), stream));
    TransferLaunch launch = scene.launch(first, count);
    launch.w_t = w.data();
    launch.rays = rays.data();
    SHPRT_CUDA_CHECK(launch_transfer(launch, stream));
    SHPRT_CUDA_CHECK(cudaStreamSynchronize(stream));
    std::vector<float> sample_major(count * S), out(count * S);
    w.download(sample_major.data(), sample_major.size());
    for (std::size_t j = 0; j < count; ++j)
        for (std::size_t k = 0; k < S; ++k) out[j * S + k] = sample_major[k * count + j];
    return out;
}

GpuTraversalResult device_traversal_rate(int device, const DeviceScene& s, int repeats) {
    SHPRT_CHECK(repeats >= 1, invalid_argument, "repeats = {} must be ≥ 1", repeats);
    SHPRT_CHECK(s.shadowed && s.bvh.node_count > 0, invalid_argument,
                "the traversal measurement needs a BVH");
    const std::lock_guard<std::mutex> lock(gpu_mutex());
    GpuContext& context = gpu_context(device);
    SHPRT_CUDA_CHECK(cudaSetDevice(context.device));
    const SceneBuffers scene(s, nullptr);
    DeviceBuffer<unsigned long long> counters(2);
    const cudaStream_t stream = context.streams[0];
    const std::size_t chunk =
        std::max<std::size_t>(1, static_cast<std::size_t>(kMaxThreads / s.samples));
    Event start, stop;
    GpuTraversalResult best;
    best.device_name = context.name;
    best.seconds = std::numeric_limits<double>::infinity();
    for (int run = 0; run <= repeats; ++run) {  // run 0 warms up
        SHPRT_CUDA_CHECK(cudaMemsetAsync(counters.data(), 0, counters.bytes(), stream));
        start.record(stream);
        for (std::size_t first = 0; first < s.vertex_count; first += chunk) {
            TransferLaunch launch = scene.launch(first, std::min(chunk, s.vertex_count - first));
            launch.rays = counters.data();
            launch.occluded = counters.data() + 1;
            SHPRT_CUDA_CHECK(launch_trace_only(launch, stream));
        }
        stop.record(stream);
        SHPRT_CUDA_CHECK(cudaStreamSynchronize(stream));
        unsigned long long counts[2] = {0, 0};
        counters.download(counts, 2);
        const double seconds = elapsed_seconds(start, stop);
        if (run == 0) {
            best.rays = counts[0];
            best.occluded = counts[1];
            continue;
        }
        SHPRT_CHECK(counts[0] == best.rays && counts[1] == best.occluded, cuda,
                    "the trace-only kernel counted {} rays / {} hits, then {} / {}: not "
                    "deterministic",
                    best.rays, best.occluded, counts[0], counts[1]);
        best.seconds = std::min(best.seconds, seconds);
    }
    return best;
}

}  // namespace shprt::cuda
