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
#include "shprt/core/file.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <Eigen/SparseCore>

#include <fcntl.h>
#include <immintrin.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace shprt {
namespace detail {

// Merges rows of A; one per worker (it keeps a dense accumulator over the vertices: 25 bytes
// each).
class TransportRowBuilder {
public:
    TransportRowBuilder(const Mesh& mesh, bool two_sided) : m_mesh(&mesh), m_two_sided(two_sided) {}

    // Appends one row to `out` (its entries, then its end in out.row_start) from its rays in
    // direction order: ray r has direction dirs[r], unoccluded weight weights[r] = max(0, n·w_s)·
    // weight_s and closest hit hits[r] (kNoTriangle: it escaped). Each hit on a front face (or
    // any face when two-sided) adds weights[r]/π · ρ_c(h) · β_k(h) to the columns of its
    // triangle's vertices k; entries of one column are summed in ray order, in double.
    void add_row(const Vec3f* dirs, const float* weights, const SampleHit* hits, std::uint32_t rays,
                 TransportOperator::Block& out);

    static std::size_t bytes(std::size_t vertices) { return 25 * vertices; }

private:
    const Mesh* m_mesh;
    bool m_two_sided;
    std::vector<double> m_sums;  // 3 per column
    std::vector<std::uint8_t> m_seen;
    std::vector<std::uint32_t> m_touched;
};

// The blocks of A that do not fit the memory budget: appended to one temporary file as they
// finish (any thread; each block's bytes at an offset reserved under a lock, written with pwrite
// outside it), then mapped read-only. The file is an AtomicFile's temporary, never committed: it
// is removed when this object goes (an error, a cancel) and by the CLI's signal handlers, and
// unlinked as soon as it is mapped, so that only the mapping keeps its pages.
class SpillFile {
public:
    explicit SpillFile(std::string directory) : m_directory(std::move(directory)) {
        if (m_directory.empty()) {
            const char* tmp = std::getenv("TMPDIR");
            m_directory = tmp && *tmp ? tmp : "/tmp";
        }
    }

    // Where a spilled block's arrays are in the file.
    struct Record {
        std::uint64_t offset = 0;  // row starts, then columns, then the three channels' values
        std::size_t rows = 0, nnz = 0;
    };

    // Writes the block's arrays and frees its vectors.
    Record append(TransportOperator::Block& b) {
        Record r;
        r.rows = b.rows();
        r.nnz = b.nnz();
        const std::uint64_t length = b.bytes();
        int fd = -1;
        {
            const std::lock_guard lock(m_mutex);
            if (!m_file) m_file.emplace(m_directory + "/shprt-transport-operator");
            fd = ::fileno(m_file->handle());
            r.offset = m_size;
            m_size += length;
        }
        const std::string what = "the transport operator's spill file in " + m_directory;
        std::uint64_t at = r.offset;
        const auto put = [&](const void* data, std::size_t bytes) {
            if (bytes) pwrite_all(fd, data, bytes, at, what);
            at += bytes;
        };
        put(b.row_start.data(), b.row_start.size() * sizeof(std::int32_t));
        put(b.column.data(), b.column.size() * sizeof(std::int32_t));
        for (const auto& v : b.values) put(v.data(), v.size() * sizeof(float));
        m_spilled.fetch_add(length);
        // Freed, not cleared: `v = {}` would keep the capacity (initializer-list assignment).
        std::vector<std::int32_t>().swap(b.row_start);
        std::vector<std::int32_t>().swap(b.column);
        for (auto& v : b.values) std::vector<float>().swap(v);
        return r;
    }

    std::uint64_t spilled() const { return m_spilled.load(); }

    // After the last append: maps the file read-only, unlinks it, and points the spilled blocks
    // (records[i].rows > 0) into the mapping, which the returned owner keeps.
    std::shared_ptr<const void> map(TransportOperator& A, const std::vector<Record>& records) {
        if (!m_file) return nullptr;
        const std::string& temp = m_file->temp_path();
        const int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
        SHPRT_CHECK(fd >= 0, io, "cannot read back {}: {}", temp, std::strerror(errno));
        void* base = ::mmap(nullptr, m_size, PROT_READ, MAP_SHARED, fd, 0);
        const int err = errno;
        ::close(fd);
        SHPRT_CHECK(base != MAP_FAILED, io, "cannot map {}: {}", temp, std::strerror(err));
        m_file.reset();  // unlinks the file; the mapping keeps its pages
        const std::size_t length = m_size;
        std::shared_ptr<const void> owner(
            base, [length](const void* p) { ::munmap(const_cast<void*>(p), length); });
        const auto* bytes = static_cast<const unsigned char*>(base);
        for (std::size_t i = 0; i < records.size(); ++i) {
            const Record& r = records[i];
            if (r.rows == 0) continue;
            TransportOperator::Block::Mapped& m = A.blocks[i].mapped;
            const unsigned char* p = bytes + r.offset;
            m.rows = r.rows;
            m.nnz = r.nnz;
            m.row_start = reinterpret_cast<const std::int32_t*>(p);
            m.column = m.row_start + (r.rows + 1);
            const auto* values = reinterpret_cast<const float*>(m.column + r.nnz);
            for (std::size_t c = 0; c < 3; ++c) m.values[c] = values + c * r.nnz;
        }
        return owner;
    }

private:
    std::string m_directory;
    std::mutex m_mutex;
    std::optional<AtomicFile> m_file;
    std::uint64_t m_size = 0;
    std::atomic<std::uint64_t> m_spilled{0};
};

struct TransportBlockStore::Impl {
    std::uint64_t budget;
    SpillFile spill;
    std::atomic<std::uint64_t> resident{0};
    std::mutex mutex;  // guards records
    std::vector<SpillFile::Record> records;

    Impl(std::uint64_t b, std::string directory) : budget(b), spill(std::move(directory)) {}
};

TransportBlockStore::TransportBlockStore(std::uint64_t budget, std::string spill_directory)
    : m_impl(std::make_unique<Impl>(budget, std::move(spill_directory))) {}

TransportBlockStore::~TransportBlockStore() = default;

void TransportBlockStore::keep(std::size_t index, TransportOperator::Block& block) {
    Impl& m = *m_impl;
    const std::uint64_t bytes = block.bytes();
    // Its vectors may have grown by doubling: trimmed to their size, so that the memory A holds
    // is A.bytes() (the slack was ~10 % of A, seen in the process's RSS).
    if (m.budget == 0 || m.resident.fetch_add(bytes) + bytes <= m.budget) {
        block.row_start.shrink_to_fit();
        block.column.shrink_to_fit();
        for (auto& v : block.values) v.shrink_to_fit();
        return;
    }
    m.resident.fetch_sub(bytes);
    const SpillFile::Record record = m.spill.append(block);
    const std::lock_guard lock(m.mutex);
    if (m.records.size() <= index) m.records.resize(index + 1);
    m.records[index] = record;
}

void TransportBlockStore::finish(TransportOperator& A) {
    Impl& m = *m_impl;
    m.records.resize(A.blocks.size());
    A.spill = m.spill.map(A, m.records);
    A.spilled_bytes = m.spill.spilled();
}

std::uint64_t transport_memory_budget(const Mesh& mesh, const BakeOptions& options) {
    if (options.memory_budget == 0) return 0;
    const std::uint64_t rest =
        estimate_bake_peak_bytes(mesh.triangle_count(), mesh.vertex_count(), options, true);
    return options.memory_budget > rest ? options.memory_budget - rest : 1;
}

}  // namespace detail

namespace {

// One worker's buffers.
struct RowScratch {
    std::vector<float> weight;  // T_0's weight row when none is given (A alone)
    std::vector<Vec3f> ray_dirs;
    std::vector<std::uint32_t> ray_index;
    std::vector<Hit> hits;
    std::vector<SampleHit> sample_hits;  // the hits as TransportRowBuilder takes them
    std::vector<float> ray_weights;      // the rays' unoccluded weights
    std::optional<detail::TransportRowBuilder> rows;
    std::vector<float> w;  // W[block×S] for T_0's projection (fused pass)
    double trace_seconds = 0, merge_seconds = 0, project_seconds = 0;  // this worker's CPU time
};

using SparseMap = Eigen::Map<const Eigen::SparseMatrix<float, Eigen::RowMajor, std::int32_t>>;
using DenseMap =
    Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>, 0,
               Eigen::OuterStride<>>;
using DenseOut = Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>,
                            0, Eigen::OuterStride<>>;

// The three channels' products for the rows of one block with AVX2, one pass over the rows'
// non-zeros (the shared pattern) instead of three: y(v) = Σ_nz a_c · x(col) per channel,
// accumulated in the order of the row's non-zeros from zero, one rounded multiply and one rounded
// add per element — exactly the operations of Eigen's row-major sparse × dense product (res.row
// += value · rhs.row, from zero), so the bits are Eigen's (checked by the benchmark and a test).
// No FMA: a fused multiply-add rounds once and would change them. Intrinsics only: a target
// attribute does not reach inline functions from headers, which must not be compiled for AVX2
// here (the linker could keep those copies for the portable path).
__attribute__((target("avx2"))) void transport_rows_avx2(const TransportOperator::Block& A,
                                                         const float* in, float* out, int K,
                                                         float* acc) {
    const std::size_t stride = 3 * std::size_t(K);
    const int vec_end = K / 8 * 8;
    const float* v0 = A.channel(0);
    const float* v1 = A.channel(1);
    const float* v2 = A.channel(2);
    const std::int32_t* starts = A.starts();
    const std::int32_t* columns = A.columns();
    for (std::size_t r = 0; r < A.rows(); ++r) {
        for (std::size_t i = 0; i < stride; ++i) acc[i] = 0.0f;
        for (std::int32_t p = starts[r]; p < starts[r + 1]; ++p) {
            const float* x = in + std::size_t(columns[std::size_t(p)]) * stride;
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
        float* y = out + (A.first + r) * stride;
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

// T_0's rows from the same rays as A's (the fused pass of bake_interreflected): the visibility of
// a direction is "no closest hit", the very answer of the shadowed bake's occlusion rays, and the
// rows are projected as bake_cpu projects them (the same weights, chunks and SGEMM), so T_0's
// bits are the shadowed bake's (tested).
struct DirectRows {
    const float* Y = nullptr;  // the basis table, S×K
    int K = 0;
    float* rows = nullptr;  // V×K
};

// The rows of A (and, given `direct`, of T_0) for every vertex, in blocks of `rows_per_block`.
// `then`: the bounces that follow (ProgressInfo::then), empty for A alone.
TransportOperator trace_transport(const Mesh& mesh, const detail::DirectionTable& table,
                                  const Tracer& tracer, const TransportOptions& options,
                                  const DirectRows* direct, RowScratch* totals,
                                  std::string_view then = {}) {
    const std::size_t V = mesh.vertex_count();
    SHPRT_CHECK(mesh.albedo.size() == V && mesh.normals.size() == V, invalid_argument,
                "interreflected transfer needs a normal and an albedo per vertex ({} vertices, {} "
                "normals, {} albedo values)",
                V, mesh.normals.size(), mesh.albedo.size());
    SHPRT_CHECK(V <= std::size_t(std::numeric_limits<std::int32_t>::max()), invalid_argument,
                "interreflected transfer supports at most 2^31 - 1 vertices ({} given)", V);
    const std::size_t S = table.size();
    const std::size_t block_rows =
        options.rows_per_block > 0 ? options.rows_per_block : auto_chunk_receivers(V, S);
    const std::size_t block_count = (V + block_rows - 1) / block_rows;
    TransportOperator A;
    A.vertices = V;
    A.blocks.resize(block_count);
    tbb::enumerable_thread_specific<RowScratch> scratch;
    detail::BakeProgress progress(options.progress, true, V, S);
    progress.set_then(then);
    // A finished block stays in memory while the finished blocks fit the budget, else it goes
    // to the spill file.
    detail::TransportBlockStore store(options.memory_budget, options.spill_directory);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr float kKeep[2] = {1.0f, 0.0f};  // visible, occluded: as trace_row, branch-free

    // One row: its rays' closest hits, T_0's weights (`weight`: zeroed where a ray hits anything,
    // front or back — an occluder either way) and A's merged entries.
    auto build_row = [&](std::size_t v, RowScratch& sc, float* weight,
                         TransportOperator::Block& out) -> std::uint64_t {
        const double trace_start = thread_cpu_seconds();
        sc.ray_dirs.resize(S);
        sc.ray_index.resize(S);
        sc.hits.resize(S);
        sc.sample_hits.resize(S);
        sc.ray_weights.resize(S);
        if (!sc.rows) sc.rows.emplace(mesh, options.two_sided);
        const Vec3f n = mesh.normals[v];
        detail::weight_row(n, table, weight);
        std::uint32_t m = 0;
        for (std::size_t s = 0; s < S; ++s) {
            sc.ray_index[m] = static_cast<std::uint32_t>(s);
            sc.ray_dirs[m] = table.dirs[s];
            m += weight[s] != 0.0f ? 1u : 0u;
        }
        if (m > 0)
            tracer.closest_hits(offset_ray_origin(mesh.positions[v], n), sc.ray_dirs.data(),
                                static_cast<int>(m), 0.0f, kInf, sc.hits.data());
        const double merge_start = thread_cpu_seconds();
        for (std::uint32_t r = 0; r < m; ++r) {
            const Hit& h = sc.hits[r];
            sc.sample_hits[r] = SampleHit{h.hit ? h.triangle : kNoTriangle, h.u, h.v};
            sc.ray_weights[r] = weight[sc.ray_index[r]];
            weight[sc.ray_index[r]] *= kKeep[h.hit ? 1 : 0];
        }
        sc.rows->add_row(sc.ray_dirs.data(), sc.ray_weights.data(), sc.sample_hits.data(), m, out);
        const double end = thread_cpu_seconds();
        sc.trace_seconds += merge_start - trace_start;
        sc.merge_seconds += end - merge_start;
        return m;
    };

    auto build_block = [&](std::size_t c) {
        if (progress.stopped()) return;
        RowScratch& sc = scratch.local();
        TransportOperator::Block& out = A.blocks[c];
        out.first = c * block_rows;
        const std::size_t count = std::min(block_rows, V - out.first);
        out.row_start.reserve(count + 1);
        out.row_start.push_back(0);
        float* W = nullptr;
        if (direct) {
            sc.w.resize(block_rows * S);
            W = sc.w.data();
        } else {
            sc.weight.resize(S);
        }
        std::uint64_t rays = 0;
        for (std::size_t j = 0; j < count; ++j) {
            rays += build_row(out.first + j, sc, W ? W + j * S : sc.weight.data(), out);
            if ((j & 15u) == 15u || j + 1 == count) {
                progress.add((j & 15u) + 1, rays);
                rays = 0;
            }
            if (!progress.poll()) return;
        }
        if (direct) {
            const double project_start = thread_cpu_seconds();
            detail::project_rows(W, count, S, direct->Y, direct->K,
                                 direct->rows + out.first * std::size_t(direct->K));
            sc.project_seconds += thread_cpu_seconds() - project_start;
        }
        store.keep(c, out);
    };

    {
        const detail::SingleThreadedBlas single_threaded_blas;
        parallel_each(options.threads, block_count, build_block);
    }
    SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled after {} of {} vertices",
                progress.receivers_done(), V);
    A.rays_cast = progress.rays();
    store.finish(A);
    if (totals)
        for (const RowScratch& sc : scratch) {
            totals->trace_seconds += sc.trace_seconds;
            totals->merge_seconds += sc.merge_seconds;
            totals->project_seconds += sc.project_seconds;
            totals->w.resize(totals->w.size() + sc.w.size());  // counts the W buffers' floats
        }
    return A;
}

}  // namespace

namespace detail {

void TransportRowBuilder::add_row(const Vec3f* dirs, const float* weights, const SampleHit* hits,
                                  std::uint32_t rays, TransportOperator::Block& out) {
    const Mesh& mesh = *m_mesh;
    const std::size_t V = mesh.vertex_count();
    if (m_seen.size() != V) {
        m_sums.assign(3 * V, 0.0);
        m_seen.assign(V, 0);
    }
    m_touched.clear();
    const TransportMeshView view = transport_mesh_view(mesh);
    TransportHitEntries entries;
    for (std::uint32_t r = 0; r < rays; ++r) {
        if (!transport_hit_entries(view, dirs[r], weights[r], hits[r], m_two_sided, entries))
            continue;
        // Entries of the same column merge, summed in ray order: deterministic.
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t col = entries.column[k];
            if (!m_seen[col]) {
                m_seen[col] = 1;
                m_touched.push_back(col);
            }
            double* sum = m_sums.data() + 3 * std::size_t(col);
            sum[0] += entries.value[k][0];
            sum[1] += entries.value[k][1];
            sum[2] += entries.value[k][2];
        }
    }
    std::sort(m_touched.begin(), m_touched.end());
    for (const std::uint32_t col : m_touched) {
        double* sum = m_sums.data() + 3 * std::size_t(col);
        const double r = sum[0], g = sum[1], b = sum[2];
        sum[0] = sum[1] = sum[2] = 0.0;
        m_seen[col] = 0;
        if (r == 0 && g == 0 && b == 0) continue;  // a black or grazing hit
        out.column.push_back(static_cast<std::int32_t>(col));
        out.values[0].push_back(static_cast<float>(r));
        out.values[1].push_back(static_cast<float>(g));
        out.values[2].push_back(static_cast<float>(b));
    }
    SHPRT_CHECK(out.column.size() <= std::size_t(std::numeric_limits<std::int32_t>::max()),
                out_of_memory,
                "a block of the transport operator has more than 2^31 - 1 non-zeros (use fewer "
                "samples)");
    out.row_start.push_back(static_cast<std::int32_t>(out.column.size()));
}

}  // namespace detail

namespace {

// The products of apply_transport, with an optional progress reporter counting rows.
void apply_transport_blocks(const TransportOperator& A, const float* in, float* out, int K,
                            int threads, TransportKernel kernel, detail::BakeProgress* progress) {
    const auto V = static_cast<Eigen::Index>(A.vertices);
    const Eigen::Index stride = 3 * Eigen::Index(K);
    const bool avx2 =
        kernel == TransportKernel::avx2 || (kernel == TransportKernel::automatic && cpu_has_avx2());
    SHPRT_CHECK(!avx2 || cpu_has_avx2(), unsupported, "this CPU has no AVX2");
    // Each output row is its own sum over its row's entries in column order: the bits never
    // depend on the blocks, the threads or the kernel.
    const auto eigen_block = [&](const TransportOperator::Block& b) {
        const auto rows = static_cast<Eigen::Index>(b.rows());
        for (int c = 0; c < 3; ++c) {
            const SparseMap a(rows, V, Eigen::Index(b.nnz()), b.starts(), b.columns(),
                              b.channel(c));
            const DenseMap x(in + c * K, V, K, Eigen::OuterStride<>(stride));
            DenseOut y(out + Eigen::Index(b.first) * stride + c * K, rows, K,
                       Eigen::OuterStride<>(stride));
            y.noalias() = a * x;
        }
    };
    tbb::enumerable_thread_specific<std::vector<float>> accumulators;
    const auto run_block = [&](const TransportOperator::Block& b) {
        if (progress && progress->stopped()) return;
        if (!avx2) {
            eigen_block(b);
        } else {
            std::vector<float>& acc = accumulators.local();
            acc.resize(std::size_t(stride));
            transport_rows_avx2(b, in, out, K, acc.data());
        }
        if (progress) {
            progress->add(b.rows(), 0);
            progress->poll();
        }
    };
    const std::size_t blocks = A.blocks.size();
    if (thread_count(threads) == 1 || blocks == 1) {
        for (const auto& b : A.blocks) run_block(b);
        return;
    }
    parallel_each(threads, blocks, [&](std::size_t b) { run_block(A.blocks[b]); });
}

}  // namespace

TransportMeshView transport_mesh_view(const Mesh& mesh) {
    static_assert(sizeof(mesh.triangles[0]) == 3 * sizeof(std::uint32_t));
    return TransportMeshView{mesh.positions.data(),
                             reinterpret_cast<const std::uint32_t*>(mesh.triangles.data()),
                             mesh.albedo.data()};
}

TransportOperator build_transport_operator(const Mesh& mesh, const DirectionSet& directions,
                                           const Tracer& tracer, const TransportOptions& options) {
    return trace_transport(mesh, detail::make_direction_table(directions), tracer, options, nullptr,
                           nullptr);
}

void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads) {
    apply_transport_blocks(A, in, out, K, threads, TransportKernel::automatic, nullptr);
}

void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads,
                     TransportKernel kernel) {
    apply_transport_blocks(A, in, out, K, threads, kernel, nullptr);
}

namespace detail {

void check_interreflected_job(const BakeJob& job) {
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
                "interreflected transfer writes host rows (a DeviceSink cannot take them)");
    // bounces, tolerance and max_bounces were checked by validate() at bake()'s boundary.
    SHPRT_CHECK(mesh.albedo.size() == V, invalid_argument,
                "interreflected transfer needs an albedo per vertex ({} for {} vertices)",
                mesh.albedo.size(), V);
}

TransferInfo bake_interreflected(const BakeJob& job, const BakeOptions& options,
                                 const DirectionSet& directions, const Tracer* tracer,
                                 double seconds_bvh) {
    const auto start = Clock::now();
    check_interreflected_job(job);
    const Mesh& mesh = *job.occluders;
    const Receivers& rx = job.receivers;
    const std::size_t V = mesh.vertex_count();
    const int K = options.K;

    const int wanted = options.converge ? options.max_bounces : options.bounces;
    std::vector<float> T0;
    TransferInfo info;
    TransportOperator A;
    std::uint64_t pass_bytes = 0;  // the fused pass's tables and buffers
    if (wanted == 0) {
        // T_0 alone: exactly the shadowed bake (same stages, same bits), into host memory.
        BakeOptions direct_options = options;
        direct_options.transfer = TransferKind::shadowed;
        HostSink direct_sink;
        BakeJob direct_job = job;
        direct_job.sink = &direct_sink;
        info = bake_cpu(direct_job, direct_options, directions, tracer, seconds_bvh);
        T0 = direct_sink.take_rows();
    } else {
        // One pass of closest hits gives T_0's visibility and A's rows (the same rays).
        const auto pass_start = Clock::now();
        const DirectionTable table = make_direction_table(directions);
        const std::vector<float> Y = basis_table(K, directions);
        T0.resize(V * std::size_t(K));
        const DirectRows direct{Y.data(), K, T0.data()};
        TransportOptions to;
        to.two_sided = options.two_sided;
        to.threads = options.threads;
        to.rows_per_block = options.chunk_receivers;  // 0: the CPU bake's chunks
        to.progress = options.progress;
        // What the budget leaves for A once the rest of the bake (estimated before it: tables,
        // buffers, T_0, the bounce arrays and the rows) has its share; nothing left → every
        // block spills.
        to.memory_budget = transport_memory_budget(mesh, options);
        to.spill_directory = options.spill_directory;
        RowScratch totals;
        // The tracing stage's ETA cannot include the bounces (their cost is known once A is):
        // the bar names them after it, and the bounces' own stage then has the whole rest.
        const std::string then = options.converge
                                     ? std::string("bounces")
                                     : fmt::format("{} bounce{}", wanted, wanted == 1 ? "" : "s");
        A = trace_transport(mesh, table, *tracer, to, &direct, &totals, then);
        const double wall = seconds_since(pass_start);
        BakeOptions direct_options = options;
        direct_options.transfer = TransferKind::shadowed;
        info = bake_info(direct_options, rx, directions.size());
        BakeStats& st = info.stats;
        const double busy = totals.trace_seconds + totals.merge_seconds + totals.project_seconds;
        if (busy > 0) {
            st.seconds_trace = wall * totals.trace_seconds / busy;
            st.seconds_operator = wall * totals.merge_seconds / busy;
            st.seconds_project = wall * totals.project_seconds / busy;
        }
        st.seconds_bvh = seconds_bvh;
        st.rays_cast = A.rays_cast;
        const int threads = thread_count(options.threads);
        st.device_name = fmt::format("cpu: {} thread{}", threads, threads == 1 ? "" : "s");
        pass_bytes =
            Y.size() * sizeof(float) + table.bytes() + totals.w.size() * sizeof(float) +
            std::uint64_t(threads) *
                (directions.size() * (sizeof(Vec3f) + sizeof(std::uint32_t) + sizeof(Hit)) +
                 25 * std::uint64_t(V));
    }

    return finish_interreflected(
        job, options, std::move(info), std::move(T0), A,
        [&](const float* in, float* out, BakeProgress& progress) {
            apply_transport_blocks(A, in, out, K, options.threads, TransportKernel::automatic,
                                   &progress);
        },
        pass_bytes + (tracer ? tracer->memory_bytes() : 0), seconds_bvh + seconds_since(start));
}

TransferInfo finish_interreflected(const BakeJob& job, const BakeOptions& options,
                                   TransferInfo info, std::vector<float> T0,
                                   const TransportOperator& A, const BounceProduct& bounce,
                                   std::uint64_t other_bytes, double seconds_so_far) {
    const auto start = Clock::now();
    const std::size_t V = job.occluders->vertex_count();
    const int K = options.K;
    const int wanted = options.converge ? options.max_bounces : options.bounces;
    info.kind = TransferKind::interreflected;
    info.layout.channels = 3;
    InterreflectionInfo& ir = info.interreflection;
    ir.two_sided = options.two_sided;
    ir.converge = options.converge;
    ir.tolerance = options.converge ? options.tolerance : 0.0;
    ir.albedo_source = job.occluders->albedo_source;
    ir.operator_nnz = A.nnz();
    ir.operator_bytes = A.bytes();
    ir.operator_rays = A.rays_cast;
    info.stats.operator_bytes_spilled = A.spilled_bytes;

    const std::size_t row = 3 * std::size_t(K);
    std::vector<float> sum(V * row);
    for (std::size_t v = 0; v < V; ++v)
        for (int c = 0; c < 3; ++c)
            std::copy_n(T0.data() + v * K, K, sum.data() + v * row + std::size_t(c) * K);

    std::uint64_t buffers_bytes = sum.size() * sizeof(float);
    if (wanted > 0) {
        const auto bounce_start = Clock::now();
        std::vector<float> previous = sum, current(sum.size());
        buffers_bytes += 2 * sum.size() * sizeof(float);
        // One bar over the bounces' rows (with --bounces converged the total is unknown).
        BakeProgress progress(options.progress, "bounces", "rows",
                              options.converge ? 0 : std::uint64_t(wanted) * V);
        for (int b = 1; b <= wanted; ++b) {
            bounce(previous.data(), current.data(), progress);
            SHPRT_CHECK(!progress.stopped(), cancelled, "bake cancelled during bounce {}", b);
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
            if (options.converge && change < options.tolerance) break;
        }
        SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled after {} bounces", ir.bounces);
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
    st.seconds_total = seconds_so_far + seconds_since(start);
    st.peak_bytes_host = std::max<std::uint64_t>(
        st.peak_bytes_host, V * std::size_t(K) * sizeof(float) + (A.bytes() - A.spilled_bytes) +
                                buffers_bytes + other_bytes);
    return info;
}

}  // namespace detail
}  // namespace shprt
