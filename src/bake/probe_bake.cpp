// The bake of transfer probes (bake/probe_bake.hpp, docs/probes.md): closest hits from every
// probe over the bake's sphere set, the shadowed part projected as the glossy bake projects its
// matrices (Yᵀ·diag(W)·Y by one SGEMM per chunk on the pair-product table), the bounced part of an
// interreflected bake from the bounce sources' light with the transport operator's own entries.
#include "shprt/bake/probe_bake.hpp"

#include "bake/bake_internal.hpp"
#include "bake/bake_progress.hpp"
#include "bake/stages.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace shprt {
namespace {

constexpr const char* kProbesForm =
    "expected auto, auto:SPACING, NX,NY,NZ or NX,NY,NZ:SPACING (e.g. 16,8,16 or auto:0.5)";

// One worker's buffers.
struct ProbeScratch {
    std::vector<float> w;             // W[chunk×S]: weight_s where the ray escapes
    std::vector<float> c;             // the chunk's packed matrices, K(K+1)/2 each
    std::vector<Hit> hits;            // one probe's closest hits, in the trace order
    std::vector<float> g;             // the bounced light, K×S per channel (transposed)
    std::vector<float> m;             // its projection, K×K (transposed)
    std::vector<std::uint8_t> valid;  // the chunk's probes
};

}  // namespace

std::optional<ProbeSpec> parse_probes(const std::string& probes, const std::string& box,
                                      std::optional<long long> bands) {
    if (probes.empty()) {
        SHPRT_CHECK(box.empty(), invalid_argument,
                    "--probe-box needs --probes (auto or NX,NY,NZ): it is the probe grid's box");
        SHPRT_CHECK(!bands, invalid_argument,
                    "--probe-bands needs --probes (auto or NX,NY,NZ): it is the probes' SH size");
        return std::nullopt;
    }
    ProbeSpec spec;
    const std::size_t colon = probes.find(':');
    const std::string grid = probes.substr(0, colon);
    if (colon != std::string::npos) {
        double spacing = 0;
        SHPRT_CHECK(parse_number(probes.substr(colon + 1), spacing) && spacing > 0 &&
                        std::isfinite(spacing) && float(spacing) > 0,
                    invalid_argument,
                    "--probes '{}': the spacing must be a positive number of "
                    "metres; {}",
                    probes, kProbesForm);
        spec.spacing = float(spacing);
    }
    if (grid != "auto") {
        std::size_t start = 0, total = 1;
        for (int a = 0; a < 3; ++a) {
            const std::size_t comma = grid.find(',', start);
            SHPRT_CHECK((comma == std::string::npos) == (a == 2), invalid_argument,
                        "--probes '{}': {}", probes, kProbesForm);
            std::int64_t n = 0;
            const std::string item =
                grid.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
            SHPRT_CHECK(parse_integer(item, n) == IntegerParse::ok, invalid_argument,
                        "--probes '{}': '{}' is not a whole number; {}", probes, item, kProbesForm);
            SHPRT_CHECK(n >= 1 && n <= kMaxProbeSide, invalid_argument,
                        "--probes '{}': each count must be 1 to {}", probes, kMaxProbeSide);
            spec.counts[std::size_t(a)] = int(n);
            total *= std::size_t(n);
            start = comma + 1;
        }
        SHPRT_CHECK(total <= kMaxProbes, invalid_argument,
                    "--probes '{}': {} probes, more than the {} a grid may hold", probes, total,
                    kMaxProbes);
    }
    if (!box.empty()) {
        const std::vector<double> v = parse_numbers(box, 6, "--probe-box X0,Y0,Z0,X1,Y1,Z1");
        SHPRT_CHECK(v[0] <= v[3] && v[1] <= v[4] && v[2] <= v[5], invalid_argument,
                    "--probe-box '{}': each low corner coordinate must be at most the high one's",
                    box);
        spec.box = std::array<Vec3f, 2>{Vec3f{float(v[0]), float(v[1]), float(v[2])},
                                        Vec3f{float(v[3]), float(v[4]), float(v[5])}};
    }
    if (bands) {
        SHPRT_CHECK(*bands >= 1 && *bands <= kMaxProbeBands, invalid_argument,
                    "--probe-bands {}: must be 1 to {} (K = bands² coefficients)", *bands,
                    kMaxProbeBands);
        spec.bands = int(*bands);
    }
    return spec;
}

ProbeGrid probe_grid_layout(const ProbeSpec& spec, const Mesh& mesh, bool interreflected) {
    Vec3f lo, hi;
    if (spec.box) {
        lo = (*spec.box)[0], hi = (*spec.box)[1];
    } else {
        const Bounds b = mesh_bounds(mesh);
        lo = b.lo, hi = b.hi;
    }
    ProbeGrid grid;
    grid.K = sh_count(spec.bands);
    grid.channels = interreflected ? 3 : 1;
    const bool automatic = spec.counts[0] == 0;
    float spacing = spec.spacing > 0 ? spec.spacing : kDefaultProbeSpacing;
    const auto count_along = [&](int a, float s) {
        const double n = std::ceil(double(hi[a] - lo[a]) / double(s) - 1e-4);
        return int(std::clamp(n, 1.0, double(kMaxProbeSide)));
    };
    if (automatic && spec.spacing == 0) {
        // The default spacing, grown until the grid is at most kMaxAutoProbes.
        for (;;) {
            const std::size_t n = std::size_t(count_along(0, spacing)) *
                                  std::size_t(count_along(1, spacing)) *
                                  std::size_t(count_along(2, spacing));
            if (n <= kMaxAutoProbes) break;
            spacing *= 1.25f;
        }
    }
    for (int a = 0; a < 3; ++a) {
        const std::size_t i = std::size_t(a);
        const float extent = hi[a] - lo[a];
        const int n = automatic ? count_along(a, spacing) : spec.counts[i];
        // Counts with a spacing: that grid, centred on the box. Otherwise the centres of n equal
        // cells that fill the box (automatic: n = ⌈extent / spacing⌉, so cells of at most the
        // spacing) — never on the box's own faces, which are a scene's outer surfaces.
        const bool centred = !automatic && spec.spacing > 0;
        const float s = centred ? spacing : (extent > 0 ? extent / float(n) : spacing);
        grid.counts[i] = n;
        grid.spacing[a] = s;
        grid.origin[a] = 0.5f * (lo[a] + hi[a]) - 0.5f * float(n - 1) * s;
    }
    SHPRT_CHECK(grid.count() <= kMaxProbes, invalid_argument,
                "--probes: {}x{}x{} probes, more than the {} a grid may hold", grid.counts[0],
                grid.counts[1], grid.counts[2], kMaxProbes);
    return grid;
}

std::uint64_t bake_probe_grid(ProbeGrid& grid, const Mesh& occluders, const BakeOptions& options,
                              const DirectionSet& directions, const Tracer* tracer,
                              const ProbeBounce* bounce) {
    const int K = grid.K;
    SHPRT_CHECK(K >= 1 && K <= sh_count(kMaxProbeBands), invalid_argument,
                "probe grid: K = {} (1 to {})", K, sh_count(kMaxProbeBands));
    SHPRT_CHECK(grid.channels == (bounce ? 3 : grid.channels) && !(bounce && !tracer),
                invalid_argument, "probe grid: bounced light needs 3 channels and a tracer");
    SHPRT_CHECK(!bounce || bounce->K >= K, invalid_argument,
                "probe grid: the sources' light has {} coefficients, fewer than the probes' {}",
                bounce ? bounce->K : 0, K);
    const std::size_t P = grid.count(), S = directions.size(), KK = std::size_t(K) * K;
    const std::size_t F = std::size_t(K) * std::size_t(K + 1) / 2;
    const detail::DirectionTable table = detail::make_direction_table(directions);
    const std::vector<float> Y = basis_table(K, directions);
    const std::vector<float> pairs = detail::pair_product_table(Y, S, K);
    grid.matrices.assign(P * std::size_t(grid.channels) * KK, 0.0f);
    grid.valid.assign(P, 0);

    detail::BakeProgress progress(options.progress, tracer != nullptr, P, S);
    progress.set_stage("probes");
    // The stage's first report, so that a display times it from its start.
    if (options.progress &&
        !options.progress(ProgressInfo{"probes", 0, P * S, tracer ? "rays" : "samples"}))
        fail(ErrorCode::cancelled, "bake cancelled before its probes");
    tbb::enumerable_thread_specific<ProbeScratch> scratch;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const std::size_t chunks = (P + kProbeChunk - 1) / kProbeChunk;

    auto run_chunk = [&](std::size_t chunk) {
        if (progress.stopped()) return;
        ProbeScratch& sc = scratch.local();
        sc.w.assign(kProbeChunk * S, 0.0f);
        sc.c.resize(kProbeChunk * F);
        sc.hits.resize(S);
        sc.valid.assign(kProbeChunk, 1);
        const std::size_t first = chunk * kProbeChunk;
        const std::size_t count = std::min(kProbeChunk, P - first);
        for (std::size_t j = 0; j < count; ++j) {
            const std::size_t probe = first + j;
            const int x = int(probe % std::size_t(grid.counts[0]));
            const int y = int(probe / std::size_t(grid.counts[0]) % std::size_t(grid.counts[1]));
            const int z = int(probe / (std::size_t(grid.counts[0]) * grid.counts[1]));
            float* row = sc.w.data() + j * S;
            std::copy(table.weight.begin(), table.weight.end(), row);
            if (!tracer) continue;
            tracer->closest_hits(grid.position(x, y, z), table.trace_dirs.data(), int(S), 0.0f,
                                 kInf, sc.hits.data());
            std::size_t hits = 0, back = 0;
            for (std::size_t r = 0; r < S; ++r) {
                const Hit& h = sc.hits[r];
                if (!h.hit) continue;
                row[table.trace_order[r]] = 0.0f;
                ++hits;
                back += detail::meets_back_face(occluders, h.triangle, table.trace_dirs[r]);
            }
            // Inside or under geometry: most of what the probe sees are the backs of surfaces.
            if (double(back) > double(kProbeBackShare) * double(hits)) {
                sc.valid[j] = 0;
                std::fill(row, row + S, 0.0f);
            }
            if (bounce && sc.valid[j]) {
                // The light the hits send (transport_hit_entries: the hit's cell corners, its
                // albedo, weight_s/π), per channel c and coefficient k at g[(c·K + k)·S + s]:
                // G_cᵀ, whose product with Y is the bounced part M_cᵀ.
                sc.g.assign(3 * std::size_t(K) * S, 0.0f);
                for (std::size_t r = 0; r < S; ++r) {
                    const Hit& h = sc.hits[r];
                    if (!h.hit) continue;
                    const std::uint32_t s = table.trace_order[r];
                    TransportHitEntries e{};
                    if (!transport_hit_entries(bounce->view, table.trace_dirs[r], table.weight[s],
                                               SampleHit{h.triangle, h.u, h.v}, bounce->two_sided,
                                               e))
                        continue;
                    for (int c = 0; c < 3; ++c)
                        for (int k = 0; k < K; ++k) {
                            float sum = 0.0f;
                            for (int q = 0; q < 3; ++q)
                                sum += e.value[q][c] *
                                       bounce->light[(std::size_t(e.column[q]) * 3 + c) *
                                                         std::size_t(bounce->K) +
                                                     std::size_t(k)];
                            sc.g[(std::size_t(c) * K + std::size_t(k)) * S + s] = sum;
                        }
                }
                sc.m.resize(3 * KK);
                for (int c = 0; c < 3; ++c)
                    detail::project_rows(sc.g.data() + std::size_t(c) * K * S, std::size_t(K), S,
                                         Y.data(), K, sc.m.data() + std::size_t(c) * KK);
                float* out = grid.matrices.data() + probe * 3 * KK;
                for (int c = 0; c < 3; ++c)
                    for (int i = 0; i < K; ++i)
                        for (int k = 0; k < K; ++k)  // M_c[i][k] = (M_cᵀ)[k][i]
                            out[std::size_t(c) * KK + std::size_t(i) * K + std::size_t(k)] =
                                sc.m[std::size_t(c) * KK + std::size_t(k) * K + std::size_t(i)];
            }
            progress.add(1, tracer ? S : 0);
            if (!progress.poll()) return;
        }
        // The visible sky: M = Yᵀ·diag(W)·Y, packed, one SGEMM over the whole chunk (rows past
        // the grid are zero), then unpacked into every channel (the sky's light is grey).
        detail::project_rows(sc.w.data(), kProbeChunk, S, pairs.data(), int(F), sc.c.data());
        for (std::size_t j = 0; j < count; ++j) {
            const std::size_t probe = first + j;
            grid.valid[probe] = sc.valid[j];
            if (!sc.valid[j]) continue;
            const float* packed = sc.c.data() + j * F;
            for (int c = 0; c < grid.channels; ++c) {
                float* m = grid.matrices.data() + (probe * std::size_t(grid.channels) + c) * KK;
                const float* p = packed;
                for (int i = 0; i < K; ++i)
                    for (int k = i; k < K; ++k, ++p) {
                        m[std::size_t(i) * K + std::size_t(k)] += *p;
                        if (k != i) m[std::size_t(k) * K + std::size_t(i)] += *p;
                    }
            }
        }
    };
    {
        const detail::SingleThreadedBlas single_threaded_blas;
        parallel_each(options.threads, chunks, run_chunk);
    }
    SHPRT_CHECK(progress.finish(), cancelled, "bake cancelled after {} of {} probes",
                progress.receivers_done(), P);
    return progress.rays();
}

namespace detail {

void bake_job_probes(const BakeJob& job, const BakeOptions& options, const DirectionSet& directions,
                     const Tracer* tracer, const ProbeBounce* bounce, TransferInfo& info) {
    if (!job.probes) return;
    const auto start = std::chrono::steady_clock::now();
    // A probe has no tangent frame: a local bake's probes take its sampler's sphere set.
    const bool local = options.direction_frame == DirectionFrame::local;
    const DirectionSet sphere =
        local ? make_direction_set(options.sampler, options.seed, options.samples) : DirectionSet{};
    std::unique_ptr<Tracer> own;
    if (!tracer && kind_row(options.transfer).traces_rays) {
        EmbreeTracerOptions closest_hits_only;  // a probe's rays find their closest hits
        closest_hits_only.merge_coplanar = false;
        in_arena(options.threads,
                 [&] { own = make_embree_tracer(*job.occluders, closest_hits_only); });
        tracer = own.get();
    }
    const std::uint64_t rays = bake_probe_grid(*job.probes, *job.occluders, options,
                                               local ? sphere : directions, tracer, bounce);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    info.stats.rays_cast += rays;
    info.stats.seconds_trace += seconds;
    info.stats.seconds_total += seconds;
}

}  // namespace detail

}  // namespace shprt
