// Interreflected transfer (interreflect.hpp, docs/interreflection.md): the bounces of diffuse
// PRT as products with a sparse transport operator.
//
// Sloan, Kautz & Snyder 2002, section 5 ("interreflected transfer"): per bounce, gather the
// previous bounce's transfer at the hits of each vertex's rays, weighted by the cosine and the
// albedo. They re-trace per bounce; here T_0 is the shadowed bake, and the closest hits of a
// nested prefix of the directions from every bounce source (bounce_sources.hpp) are traced once
// into the sparse N×N operator A (one row per source, in row blocks of compressed rows), so that
// each bounce is one sparse × dense product over the K·3 columns of the transfer. A's blocks are
// kept or spilled by transport_store.cpp.
#include "shprt/bake/interreflect.hpp"

#include "bake/bake_internal.hpp"
#include "bake/bake_progress.hpp"
#include "bake/stages.hpp"
#include "shprt/bake/bounce_sources.hpp"
#include "shprt/bake/ground_truth.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace shprt {
namespace detail {

bool meets_back_face(const Mesh& mesh, std::uint32_t t, Vec3f dir) {
    const auto& tri = mesh.triangles[t];
    const Vec3f p0 = mesh.positions[tri[0]];
    const Vec3f face = cross(mesh.positions[tri[1]] - p0, mesh.positions[tri[2]] - p0);
    return dot(face, dir) >= 0.0f;
}

// Merges rows of A; one per worker (it keeps a dense accumulator over the vertices: 25 bytes
// each).
class TransportRowBuilder {
public:
    // `view`: the mesh and its bounce sources; `columns`: the sources (A's columns).
    TransportRowBuilder(const TransportMeshView& view, std::size_t columns, bool two_sided)
        : m_view(view), m_columns(columns), m_two_sided(two_sided) {}

    // Appends one row to `out` (its entries, then its end in out.row_start) from its rays in
    // direction order: ray r has direction dirs[r], unoccluded weight weights[r] = max(0, n·w_s)·
    // weight_s and closest hit hits[r] (kNoTriangle: it escaped). Each hit on a front face (or
    // any face when two-sided) adds weights[r]/π · ρ_c(h) · β_k(h) to the columns of its
    // triangle's vertices k; entries of one column are summed in ray order, in double.
    void add_row(const Vec3f* dirs, const float* weights, const SampleHit* hits, std::uint32_t rays,
                 TransportOperator::Block& out);

    static std::size_t bytes(std::size_t columns) { return 25 * columns; }

private:
    TransportMeshView m_view;
    std::size_t m_columns;
    bool m_two_sided;
    std::vector<double> m_sums;  // 3 per column
    std::vector<std::uint8_t> m_seen;
    std::vector<std::uint32_t> m_touched;
};

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

// T_0's rows of the inner bounce sources from the same rays as A's (the fused pass of
// bake_interreflected): the visibility of a direction is "no closest hit", the very answer of the
// shadowed bake's occlusion rays, projected with the SGEMM of bake_cpu over the directions the
// source traced (its nested prefix). The receivers' rows (RowPoints::gather_rows) are not
// projected: the full bake's T_0 replaces them (finish_interreflected).
struct DirectRows {
    const float* Y = nullptr;  // the basis table, S×K
    int K = 0;
    float* rows = nullptr;  // V×K
};

// The points whose rows A has: the bounce sources (the mesh's vertices first), the view their
// hits are read through and, per point, validity's reach (bounce_sources.hpp).
struct RowPoints {
    const Vec3f* positions = nullptr;
    const Vec3f* normals = nullptr;
    const float* reach = nullptr;  // nullptr: no validity counts
    std::size_t count = 0;
    TransportMeshView view;
    // Rows [0, gather_rows) trace every direction of the table (the receivers' final gather);
    // the others the first `inner` (0: all), weighted as a set of their own.
    std::size_t gather_rows = std::numeric_limits<std::size_t>::max();
    std::size_t inner = 0;
    // The gather rows cast the table's directions mapped to their cosine-weighted hemisphere
    // (cosine_gather_directions) instead of the sphere's directions above their horizon.
    bool cosine_gather = false;
};

// The directions of a sphere set mapped to the cosine-weighted hemisphere around +z: a direction
// (x, y, z) of a set uniform on the sphere has z uniform on [−1, 1] and azimuth φ uniform, so
// u = (1 + z)/2 is uniform on [0, 1] and (cos θ = √u, φ) is distributed as cos θ/π on the
// hemisphere — the map keeps the set's stratification. Local (x, y, z) = (x, y)/√(2(1 + z)),
// √((1 + z)/2); the pole z = −1 goes to the horizon along +x.
std::vector<Vec3f> cosine_gather_directions(const detail::DirectionTable& table) {
    std::vector<Vec3f> out(table.size());
    for (std::size_t s = 0; s < table.size(); ++s) {
        const Vec3f d = table.dirs[s];
        const float up = 1.0f + d.z;
        if (up <= 0.0f) {
            out[s] = Vec3f{1.0f, 0.0f, 0.0f};
            continue;
        }
        const float r = 1.0f / std::sqrt(2.0f * up);
        out[s] = Vec3f{d.x * r, d.y * r, std::sqrt(0.5f * up)};
    }
    return out;
}

// What one point's rays met, for its validity (source_is_valid).
struct PointRays {
    std::uint32_t rays = 0, back = 0, near_back = 0;
};

// The rows of A (and, given `direct`, of T_0) for every point, in blocks of `rows_per_block`;
// `counts` (one per point, or null) gets what each point's rays met. `then`: what follows
// (ProgressInfo::then), empty for A alone.
TransportOperator trace_transport(const Mesh& mesh, const RowPoints& points,
                                  const detail::DirectionTable& table, const Tracer& tracer,
                                  const TransportOptions& options, const DirectRows* direct,
                                  RowScratch* totals, PointRays* counts,
                                  std::string_view stage = "bake", std::string_view then = {}) {
    const std::size_t V = points.count;
    SHPRT_CHECK(
        mesh.albedo.size() == mesh.vertex_count() && mesh.normals.size() == mesh.vertex_count(),
        invalid_argument,
        "interreflected transfer needs a normal and an albedo per vertex ({} vertices, {} "
        "normals, {} albedo values)",
        mesh.vertex_count(), mesh.normals.size(), mesh.albedo.size());
    SHPRT_CHECK(V <= std::size_t(std::numeric_limits<std::int32_t>::max()), invalid_argument,
                "interreflected transfer supports at most 2^31 - 1 bounce sources ({} given)", V);
    const std::size_t S = table.size();
    const std::size_t block_rows =
        options.rows_per_block > 0 ? options.rows_per_block : auto_chunk_receivers(V, S);
    const std::size_t block_count = (V + block_rows - 1) / block_rows;
    TransportOperator A;
    A.vertices = V;
    A.blocks.resize(block_count);
    tbb::enumerable_thread_specific<RowScratch> scratch;
    detail::BakeProgress progress(options.progress, true, V, S);
    progress.set_stage(stage);
    progress.set_then(then);
    // A finished block stays in memory while the finished blocks fit the budget, else it goes
    // to the spill file.
    detail::TransportBlockStore store(options.memory_budget, options.spill_directory);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr float kKeep[2] = {1.0f, 0.0f};  // visible, occluded: as trace_row, branch-free
    const std::vector<Vec3f> gather_local =
        points.cosine_gather ? cosine_gather_directions(table) : std::vector<Vec3f>();
    // A cosine-distributed ray's weight: ∫ cos·f dω ≈ (π/S)·Σ f (add_row divides by π).
    const float gather_weight = float(kPi) / float(S);

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
        if (!sc.rows) sc.rows.emplace(points.view, V, options.two_sided);
        const Vec3f n = points.normals[v];
        // The rays: m directions and their unoccluded weights.
        const bool gather = points.cosine_gather && v < points.gather_rows;
        std::uint32_t m = 0;
        if (gather) {
            // A receiver's final gather: every direction, in its own hemisphere. Its T_0 row is
            // not projected (the full bake's replaces it), so `weight` is not needed.
            Vec3d t, b;
            orthonormal_frame(Vec3d{n.x, n.y, n.z}, t, b);
            const Vec3f tf{float(t.x), float(t.y), float(t.z)};
            const Vec3f bf{float(b.x), float(b.y), float(b.z)};
            for (std::size_t s = 0; s < S; ++s) {
                const Vec3f l = gather_local[s];
                sc.ray_dirs[s] = tf * l.x + bf * l.y + n * l.z;
                sc.ray_weights[s] = gather_weight;
            }
            m = static_cast<std::uint32_t>(S);
        } else {
            detail::weight_row(n, table, weight);
            if (v >= points.gather_rows && points.inner > 0 && points.inner < S) {
                // An inner source: the nested prefix of `inner` directions, each weighing
                // S/inner of the table's (a Monte Carlo set of its own: 4π/inner).
                const float scale = float(S) / float(points.inner);
                for (std::size_t s = 0; s < points.inner; ++s) weight[s] *= scale;
                std::fill(weight + points.inner, weight + S, 0.0f);
            }
            for (std::size_t s = 0; s < S; ++s) {
                sc.ray_index[m] = static_cast<std::uint32_t>(s);
                sc.ray_dirs[m] = table.dirs[s];
                m += weight[s] != 0.0f ? 1u : 0u;
            }
            for (std::uint32_t r = 0; r < m; ++r) sc.ray_weights[r] = weight[sc.ray_index[r]];
        }
        if (m > 0)
            tracer.closest_hits(offset_ray_origin(points.positions[v], n), sc.ray_dirs.data(),
                                static_cast<int>(m), 0.0f, kInf, sc.hits.data());
        const double merge_start = thread_cpu_seconds();
        PointRays met{m, 0, 0};
        for (std::uint32_t r = 0; r < m; ++r) {
            const Hit& h = sc.hits[r];
            sc.sample_hits[r] = SampleHit{h.hit ? h.triangle : kNoTriangle, h.u, h.v};
            if (!gather) weight[sc.ray_index[r]] *= kKeep[h.hit ? 1 : 0];
            if (counts && h.hit && detail::meets_back_face(mesh, h.triangle, sc.ray_dirs[r])) {
                ++met.back;
                met.near_back += h.t < points.reach[v] ? 1u : 0u;
            }
        }
        if (counts) counts[v] = met;
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
            // The inner sources of the block: the rows from max(first, gather_rows) on.
            const std::size_t skip =
                std::min(count, points.gather_rows > out.first ? points.gather_rows - out.first
                                                               : std::size_t(0));
            const std::size_t depth = points.inner > 0 && points.inner < S ? points.inner : S;
            if (skip < count)
                detail::project_rows(W + skip * S, count - skip, S, depth, direct->Y, direct->K,
                                     direct->rows + (out.first + skip) * std::size_t(direct->K));
            sc.project_seconds += thread_cpu_seconds() - project_start;
        }
        store.keep(c, out);
    };

    {
        const detail::SingleThreadedBlas single_threaded_blas;
        parallel_each(options.threads, block_count, build_block);
    }
    SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled after {} of {} bounce sources",
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

RowPoints row_points(const Mesh& mesh, const BounceSources& sources) {
    return RowPoints{sources.positions.data(), sources.normals.data(), sources.reach.data(),
                     sources.size(), sources.view(mesh)};
}

}  // namespace

namespace detail {

void TransportRowBuilder::add_row(const Vec3f* dirs, const float* weights, const SampleHit* hits,
                                  std::uint32_t rays, TransportOperator::Block& out) {
    if (m_seen.size() != m_columns) {
        m_sums.assign(3 * m_columns, 0.0);
        m_seen.assign(m_columns, 0);
    }
    m_touched.clear();
    TransportHitEntries entries;
    for (std::uint32_t r = 0; r < rays; ++r) {
        if (!transport_hit_entries(m_view, dirs[r], weights[r], hits[r], m_two_sided, entries))
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

TransportMeshView transport_mesh_view(const Mesh& mesh) {
    static_assert(sizeof(mesh.triangles[0]) == 3 * sizeof(std::uint32_t));
    return TransportMeshView{mesh.positions.data(),
                             reinterpret_cast<const std::uint32_t*>(mesh.triangles.data()),
                             mesh.albedo.data()};
}

TransportOperator build_transport_operator(const Mesh& mesh, const DirectionSet& directions,
                                           const Tracer& tracer, const TransportOptions& options) {
    const BounceSources sources =
        make_bounce_sources(mesh, std::numeric_limits<float>::infinity(), options.two_sided);
    return build_source_operator(mesh, sources, directions, tracer, options);
}

TransportOperator build_source_operator(const Mesh& mesh, const BounceSources& sources,
                                        const DirectionSet& directions, const Tracer& tracer,
                                        const TransportOptions& options) {
    SHPRT_CHECK(
        sources.vertices == mesh.vertex_count() && sources.grid.size() == mesh.triangle_count() &&
            sources.two_sided == options.two_sided,
        invalid_argument, "the bounce sources were made for another mesh or the other side option");
    return trace_transport(mesh, row_points(mesh, sources),
                           detail::make_direction_table(directions), tracer, options, nullptr,
                           nullptr, nullptr);
}

int bounce_coeffs(const BakeOptions& options) {
    return std::min(options.K,
                    options.bounce_coeffs > 0 ? options.bounce_coeffs : kDefaultBounceCoeffs);
}

DirectionSet indirect_direction_set(const BakeOptions& options, const DirectionSet& directions,
                                    std::size_t gather_base) {
    const std::size_t base = gather_base > 0 ? gather_base : directions.size();
    const std::size_t n = options.indirect_samples > 0
                              ? options.indirect_samples
                              : std::max<std::size_t>(1, base / kIndirectSampleShare);
    // A local bake's set is in the frame; the bounce sources take the sphere set of its sampler.
    if (n >= directions.size() && options.direction_frame == DirectionFrame::sphere)
        return directions;
    return make_direction_set(options.sampler, options.seed,
                              static_cast<std::uint32_t>(std::min(n, directions.size())));
}

std::size_t gather_base_of(const std::vector<std::uint32_t>& receiver_samples) {
    if (receiver_samples.empty()) return 1;
    double sum = 0;
    for (const std::uint32_t s : receiver_samples) sum += double(s);
    return std::bit_ceil(
        static_cast<std::size_t>(std::ceil(sum / double(receiver_samples.size()))));
}

float bake_source_spacing(const Mesh& mesh, const BakeOptions& options) {
    return options.source_spacing > 0 ? options.source_spacing : default_source_spacing(mesh);
}

BounceSources detail::bake_bounce_sources(const Mesh& mesh, const BakeOptions& options) {
    return make_bounce_sources(mesh, bake_source_spacing(mesh, options), options.two_sided);
}

std::size_t bake_bounce_source_count(const Mesh& mesh, const BakeOptions& options) {
    if (!kind_row(options.transfer).interreflection) return 0;
    return bounce_source_count(mesh, bake_source_spacing(mesh, options), options.two_sided);
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

BakeOptions direct_stage_options(const BakeOptions& options) {
    BakeOptions direct = options;
    direct.transfer = TransferKind::shadowed;
    const int wanted = options.converge ? options.max_bounces : options.bounces;
    if (wanted > 0 && options.progress) {
        // Its bar names what follows outside its total (ProgressInfo::then).
        auto then = std::make_shared<std::string>(
            options.converge
                ? std::string("bounce sources + bounces")
                : fmt::format("bounce sources + {} bounce{}", wanted, wanted == 1 ? "" : "s"));
        direct.progress = [fn = options.progress, then](const ProgressInfo& info) {
            ProgressInfo with = info;
            with.then = *then;
            return fn(with);
        };
    }
    return direct;
}

std::size_t inner_source_samples(std::size_t gather) {
    return std::max<std::size_t>(1, gather / kInnerSourceShare);
}

SourceOperator trace_source_operator(const Mesh& mesh, const BakeOptions& options,
                                     const DirectionSet& directions, const Tracer& tracer,
                                     BakeStats& stats, std::size_t gather_base) {
    const auto pass_start = Clock::now();
    const std::size_t V = mesh.vertex_count();
    const int K = options.K;
    SourceOperator out;
    out.sources = std::make_unique<BounceSources>(bake_bounce_sources(mesh, options));
    const BounceSources& sources = *out.sources;
    const DirectionSet indirect = indirect_direction_set(options, directions, gather_base);
    const DirectionTable table = make_direction_table(indirect);
    const std::vector<float> Y = basis_table(K, indirect);
    out.T0_sources.resize(sources.size() * std::size_t(K));
    const DirectRows direct{Y.data(), K, out.T0_sources.data()};
    TransportOptions to;
    to.two_sided = options.two_sided;
    to.threads = options.threads;
    to.rows_per_block = options.chunk_receivers;  // 0: the CPU bake's chunks
    to.progress = options.progress;
    // What the budget leaves for A once the rest of the bake (estimated before it: tables,
    // buffers, T_0, the bounce arrays and the rows) has its share; nothing left → every block
    // spills.
    to.memory_budget = transport_memory_budget(mesh, options);
    to.spill_directory = options.spill_directory;
    RowScratch totals;
    std::vector<PointRays> counts(sources.size());
    // The tracing stage's ETA cannot include the bounces (their cost is known once A is): the
    // bar names them after it, and the bounces' own stage then has the whole rest.
    const int wanted = options.converge ? options.max_bounces : options.bounces;
    const std::string then = options.converge
                                 ? std::string("bounces")
                                 : fmt::format("{} bounce{}", wanted, wanted == 1 ? "" : "s");
    RowPoints points = row_points(mesh, sources);
    points.gather_rows = V;
    points.inner = inner_source_samples(indirect.size());
    points.cosine_gather = true;
    out.A = trace_transport(mesh, points, table, tracer, to, &direct, &totals, counts.data(),
                            "bounce sources", then);
    const double wall = seconds_since(pass_start);
    BounceSourceRays& rays = out.rays;
    rays.sources = out.sources.get();
    rays.indirect_samples = indirect.size();
    rays.valid.resize(sources.size());
    for (std::size_t q = 0; q < sources.size(); ++q) {
        const PointRays& c = counts[q];
        rays.valid[q] = source_is_valid(c.rays, c.back, c.near_back) ? 1 : 0;
        if (q < V) rays.receivers_seeing_back_faces += c.back > 0 ? 1 : 0;
    }
    const double busy = totals.trace_seconds + totals.merge_seconds + totals.project_seconds;
    if (busy > 0) {
        stats.seconds_trace += wall * totals.trace_seconds / busy;
        stats.seconds_operator = wall * totals.merge_seconds / busy;
        stats.seconds_project += wall * totals.project_seconds / busy;
    }
    stats.rays_cast += out.A.rays_cast;
    const int threads = thread_count(options.threads);
    out.pass_bytes = Y.size() * sizeof(float) + table.bytes() + totals.w.size() * sizeof(float) +
                     sources.size() * (2 * sizeof(Vec3f) + sizeof(float) + sizeof(PointRays)) +
                     std::uint64_t(threads) *
                         (indirect.size() * (sizeof(Vec3f) + sizeof(std::uint32_t) + sizeof(Hit)) +
                          25 * std::uint64_t(sources.size()));
    return out;
}

TransferInfo bake_interreflected(const BakeJob& job, const BakeOptions& options,
                                 const DirectionSet& directions, const Tracer* tracer,
                                 double seconds_bvh) {
    const auto start = Clock::now();
    check_interreflected_job(job);
    const Mesh& mesh = *job.occluders;
    const int wanted = options.converge ? options.max_bounces : options.bounces;

    // T_0: the shadowed bake itself, with every direction (same stages, same bits).
    BakeOptions direct_options = direct_stage_options(options);
    HostSink direct_sink;
    BakeJob direct_job = job;
    direct_job.sink = &direct_sink;
    TransferInfo info = bake_cpu(direct_job, direct_options, directions, tracer, seconds_bvh);
    std::vector<float> T0 = direct_sink.take_rows();
    // An error-bounded bake bounds T_0 per receiver (its estimates go to the file), and its final
    // gather takes the prefix the receivers needed, of the same nested set (docs/sampling.md).
    TransferSet estimates;
    direct_sink.take_estimates(estimates);
    const std::size_t gather_base =
        options.target_error > 0 ? gather_base_of(estimates.receiver_samples) : 0;
    if (wanted == 0) {
        info = finish_interreflected(job, options, std::move(info), std::move(T0), {},
                                     BounceSourceRays{}, TransportOperator{}, {}, 0,
                                     seconds_since(start) + seconds_bvh, nullptr, &estimates);
        bake_job_probes(job, options, directions, tracer, nullptr, info);
        return info;
    }

    SourceOperator op =
        trace_source_operator(mesh, options, directions, *tracer, info.stats, gather_base);
    const TransportOperator& A = op.A;
    std::vector<float> light;  // the probes' light at the sources
    info = finish_interreflected(
        job, options, std::move(info), std::move(T0), std::move(op.T0_sources), op.rays, A,
        [&](const BounceRows& rows, BakeProgress& progress) {
            apply_transport_rows(A, rows, options.threads, TransportKernel::automatic, &progress);
        },
        op.pass_bytes + (tracer ? tracer->memory_bytes() : 0), seconds_bvh + seconds_since(start),
        job.probes ? &light : nullptr, &estimates);
    if (job.probes) {
        const ProbeBounce bounce{op.sources->view(mesh), light.data(), options.K,
                                 options.two_sided};
        bake_job_probes(job, options, directions, tracer, &bounce, info);
    }
    return info;
}

TransferInfo finish_interreflected(const BakeJob& job, const BakeOptions& options,
                                   TransferInfo info, std::vector<float> T0,
                                   std::vector<float> T0_sources, const BounceSourceRays& rays,
                                   const TransportOperator& A, const BounceProduct& bounce,
                                   std::uint64_t other_bytes, double seconds_so_far,
                                   std::vector<float>* source_light, const TransferSet* estimates) {
    const auto start = Clock::now();
    const Mesh& mesh = *job.occluders;
    const std::size_t V = mesh.vertex_count();
    const int K = options.K;
    const int wanted = options.converge ? options.max_bounces : options.bounces;
    info.kind = TransferKind::interreflected;
    info.layout.channels = 3;
    InterreflectionInfo& ir = info.interreflection;
    ir.two_sided = options.two_sided;
    ir.converge = options.converge;
    ir.tolerance = options.converge ? options.tolerance : 0.0;
    ir.albedo_source = mesh.albedo_source;
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
        const BounceSources& sources = *rays.sources;
        const std::size_t N = sources.size();
        ir.sources = N;
        ir.source_spacing = sources.spacing;
        ir.indirect_samples = rays.indirect_samples;
        ir.receivers_seeing_back_faces = rays.receivers_seeing_back_faces;
        const SourceFill fill = plan_source_fill(mesh, sources, rays.valid);
        ir.invalid_sources = fill.invalid;
        const auto bounce_start = Clock::now();
        // The sources' light before the first bounce, one channel (T_0 is grey): the
        // receivers' T_0 from the full bake (every direction), the other sources' from the
        // operator's own rays.
        std::vector<float> first = std::move(T0_sources);
        std::copy_n(T0.data(), V * std::size_t(K), first.data());
        // The first bounce reaches the receivers in every coefficient: the rows of A's blocks
        // that hold them (`wide_rows`, what a last bounce computes) in all K. The light of the
        // later bounces is carried in the first `narrow` (bounce_coeffs), so every other row, at
        // every bounce, is computed in those alone, into rows of 3 × narrow floats.
        std::size_t wide_rows = 0;
        for (const TransportOperator::Block& blk : A.blocks)
            if (blk.first < V) wide_rows = blk.first + blk.rows();
        const int narrow = bounce_coeffs(options);
        const std::size_t narrow_row = 3 * std::size_t(narrow);
        ir.bounce_coeffs = std::uint64_t(narrow);
        std::vector<float> wide(wide_rows * row), previous(N * narrow_row), current(N * narrow_row);
        buffers_bytes += (wide.size() + 2 * current.size()) * sizeof(float);
        // One bar over the bounces' rows (with --bounces converged the total is unknown).
        BakeProgress progress(options.progress, "bounces", "rows",
                              options.converge ? 0 : std::uint64_t(wanted - 1) * N + wide_rows);
        // The probes' light at the sources: each bounce's input, filled, summed in K columns.
        if (source_light) {
            source_light->assign(N * row, 0.0f);
            buffers_bytes += source_light->size() * sizeof(float);
        }
        const auto add_light = [&](const float* in, int in_channels, int in_K) {
            if (!source_light) return;
            for (std::size_t q = 0; q < N; ++q)
                for (int c = 0; c < 3; ++c) {
                    const float* from = in + (q * std::size_t(in_channels) +
                                              std::size_t(in_channels == 1 ? 0 : c)) *
                                                 std::size_t(in_K);
                    float* to = source_light->data() + q * row + std::size_t(c) * K;
                    for (int k = 0; k < in_K; ++k) to[k] += from[k];
                }
        };
        for (int b = 1; b <= wanted; ++b) {
            // Invalid sources (inside or under geometry) send their valid neighbours' light.
            // The last of a fixed number of bounces is needed at the receivers alone (the final
            // gather): the other sources' rows would feed no further bounce.
            const bool last = !options.converge && b == wanted;
            if (b == 1) {
                fill.apply(first.data(), std::size_t(K), options.threads);
                add_light(first.data(), 1, K);
                bounce(BounceRows{first.data(), 1, K, 0, wide_rows, wide.data(), K, K}, progress);
                if (!last)
                    bounce(BounceRows{first.data(), 1, K, wide_rows, N,
                                      current.data() + wide_rows * narrow_row, narrow, narrow},
                           progress);
            } else {
                fill.apply(previous.data(), narrow_row, options.threads);
                add_light(previous.data(), 3, narrow);
                bounce(BounceRows{previous.data(), 3, narrow, 0, last ? wide_rows : N,
                                  current.data(), narrow, narrow},
                       progress);
            }
            SHPRT_CHECK(!progress.stopped(), cancelled, "bake cancelled during bounce {}", b);
            // The largest relative change of any receiver's transfer by this bounce:
            // |T_b(v)| / |T_0(v) + … + T_b(v)| (Euclidean over its 3K floats; T_b's coefficients
            // past `columns` are zero). The first bounce's receivers' rows go on in `narrow`.
            const int columns = b == 1 ? K : narrow;
            const float* added = b == 1 ? wide.data() : current.data();
            const std::size_t added_row = b == 1 ? row : narrow_row;
            double change = 0;
            for (std::size_t v = 0; v < V; ++v) {
                double t2 = 0, s2 = 0;
                float* s = sum.data() + v * row;
                const float* t = added + v * added_row;
                for (int c = 0; c < 3; ++c) {
                    float* sc = s + std::size_t(c) * K;
                    const float* tc = t + std::size_t(c) * std::size_t(columns);
                    for (int k = 0; k < K; ++k) {
                        if (k < columns) {
                            sc[k] += tc[k];
                            t2 += double(tc[k]) * tc[k];
                        }
                        s2 += double(sc[k]) * sc[k];
                    }
                }
                if (s2 > 0) change = std::max(change, std::sqrt(t2 / s2));
            }
            ir.bounces = b;
            ir.last_change = change;
            if (b == 1) {
                if (!last)
                    for (std::size_t q = 0; q < wide_rows; ++q)
                        for (int c = 0; c < 3; ++c)
                            std::copy_n(wide.data() + q * row + std::size_t(c) * K, narrow,
                                        current.data() + q * narrow_row + std::size_t(c) * narrow);
                first = {};
                wide = {};
            }
            std::swap(previous, current);
            if (options.converge && change < options.tolerance) break;
        }
        SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled after {} bounces", ir.bounces);
        info.stats.seconds_bounces = seconds_since(bounce_start);
    }
    ir.converged = options.converge && ir.bounces > 0 && ir.last_change < options.tolerance;

    TransferSink& sink = *job.sink;
    const bool bounded = estimates != nullptr && !estimates->receiver_samples.empty();
    sink.begin(info.layout, 0, V);
    if (bounded) sink.begin_estimates();
    if (float* rows = sink.host_rows(0, V)) {
        std::copy(sum.begin(), sum.end(), rows);
        sink.write(0, V, rows);
    } else {
        sink.write(0, V, sum.data());
    }
    if (bounded)
        sink.write_estimates(0, V, estimates->receiver_samples.data(),
                             estimates->receiver_error.data());
    sink.finish();
    if (job.direct) {
        job.direct->begin(direct_part_layout(info.layout), 0, V);
        job.direct->write(0, V, T0.data());
        job.direct->finish();
    }

    BakeStats& st = info.stats;
    st.seconds_total = seconds_so_far + seconds_since(start);
    st.peak_bytes_host = std::max<std::uint64_t>(
        st.peak_bytes_host, V * std::size_t(K) * sizeof(float) + (A.bytes() - A.spilled_bytes) +
                                buffers_bytes + other_bytes);
    return info;
}

}  // namespace detail
}  // namespace shprt
