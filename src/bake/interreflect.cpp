// Interreflected transfer (interreflect.hpp, docs/interreflection.md): the bounces of diffuse
// PRT as products with a sparse transport operator.
//
// Sloan, Kautz & Snyder 2002, section 5 ("interreflected transfer"): per bounce, gather the
// previous bounce's transfer at the hits of each vertex's rays, weighted by the cosine and the
// albedo. They re-trace per bounce; here the closest hits of the shared direction set are traced
// once and turned into the sparse V×V operator A (one row per vertex, Eigen's compressed rows), so
// that each bounce is one sparse × dense product over the K·3 columns of the transfer.
#include "shprt/bake/interreflect.hpp"

#include "bake/bake_internal.hpp"
#include "bake/progress.hpp"
#include "bake/stages.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <Eigen/SparseCore>

#include <immintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

namespace shprt {
namespace {

int thread_count(int threads) {
    return threads > 0 ? threads : std::max(1, tbb::info::default_concurrency());
}

// The merged rows of one chunk of vertices, concatenated; row_nnz per vertex.
struct ChunkRows {
    std::vector<std::int32_t> column;
    std::vector<float> r, g, b;
    std::vector<std::uint32_t> row_nnz;
};

// One worker's buffers.
struct RowScratch {
    std::vector<float> weight;
    std::vector<Vec3f> ray_dirs;
    std::vector<std::uint32_t> ray_index;
    std::vector<Hit> hits;
    // The row being merged: per column (vertex) three sums, and the columns touched. Dense over
    // the vertices (24 bytes each per worker), so merging costs one add per entry and a sort of
    // the distinct columns only.
    std::vector<double> sums;
    std::vector<std::uint8_t> seen;
    std::vector<std::uint32_t> touched;
};

// Rows per chunk of the operator build: fixed (never from the thread count), so the chunks and
// with them the rows' bits do not depend on the threads.
constexpr std::size_t kRowsPerChunk = 64;

using SparseMap = Eigen::Map<const Eigen::SparseMatrix<float, Eigen::RowMajor, std::int32_t>>;
using DenseMap =
    Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>, 0,
               Eigen::OuterStride<>>;
using DenseOut = Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>,
                            0, Eigen::OuterStride<>>;

// The three channels' products for rows [first, first + rows) with AVX2, one pass over the
// rows' non-zeros (the shared pattern) instead of three: y(v) = Σ_nz a_c · x(col) per channel,
// accumulated in the order of the row's non-zeros from zero, one rounded multiply and one rounded
// add per element — exactly the operations of Eigen's row-major sparse × dense product (res.row
// += value · rhs.row, from zero), so the bits are Eigen's (checked by the benchmark and a test).
// No FMA: a fused multiply-add rounds once and would change them. Intrinsics only: a target
// attribute does not reach inline functions from headers, which must not be compiled for AVX2
// here (the linker could keep those copies for the portable path).
__attribute__((target("avx2"))) void transport_rows_avx2(const TransportOperator& A,
                                                         const float* in, float* out, int K,
                                                         std::size_t first, std::size_t rows,
                                                         float* acc) {
    const std::size_t stride = 3 * std::size_t(K);
    const int vec_end = K / 8 * 8;
    const float* v0 = A.values[0].data();
    const float* v1 = A.values[1].data();
    const float* v2 = A.values[2].data();
    for (std::size_t r = first; r < first + rows; ++r) {
        for (std::size_t i = 0; i < stride; ++i) acc[i] = 0.0f;
        for (std::int32_t p = A.row_start[r]; p < A.row_start[r + 1]; ++p) {
            const float* x = in + std::size_t(A.column[std::size_t(p)]) * stride;
            const float a[3] = {v0[p], v1[p], v2[p]};
            for (int c = 0; c < 3; ++c) {
                const float* xc = x + std::size_t(c) * K;
                float* yc = acc + std::size_t(c) * K;
                const __m256 av = _mm256_set1_ps(a[c]);
                int k = 0;
                for (; k < vec_end; k += 8)
                    _mm256_storeu_ps(yc + k,
                                     _mm256_add_ps(_mm256_loadu_ps(yc + k),
                                                   _mm256_mul_ps(av, _mm256_loadu_ps(xc + k))));
                for (; k < K; ++k) yc[k] = yc[k] + a[c] * xc[k];
            }
        }
        float* y = out + r * stride;
        for (std::size_t i = 0; i < stride; ++i) y[i] = acc[i];
    }
}

bool cpu_has_avx2() {
    static const bool has = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return has;
}

}  // namespace

TransportOperator build_transport_operator(const Mesh& mesh, const DirectionSet& directions,
                                           const Tracer& tracer, const TransportOptions& options) {
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(mesh.albedo.size() == V && mesh.normals.size() == V, invalid_argument,
                "interreflected transfer needs a normal and an albedo per vertex ({} vertices, {} "
                "normals, {} albedo values)",
                V, mesh.normals.size(), mesh.albedo.size());
    SHPRT_CHECK(V <= std::size_t(std::numeric_limits<std::int32_t>::max()), invalid_argument,
                "interreflected transfer supports at most 2^31 - 1 vertices ({} given)", V);
    const detail::DirectionTable table = detail::make_direction_table(directions);
    const std::size_t S = table.size();
    const std::size_t chunk_count = (V + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<ChunkRows> chunks(chunk_count);
    tbb::enumerable_thread_specific<RowScratch> scratch;
    detail::BakeProgress progress(options.progress, true, V, S);
    const float inv_pi = float(1.0 / std::numbers::pi);
    constexpr float kInf = std::numeric_limits<float>::infinity();

    auto build_row = [&](std::size_t v, RowScratch& sc, ChunkRows& out) -> std::uint64_t {
        sc.weight.resize(S);
        sc.ray_dirs.resize(S);
        sc.ray_index.resize(S);
        sc.hits.resize(S);
        const Vec3f n = mesh.normals[v];
        detail::weight_row(n, table, sc.weight.data());
        std::uint32_t m = 0;
        for (std::size_t s = 0; s < S; ++s) {
            sc.ray_index[m] = static_cast<std::uint32_t>(s);
            sc.ray_dirs[m] = table.dirs[s];
            m += sc.weight[s] != 0.0f ? 1u : 0u;
        }
        if (sc.seen.size() != V) {
            sc.sums.assign(3 * V, 0.0);
            sc.seen.assign(V, 0);
        }
        sc.touched.clear();
        if (m > 0)
            tracer.closest_hits(offset_ray_origin(mesh.positions[v], n), sc.ray_dirs.data(),
                                static_cast<int>(m), 0.0f, kInf, sc.hits.data());
        for (std::uint32_t r = 0; r < m; ++r) {
            const Hit& h = sc.hits[r];
            if (!h.hit) continue;
            const auto& tri = mesh.triangles[h.triangle];
            const Vec3f p0 = mesh.positions[tri[0]];
            const Vec3f face = cross(mesh.positions[tri[1]] - p0, mesh.positions[tri[2]] - p0);
            // The ray meets the front (counter-clockwise) side when it runs against the face's
            // normal; a back face is a one-sided surface's inside and sends nothing.
            if (!options.two_sided && dot(face, sc.ray_dirs[r]) >= 0.0f) continue;
            const float bary[3] = {1.0f - h.u - h.v, h.u, h.v};
            Vec3f rho{0, 0, 0};
            for (int k = 0; k < 3; ++k) rho += mesh.albedo[tri[k]] * bary[k];
            const float a = sc.weight[sc.ray_index[r]] * inv_pi;
            // Entries of the same column merge, summed in ray order: deterministic.
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t col = tri[k];
                const float ab = a * bary[k];
                if (!sc.seen[col]) {
                    sc.seen[col] = 1;
                    sc.touched.push_back(col);
                }
                double* sum = sc.sums.data() + 3 * std::size_t(col);
                sum[0] += ab * rho.x;
                sum[1] += ab * rho.y;
                sum[2] += ab * rho.z;
            }
        }
        std::sort(sc.touched.begin(), sc.touched.end());
        std::uint32_t count = 0;
        for (const std::uint32_t col : sc.touched) {
            double* sum = sc.sums.data() + 3 * std::size_t(col);
            const double r = sum[0], g = sum[1], b = sum[2];
            sum[0] = sum[1] = sum[2] = 0.0;
            sc.seen[col] = 0;
            if (r == 0 && g == 0 && b == 0) continue;  // a black or grazing hit
            out.column.push_back(static_cast<std::int32_t>(col));
            out.r.push_back(static_cast<float>(r));
            out.g.push_back(static_cast<float>(g));
            out.b.push_back(static_cast<float>(b));
            ++count;
        }
        out.row_nnz.push_back(count);
        return m;
    };

    tbb::task_arena arena(thread_count(options.threads));
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, chunk_count, 1),
            [&](const tbb::blocked_range<std::size_t>& range) {
                for (std::size_t c = range.begin(); c != range.end(); ++c) {
                    if (progress.stopped()) return;
                    RowScratch& sc = scratch.local();
                    const std::size_t first = c * kRowsPerChunk;
                    const std::size_t last = std::min(V, first + kRowsPerChunk);
                    std::uint64_t rays = 0;
                    for (std::size_t v = first; v < last; ++v) rays += build_row(v, sc, chunks[c]);
                    progress.add(last - first, rays);
                    if (!progress.poll()) return;
                }
            },
            tbb::simple_partitioner());
    });
    SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled while tracing the bounce rays");

    TransportOperator A;
    A.vertices = V;
    A.rays_cast = progress.rays();
    std::uint64_t nnz = 0;
    for (const ChunkRows& c : chunks) nnz += c.column.size();
    SHPRT_CHECK(nnz <= std::uint64_t(std::numeric_limits<std::int32_t>::max()), out_of_memory,
                "the transport operator has {} non-zeros, more than 2^31 - 1 (chunking it is not "
                "implemented; use fewer samples)",
                nnz);
    A.row_start.resize(V + 1);
    A.column.reserve(nnz);
    for (auto& values : A.values) values.reserve(nnz);
    std::size_t row = 0;
    A.row_start[0] = 0;
    for (ChunkRows& c : chunks) {
        A.column.insert(A.column.end(), c.column.begin(), c.column.end());
        A.values[0].insert(A.values[0].end(), c.r.begin(), c.r.end());
        A.values[1].insert(A.values[1].end(), c.g.begin(), c.g.end());
        A.values[2].insert(A.values[2].end(), c.b.begin(), c.b.end());
        for (std::uint32_t k : c.row_nnz) {
            A.row_start[row + 1] = A.row_start[row] + static_cast<std::int32_t>(k);
            ++row;
        }
        c = ChunkRows{};  // release as we go
    }
    return A;
}

void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads) {
    apply_transport(A, in, out, K, threads, TransportKernel::automatic);
}

void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads,
                     TransportKernel kernel) {
    const auto V = static_cast<Eigen::Index>(A.vertices);
    const Eigen::Index stride = 3 * Eigen::Index(K);
    const bool avx2 =
        kernel == TransportKernel::avx2 || (kernel == TransportKernel::automatic && cpu_has_avx2());
    SHPRT_CHECK(!avx2 || cpu_has_avx2(), unsupported, "this CPU has no AVX2");
    // Rows in fixed blocks (the bits never depend on them: each output row is its own sum over
    // its row's entries in column order), large enough that a block's product runs at the speed
    // of Eigen's whole-matrix product; Eigen on one thread runs that whole-matrix product itself.
    constexpr Eigen::Index kBlockRows = 2048;
    const Eigen::Index blocks = (V + kBlockRows - 1) / kBlockRows;
    const auto eigen_rows = [&](Eigen::Index first, Eigen::Index rows) {
        for (int c = 0; c < 3; ++c) {
            const SparseMap a(V, V, Eigen::Index(A.nnz()), A.row_start.data(), A.column.data(),
                              A.values[c].data());
            const DenseMap x(in + c * K, V, K, Eigen::OuterStride<>(stride));
            DenseOut y(out + first * stride + c * K, rows, K, Eigen::OuterStride<>(stride));
            if (first == 0 && rows == V)
                y.noalias() = a * x;
            else
                y.noalias() = a.middleRows(first, rows) * x;
        }
    };
    tbb::enumerable_thread_specific<std::vector<float>> accumulators;
    const auto run_block = [&](Eigen::Index first, Eigen::Index rows) {
        if (!avx2) return eigen_rows(first, rows);
        std::vector<float>& acc = accumulators.local();
        acc.resize(std::size_t(stride));
        transport_rows_avx2(A, in, out, K, std::size_t(first), std::size_t(rows), acc.data());
    };
    if (thread_count(threads) == 1 || blocks == 1) return run_block(0, V);
    tbb::task_arena arena(thread_count(threads));
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<Eigen::Index>(0, blocks, 1),
            [&](const tbb::blocked_range<Eigen::Index>& range) {
                for (Eigen::Index b = range.begin(); b != range.end(); ++b) {
                    const Eigen::Index first = b * kBlockRows;
                    run_block(first, std::min(kBlockRows, V - first));
                }
            },
            tbb::simple_partitioner());
    });
}

namespace detail {

TransferInfo bake_interreflected(const BakeJob& job, const BakeOptions& options,
                                 const DirectionSet& directions, const Tracer* tracer,
                                 double seconds_bvh) {
    const auto start = Clock::now();
    const Mesh& mesh = *job.occluders;
    const Receivers& rx = job.receivers;
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(rx.domain == ReceiverDomain::vertex && rx.first == 0 && rx.count == V &&
                    rx.total == V && rx.positions == mesh.positions.data() &&
                    rx.normals == mesh.normals.data(),
                unsupported,
                "interreflected transfer bakes every vertex of the scene at once (its bounces "
                "couple them all): no shards, receiver ranges or MPI");
    SHPRT_CHECK(job.sink->device_rows() == nullptr, unsupported,
                "the CPU bake cannot write into a device buffer (a DeviceSink needs device "
                "'cuda')");
    // bounces, tolerance and max_bounces were checked by validate() at bake()'s boundary.
    SHPRT_CHECK(mesh.albedo.size() == V, invalid_argument,
                "interreflected transfer needs an albedo per vertex ({} for {} vertices)",
                mesh.albedo.size(), V);
    const int K = options.K;

    // T_0: exactly the shadowed bake (same stages, same bits), into host memory.
    BakeOptions direct_options = options;
    direct_options.transfer = TransferKind::shadowed;
    HostSink direct_sink;
    BakeJob direct_job = job;
    direct_job.sink = &direct_sink;
    const TransferInfo direct_info =
        bake_cpu(direct_job, direct_options, directions, tracer, seconds_bvh);
    std::vector<float> T0 = direct_sink.take_rows();

    TransferInfo info = direct_info;
    info.kind = TransferKind::interreflected;
    info.layout.channels = 3;
    InterreflectionInfo& ir = info.interreflection;
    ir.two_sided = options.two_sided;
    ir.converge = options.converge;
    ir.tolerance = options.converge ? options.tolerance : 0.0;
    ir.albedo_source = mesh.albedo_source;

    const int wanted = options.converge ? options.max_bounces : options.bounces;
    const std::size_t row = 3 * std::size_t(K);
    std::vector<float> sum(V * row);
    for (std::size_t v = 0; v < V; ++v)
        for (int c = 0; c < 3; ++c)
            std::copy_n(T0.data() + v * K, K, sum.data() + v * row + std::size_t(c) * K);

    TransportOperator A;
    std::uint64_t buffers_bytes = sum.size() * sizeof(float);
    if (wanted > 0) {
        const auto operator_start = Clock::now();
        TransportOptions to;
        to.two_sided = options.two_sided;
        to.threads = options.threads;
        to.progress = options.progress;
        A = build_transport_operator(mesh, directions, *tracer, to);
        info.stats.seconds_operator = seconds_since(operator_start);
        ir.operator_nnz = A.nnz();
        ir.operator_bytes = A.bytes();

        const auto bounce_start = Clock::now();
        std::vector<float> previous = sum, current(sum.size());
        buffers_bytes += 2 * sum.size() * sizeof(float);
        for (int b = 1; b <= wanted; ++b) {
            apply_transport(A, previous.data(), current.data(), K, options.threads);
            // The largest relative change of any receiver's transfer by this bounce:
            // |T_b(v)| / |T_0(v) + … + T_b(v)| (Euclidean over its 3K floats).
            double change = 0;
            for (std::size_t v = 0; v < V; ++v) {
                double t2 = 0, s2 = 0;
                float* s = sum.data() + v * row;
                const float* t = current.data() + v * row;
                for (std::size_t i = 0; i < row; ++i) {
                    s[i] += t[i];
                    t2 += double(t[i]) * t[i];
                    s2 += double(s[i]) * s[i];
                }
                if (s2 > 0) change = std::max(change, std::sqrt(t2 / s2));
            }
            ir.bounces = b;
            ir.last_change = change;
            std::swap(previous, current);
            if (options.progress && !options.progress(ProgressInfo{
                                        "bounces", std::uint64_t(b),
                                        options.converge ? 0 : std::uint64_t(wanted), "bounces"}))
                fail(ErrorCode::cancelled, "bake cancelled after {} bounces", b);
            if (options.converge && change < options.tolerance) break;
        }
        info.stats.seconds_bounces = seconds_since(bounce_start);
    }
    ir.converged = options.converge && ir.bounces > 0 && ir.last_change < options.tolerance;

    TransferSink& sink = *job.sink;
    sink.begin(info.layout, 0, V);
    if (float* rows = sink.host_rows(0, V)) {
        std::copy(sum.begin(), sum.end(), rows);
        sink.write(0, V, rows);
    } else {
        sink.write(0, V, sum.data());
    }
    sink.finish();
    if (job.direct) *job.direct = std::move(T0);

    BakeStats& st = info.stats;
    ir.operator_rays = A.rays_cast;
    st.seconds_total = seconds_bvh + seconds_since(start);
    st.peak_bytes_host = std::max<std::uint64_t>(
        st.peak_bytes_host, V * std::size_t(K) * sizeof(float) + A.bytes() + buffers_bytes +
                                (tracer ? tracer->memory_bytes() : 0));
    return info;
}

}  // namespace detail
}  // namespace shprt
