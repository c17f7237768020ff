// The CPU bake: visibility by stream ray casting, projection by SGEMM over chunks of vertices.
//
// Sloan, Kautz & Snyder 2002 (PRT) with Green 2003's Monte Carlo projection, organised as in the
// paper: one direction set for every vertex and the basis table Y[S×K] computed once, so that
// projecting a chunk of vertices is the matrix product C[chunk×K] = W[chunk×S]·Y[S×K].
//
// Threads: TBB runs chunks in parallel in an arena of `threads` workers; each chunk is traced
// and then projected by one cblas_sgemm on the same thread, whose W is still in its cache.
// OpenBLAS is told to use one thread: it would otherwise run its own pthreads inside every call
// and fight the TBB workers for the same cores (oversubscription: T workers × T BLAS threads on T
// cores, each waking and spinning), and a chunk's product would depend on how OpenBLAS split it.
// With one BLAS thread per chunk, each chunk's coefficients depend only on that chunk's data:
// bit-identical results for any thread count.
#include "bake/bake_internal.hpp"
#include "shprt/core/error.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <cblas.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

namespace shprt::detail {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

// CPU time of the calling thread. The time split accumulates it per worker rather than wall
// intervals: on a machine shared with other work, a preempted worker's wall interval would charge
// the waiting to whichever phase it happened in.
double thread_cpu_seconds() {
    timespec ts{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// OpenBLAS thread count set to 1 for the bake, restored afterwards (see the file comment).
class SingleThreadedBlas {
public:
    SingleThreadedBlas() : m_saved(openblas_get_num_threads()) { openblas_set_num_threads(1); }
    ~SingleThreadedBlas() { openblas_set_num_threads(m_saved); }
    SingleThreadedBlas(const SingleThreadedBlas&) = delete;
    SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

private:
    int m_saved;
};

// One worker's buffers, reused for every chunk it runs.
struct Scratch {
    std::vector<float> w;                  // W[chunk×S], row-major
    std::vector<Vec3f> ray_dirs;           // directions above the horizon of the current vertex
    std::vector<std::uint32_t> ray_index;  // their indices in the direction set
    std::vector<std::uint8_t> occluded;    // the tracer's answers
    double trace_seconds = 0;              // CPU time in ray setup and tracing (this worker)
    double project_seconds = 0;            // CPU time in SGEMM (this worker)
};

std::size_t scratch_bytes(std::size_t chunk, std::size_t S) {
    return chunk * S * sizeof(float) +
           S * (sizeof(Vec3f) + sizeof(std::uint32_t) + sizeof(std::uint8_t));
}

}  // namespace

TransferSet bake_cpu(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions,
                     const Tracer* tracer, double seconds_bvh) {
    const auto start = Clock::now();
    const bool shadowed = options.transfer == TransferKind::shadowed;
    SHPRT_CHECK(!shadowed || tracer != nullptr, invalid_argument,
                "shadowed transfer needs a tracer");
    const std::size_t V = mesh.vertex_count();
    const std::size_t S = directions.size();
    const int K = options.K;
    const int threads =
        options.threads > 0 ? options.threads : std::max(1, tbb::info::default_concurrency());
    const std::size_t chunk =
        options.chunk_vertices > 0 ? options.chunk_vertices : auto_chunk_vertices(V, S);
    const std::size_t chunk_count = (V + chunk - 1) / chunk;

    // The direction set as structure-of-arrays, so the per-vertex cosine loop vectorises.
    // (And as Vec3f, the form the tracer takes.)
    std::vector<float> dx(S), dy(S), dz(S), weight(S);
    std::vector<Vec3f> dirs(S);
    for (std::size_t s = 0; s < S; ++s) {
        dirs[s] =
            Vec3f{directions.dirs[3 * s], directions.dirs[3 * s + 1], directions.dirs[3 * s + 2]};
        dx[s] = directions.dirs[3 * s];
        dy[s] = directions.dirs[3 * s + 1];
        dz[s] = directions.dirs[3 * s + 2];
        weight[s] = directions.weights[s];
    }
    // The basis table, once for all vertices: Y[s*K + i] = y_i(w_s).
    const std::vector<float> Y = basis_table(K, directions);

    TransferSet out = empty_transfer(options, S);
    out.coeffs.assign(V * std::size_t(K), 0.0f);

    // Progress: counters bumped per vertex; only the calling thread invokes the callback.
    std::atomic<std::uint64_t> rays_done{0}, vertices_done{0};
    std::atomic<bool> stop{false};
    const std::thread::id caller = std::this_thread::get_id();
    auto last_report = start;
    constexpr auto kReportInterval = std::chrono::milliseconds(50);  // ≤ 20 reports per second
    // Rays still to come are estimated from the rays per vertex so far (S/2 before the first).
    auto report = [&](bool final) {
        const std::uint64_t vdone = vertices_done.load(std::memory_order_relaxed);
        if (!shadowed) {
            return options.progress(
                ProgressInfo{"bake", vdone * S, std::uint64_t(V) * S, "samples"});
        }
        const std::uint64_t rdone = rays_done.load(std::memory_order_relaxed);
        const double per_vertex = vdone > 0 ? double(rdone) / double(vdone) : double(S) / 2;
        const std::uint64_t total =
            final ? rdone : rdone + std::uint64_t(per_vertex * double(V - vdone) + 0.5);
        return options.progress(ProgressInfo{"bake", rdone, std::max(total, rdone), "rays"});
    };

    std::mutex on_chunk_mutex;
    tbb::enumerable_thread_specific<Scratch> scratch;
    constexpr float kInf = std::numeric_limits<float>::infinity();

    auto run_chunk = [&](std::size_t c) {
        if (stop.load(std::memory_order_relaxed)) return;
        Scratch& sc = scratch.local();
        if (sc.w.empty()) {
            sc.w.resize(chunk * S);
            sc.ray_dirs.resize(S);
            sc.ray_index.resize(S);
            sc.occluded.resize(S);
        }
        const std::size_t first = c * chunk;
        const std::size_t count = std::min(chunk, V - first);
        const double trace_start = thread_cpu_seconds();
        std::uint64_t local_rays = 0;
        for (std::size_t j = 0; j < count; ++j) {
            const std::size_t v = first + j;
            const Vec3f n = mesh.normals[v];
            float* row = sc.w.data() + j * S;
            // W = max(0, n·w)·weight; below the horizon it is 0 and no ray is cast. (Written
            // with max, not a conditional, so that the loop compiles to SIMD without branches.)
            for (std::size_t s = 0; s < S; ++s) {
                const float cosine = n.x * dx[s] + n.y * dy[s] + n.z * dz[s];
                row[s] = std::max(cosine, 0.0f) * weight[s];
            }
            if (shadowed) {
                // Compaction of the above-horizon directions, branch-free: half of the random
                // directions are above the horizon, so a branch here mispredicts every other
                // sample (it cost more than 10% of the tracing time).
                std::uint32_t m = 0;
                for (std::size_t s = 0; s < S; ++s) {
                    sc.ray_index[m] = static_cast<std::uint32_t>(s);
                    sc.ray_dirs[m] = dirs[s];
                    m += row[s] != 0.0f ? 1u : 0u;
                }
                if (m > 0) {
                    const Vec3f origin = offset_ray_origin(mesh.positions[v], n);
                    tracer->occluded(origin, sc.ray_dirs.data(), static_cast<int>(m), 0.0f, kInf,
                                     sc.occluded.data());
                    constexpr float kKeep[2] = {1.0f, 0.0f};  // visible, occluded; branch-free
                    for (std::uint32_t r = 0; r < m; ++r)
                        row[sc.ray_index[r]] *= kKeep[sc.occluded[r] & 1u];
                }
                local_rays += m;
            }
            // Shared counters every 16 vertices: a cache line bounced between the workers per
            // vertex would cost more than the progress is worth.
            if ((j & 15u) == 15u || j + 1 == count) {
                rays_done.fetch_add(local_rays, std::memory_order_relaxed);
                vertices_done.fetch_add((j & 15u) + 1, std::memory_order_relaxed);
                local_rays = 0;
            }
            if (options.progress && std::this_thread::get_id() == caller) {
                const auto now = Clock::now();
                if (now - last_report >= kReportInterval) {
                    last_report = now;
                    if (!report(false)) stop.store(true, std::memory_order_relaxed);
                }
            }
            if (stop.load(std::memory_order_relaxed)) return;
        }
        const double project_start = thread_cpu_seconds();
        float* C = out.coeffs.data() + first * std::size_t(K);
        cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(count), K,
                    static_cast<int>(S), 1.0f, sc.w.data(), static_cast<int>(S), Y.data(), K, 0.0f,
                    C, K);
        const double project_end = thread_cpu_seconds();
        sc.trace_seconds += project_start - trace_start;
        sc.project_seconds += project_end - project_start;
        if (options.on_chunk) {
            const std::lock_guard<std::mutex> lock(on_chunk_mutex);
            options.on_chunk(first, count, C);
        }
    };

    const auto parallel_start = Clock::now();
    {
        const SingleThreadedBlas single_threaded_blas;
        tbb::task_arena arena(threads);
        arena.execute([&] {
            // One task per chunk (grain 1): the partition is fixed, the scheduler only decides
            // which worker runs which chunk.
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, chunk_count, 1),
                [&](const tbb::blocked_range<std::size_t>& r) {
                    for (std::size_t c = r.begin(); c != r.end(); ++c) run_chunk(c);
                },
                tbb::simple_partitioner());
        });
    }
    const double parallel_seconds = seconds_between(parallel_start, Clock::now());
    if (!stop.load() && options.progress && !report(true)) stop.store(true);
    SHPRT_CHECK(!stop.load(), cancelled, "bake cancelled after {} of {} vertices",
                vertices_done.load(), V);

    // Split the parallel phase's wall time between tracing and projection in proportion to the
    // CPU time the workers spent in each (their sum is what the workers did; the wall time is
    // what the caller waited).
    double trace_acc = 0, project_acc = 0;
    for (const Scratch& sc : scratch) {
        trace_acc += sc.trace_seconds;
        project_acc += sc.project_seconds;
    }
    const double busy = trace_acc + project_acc;
    BakeStats& st = out.stats;
    st.seconds_bvh = seconds_bvh;
    st.seconds_trace = busy > 0 ? parallel_seconds * trace_acc / busy : 0;
    st.seconds_project = busy > 0 ? parallel_seconds * project_acc / busy : 0;
    st.seconds_total = seconds_bvh + seconds_between(start, Clock::now());
    st.rays_cast = rays_done.load();
    const std::size_t workers = std::min<std::size_t>(std::size_t(threads), chunk_count);
    st.peak_bytes_host = out.coeffs.size() * sizeof(float) + Y.size() * sizeof(float) +
                         7 * S * sizeof(float) + workers * scratch_bytes(chunk, S) +
                         (tracer ? tracer->memory_bytes() : 0);
    st.device_name = fmt::format("cpu: {} thread{}", threads, threads == 1 ? "" : "s");
    return out;
}

}  // namespace shprt::detail
