// The estimate stage of the error-bounded bake (error_bound.hpp).
#include "bake/error_bound.hpp"

#include "bake/bake_progress.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

namespace shprt::detail {

namespace {
// Rows of one segment's GEMM: W of a block stays about 1 MiB (bake.hpp's chunk rule), at least
// one row. A function of the segment's length only.
std::size_t block_rows(std::size_t length, std::size_t height) {
    constexpr std::size_t kBlockFloats = std::size_t(1) << 18;
    return std::clamp<std::size_t>(kBlockFloats / length, 1, height);
}

// √(Σ term(i)²) over i < n, in four independent sums: one chain of dependent additions would
// run at the adder's latency (a row's estimate at K = 256 is 256 of them).
template <class Term>
double root_sum_of_squares(int n, const Term& term) {
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    int i = 0;
    for (; i + 4 <= n; i += 4) {
        const double t0 = term(i), t1 = term(i + 1), t2 = term(i + 2), t3 = term(i + 3);
        s0 += t0 * t0;
        s1 += t1 * t1;
        s2 += t2 * t2;
        s3 += t3 * t3;
    }
    for (; i < n; ++i) {
        const double t = term(i);
        s0 += t * t;
    }
    return std::sqrt((s0 + s1) + (s2 + s3));
}

double distance(const float* a, const float* b, int n) {
    return root_sum_of_squares(n, [&](int i) { return double(a[i]) - double(b[i]); });
}

// ‖ĉ_hi − ĉ_lo‖ of a local row, each estimate corrected by its prefix's control: ĉ = s·sum − β·δ,
// β = s·sum₀/open₀. lo_sum is the sum over the prefix lo, lo_sum + add over hi = 2·lo.
double controlled_distance(const OpenControl& lo, const OpenControl& hi, double lo_scale,
                           double hi_scale, const float* lo_sum, const float* add, int n,
                           double* hi_beta) {
    const double beta_lo = lo_scale * double(lo_sum[0]) / lo.open0;
    const double beta_hi = hi_scale * (double(lo_sum[0]) + double(add[0])) / hi.open0;
    *hi_beta = beta_hi;
    return root_sum_of_squares(n, [&](int i) {
        const double h = hi_scale * (double(lo_sum[i]) + double(add[i])) - beta_hi * hi.delta[i];
        const double l = lo_scale * double(lo_sum[i]) - beta_lo * lo.delta[i];
        return h - l;
    });
}
}  // namespace

std::vector<OpenControl> make_open_controls(const DirectionTable& table, const float* Y, int KL,
                                            std::size_t first_samples) {
    const std::size_t Smax = table.size();
    std::vector<OpenControl> controls;
    for (std::size_t b = std::max<std::size_t>(first_samples / 2, 1); b <= Smax; b *= 2)
        controls.push_back(
            make_open_control(table.weight.data(), Y, b, double(Smax) / double(b), KL, false));
    return controls;
}

ErrorBound make_error_bound(const BakeOptions& options, const DirectionTable& table, const float* Y,
                            int KL, bool shadowed) {
    ErrorBound bound;
    bound.table = &table;
    bound.Y = Y;
    bound.KL = KL;
    bound.first_samples = std::min<std::size_t>(kTargetFirstSamples, table.size());
    bound.max_samples = table.size();
    bound.target = options.target_error;
    bound.open_norm = open_transfer_norm(KL);
    bound.shadowed = shadowed;
    // A local set's W is the weight or 0 (weight_row copies it; trace_row zeroes what is
    // blocked), projected by sums from kSumsMinColumns columns; a sphere set's holds the cosine.
    const bool local = table.frame == DirectionFrame::local;
    const float weight = local ? common_weight(table) : 0.0f;
    bound.weight = KL >= kSumsMinColumns ? weight : 0.0f;
    if (bound.weight == 0.0f && !options.open_control) return bound;
    if (weight == 0.0f) {  // a local set of unequal weights (a caller's) has no sums
        if (local && options.open_control)
            bound.controls = make_open_controls(table, Y, KL, bound.first_samples);
        return bound;
    }
    // The column sums of Y over the segments [0, S0/2), [S0/2, S0), [S0, 2·S0), …, once: the
    // sums' T, and added up, the controls of the prefixes S0/2, S0, 2·S0, … (make_open_controls
    // for equal weights, without a pass over Y per prefix).
    const std::size_t S0 = bound.first_samples, Smax = bound.max_samples;
    const std::size_t K = std::size_t(KL);
    std::vector<double> prefix(K, 0.0);
    const std::vector<double> open = options.open_control
                                         ? open_hemisphere_transfer(KL, HemisphereDensity::cosine)
                                         : std::vector<double>{};
    auto segment = [&](std::size_t a, std::size_t b) {
        const std::vector<double> sum = column_sums(Y + a * K, b - a, KL);
        if (bound.weight != 0.0f) bound.sums.emplace_back(sum.begin(), sum.end());
        if (!options.open_control) return;
        for (std::size_t k = 0; k < K; ++k) prefix[k] += sum[k];
        bound.controls.push_back(
            open_control_from_sums(prefix, double(weight) * double(Smax) / double(b), open));
    };
    segment(0, S0 / 2);
    segment(S0 / 2, S0);
    for (std::size_t a = S0; a < Smax; a *= 2) segment(a, 2 * a);
    return bound;
}

void ErrorBound::project(const float* W, std::size_t m, std::size_t stride, std::size_t a,
                         std::size_t b, float* G) const {
    const float* Ya = Y + a * std::size_t(KL);
    if (weight == 0.0f) return project_rows(W, m, stride, b - a, Ya, KL, G);
    const std::size_t S0 = first_samples;
    const std::size_t segment = a == 0 ? 0 : a < S0 ? 1 : 2 + std::size_t(std::countr_zero(a / S0));
    project_visibility_rows(W, m, stride, b - a, Ya, KL, sums[segment].data(), weight, G);
}

BoundRows ErrorBoundScratch::fresh_rows(std::size_t height, int KL) {
    acc.assign(height * std::size_t(KL), 0.0f);
    samples.assign(height, 0);
    error.assign(height, 0.0f);
    visible.assign(height, 0);
    blocked.assign(height, 0);
    more.assign(height, 0);
    return {acc.data(), samples.data(), error.data(), visible.data(), blocked.data(), more.data()};
}

namespace {

// What every row's estimate needs of the bound, once per call.
struct RowEstimator {
    const ErrorBound& bound;
    std::size_t KL, S0, Smax;
    double resolution;      // one visible ray's worth at b = 1 (÷ b at b samples)
    double low_resolution;  // … over the first two bands alone (the edge guard)
    bool controlled;        // a local set with the open part exact

    explicit RowEstimator(const ErrorBound& b)
        : bound(b), KL(std::size_t(b.KL)), S0(b.first_samples), Smax(b.max_samples) {
        // One visible sample of weight w at S samples adds w·(Smax/S)·y(ω) to ĉ_S, whose norm
        // over full bands is w·(Smax/S)·√(KL/4π) (the addition theorem: Σ_i y_i(ω)² = KL/4π); the
        // edge guard takes it over the first two bands alone, so that it does not grow with K.
        const double w = *std::max_element(b.table->weight.begin(), b.table->weight.end());
        constexpr double k4Pi = 4.0 * 3.14159265358979323846;
        resolution = w * double(Smax) * std::sqrt(double(KL) / k4Pi) / b.open_norm;
        low_resolution =
            w * double(Smax) * std::sqrt(std::min(double(KL), 4.0) / k4Pi) / b.open_norm;
        controlled = !b.controls.empty();
    }

    // Row j after the segment [a, b): G its sum over the segment (pass 0, a = 0: the second
    // half's, and G0 the first half's), its rays' outcomes already added to rows.visible and
    // rows.blocked. Adds G to the row's sum, estimates its error with the three guards and says
    // whether it asks for more. Returns whether it goes on below `cap`.
    bool update(std::size_t a, std::size_t b, std::size_t cap, const float* G, const float* G0,
                BoundRows rows, std::size_t j) const {
        float* A = rows.acc + j * KL;
        const float* old = a == 0 ? G0 : A;
        double err = 0;
        bool open = false;  // a local row whose every ray so far was visible
        if (controlled) {
            const std::size_t level = a == 0 ? 0 : std::size_t(std::countr_zero(b / S0));
            double beta = 0;
            err = controlled_distance(bound.controls[level], bound.controls[level + 1],
                                      double(Smax) / double(b / 2), double(Smax) / double(b), old,
                                      G, bound.KL, &beta) /
                  bound.open_norm;
            open = beta > 1.0 - 0.5 / double(b);
        } else {
            // ĉ_b − ĉ_{b/2} = (Smax/b)·(new half's sum − old half's sum).
            err = double(Smax) / double(b) / bound.open_norm * distance(G, old, bound.KL);
        }
        if (a == 0) std::copy(old, old + KL, A);
        for (std::size_t c = 0; c < KL; ++c) A[c] += G[c];
        // Rare outcomes (error_bound.hpp, kRareRays): fewer than kRareRays rays saw the sky
        // (none: closed) — or, with the open part exact, hit something (none: open). An opening
        // or a blocker smaller than a ray's share that both halves met (or missed) alike makes
        // them agree; the error is taken as at least kRareFloor + √n rays' worth at b samples,
        // the count's own uncertainty.
        const std::uint32_t fewest =
            controlled ? std::min(rows.visible[j], rows.blocked[j]) : rows.visible[j];
        if (bound.shadowed && fewest < kRareRays)
            err = std::max(err, (kRareFloor + std::sqrt(double(fewest))) * resolution / double(b));
        if (!bound.shadowed && open) err = std::max(err, resolution / double(b));
        // A visibility edge (error_bound.hpp, kEdgeFloor): the spread of the visible fraction,
        // √(v·h)/b, at the rate a scrambled net keeps at an edge, b^(−3/4).
        if (bound.shadowed) {
            const double v = rows.visible[j], h = rows.blocked[j];
            err = std::max(err, kEdgeFloor * std::sqrt(v * h) / double(b) *
                                    std::pow(double(b), -0.75) * low_resolution);
        }
        // Two successive estimates: a row stops at b when its estimate is under the target and
        // the last one (at b/2) was under kPreviousFactor times it; pass 0 has none, so every
        // row takes at least 2·S0.
        const double previous =
            a == 0 ? std::numeric_limits<double>::infinity() : double(rows.error[j]);
        const bool over = err > bound.target || previous > kPreviousFactor * bound.target;
        rows.samples[j] = std::uint32_t(b);
        rows.error[j] = float(err);
        rows.more[j] = over ? 1 : 0;
        return over && b < cap;
    }

    // ĉ_S = (Smax/S)·A_S: a power of two, so exactly the fixed-S bake's weights (π/S, 4π/S);
    // then a local set's open part exactly.
    void finish(BoundRows rows, std::size_t height, float* out) const {
        for (std::size_t j = 0; j < height; ++j) {
            const float f = float(Smax / std::max<std::size_t>(rows.samples[j], 1));
            const float* A = rows.acc + j * KL;
            float* o = out + j * KL;
            for (std::size_t c = 0; c < KL; ++c) o[c] = A[c] * f;
            if (controlled && rows.samples[j] > 0)
                apply_open_control(
                    bound.controls[std::size_t(std::countr_zero(rows.samples[j] / S0)) + 1], o, 1);
        }
    }
};

// The rows that go on from where `rows` stand: fresh (every row at prefix 0: all of them, and
// 0 is returned), or baked before to a smaller cap — the rows still over the target then all
// stand at that cap (returned) and go on from there.
// A row whose twin (`twin`, or none when empty) is another row is left out: copy_twins gives it
// the twin's state when the chunk is done.
std::size_t active_rows(BoundRows rows, std::size_t height, std::size_t Smax,
                        const std::vector<std::uint32_t>& twin,
                        std::vector<std::uint32_t>& active) {
    std::size_t start = 0;
    active.clear();
    for (std::size_t j = 0; j < height; ++j) start = std::max<std::size_t>(start, rows.samples[j]);
    for (std::size_t j = 0; j < height; ++j) {
        if (!twin.empty() && twin[j] != j) continue;
        if (start == 0 || (rows.samples[j] == start && rows.more[j] != 0 && start < Smax))
            active.push_back(std::uint32_t(j));
    }
    return start;
}

// Each twin row takes its twin's sums, prefix, estimate and outcomes: the same rays, so the same
// state, without casting them again.
void copy_twins(const std::vector<std::uint32_t>& twin, std::size_t KL, BoundRows rows) {
    for (std::size_t j = 0; j < twin.size(); ++j) {
        const std::size_t t = twin[j];
        if (t == j) continue;
        std::copy(rows.acc + t * KL, rows.acc + (t + 1) * KL, rows.acc + j * KL);
        rows.samples[j] = rows.samples[t], rows.error[j] = rows.error[t];
        rows.visible[j] = rows.visible[t], rows.blocked[j] = rows.blocked[t];
        rows.more[j] = rows.more[t];
    }
}

}  // namespace

std::uint64_t bake_chunk_to_error(const ErrorBound& bound, std::size_t cap, const Tracer* tracer,
                                  const Receivers& rx, std::size_t first, std::size_t height,
                                  BoundRows rows, ErrorBoundScratch& sc, BakeProgress& progress,
                                  SharedVisibility* shared) {
    const RowEstimator estimator(bound);
    const std::size_t KL = estimator.KL, S0 = estimator.S0, Smax = estimator.Smax;
    cap = std::min(cap, Smax);
    find_twins(rx.positions + first, rx.normals + first, height, sc.twin);
    const std::size_t start = active_rows(rows, height, Smax, sc.twin, sc.active);
    std::uint64_t rays = 0;
    for (std::size_t a = start, b = start == 0 ? std::min(S0, cap) : 2 * start;
         a < cap && !sc.active.empty(); a = b, b = std::min(2 * b, cap)) {
        const std::size_t length = b - a;
        const std::size_t B = block_rows(length, height);
        if (sc.w.size() < B * length) sc.w.resize(B * length);
        if (sc.g.size() < B * KL) sc.g.resize(B * KL), sc.g0.resize(B * KL);
        std::size_t kept = 0;  // sc.active is compacted in place as rows finish
        for (std::size_t k = 0; k < sc.active.size(); k += B) {
            const std::size_t m = std::min(B, sc.active.size() - k);
            const double trace_start = thread_cpu_seconds();
            std::uint64_t block_rays = 0;
            for (std::size_t i = 0; i < m; ++i) {
                const std::size_t r = first + sc.active[k + i];
                float* row = sc.w.data() + i * length;
                weight_row(rx.normals[r], *bound.table, DirectionRange{a, b}, row);
                if (!bound.shadowed) continue;
                auto nonzero = [&] {  // a 32-bit count: four lanes to an SSE register
                    std::uint32_t n = 0;
                    for (std::size_t c = 0; c < length; ++c) n += row[c] != 0.0f ? 1u : 0u;
                    return n;
                };
                const std::uint32_t slot = shared ? shared->slot(r) : CrossTwins::kNoSlot;
                std::uint32_t rays_of_row = 0;  // the rays the row stands for
                if (slot != CrossTwins::kNoSlot) {
                    rays_of_row = nonzero();
                    block_rays += shared->mask(slot, *tracer, rx.positions[r], rx.normals[r],
                                               DirectionRange{a, b}, row, sc.trace);
                } else {
                    rays_of_row = trace_row(*tracer, rx.positions[r], rx.normals[r], *bound.table,
                                            DirectionRange{a, b}, row, sc.trace);
                    block_rays += rays_of_row;
                }
                const std::uint32_t seen = nonzero();
                rows.visible[sc.active[k + i]] += seen;
                rows.blocked[sc.active[k + i]] += rays_of_row - seen;
            }
            rays += block_rays;
            progress.add(0, block_rays);
            if (!progress.poll()) return rays;
            const double project_start = thread_cpu_seconds();
            if (a == 0) {  // the first prefix: its two halves
                const std::size_t half = length / 2;
                bound.project(sc.w.data(), m, length, 0, half, sc.g0.data());
                bound.project(sc.w.data() + half, m, length, half, length, sc.g.data());
            } else {
                bound.project(sc.w.data(), m, length, a, b, sc.g.data());
            }
            for (std::size_t i = 0; i < m; ++i) {
                const std::uint32_t j = sc.active[k + i];
                if (estimator.update(a, b, cap, sc.g.data() + i * KL, sc.g0.data() + i * KL, rows,
                                     j))
                    sc.active[kept++] = j;
            }
            sc.trace_seconds += project_start - trace_start;
            sc.project_seconds += thread_cpu_seconds() - project_start;
        }
        sc.active.resize(kept);
    }
    copy_twins(sc.twin, KL, rows);
    sc.out.resize(height * KL);
    estimator.finish(rows, height, sc.out.data());
    return rays;
}

std::uint64_t bake_segments_to_error(const ErrorBound& bound, std::size_t height,
                                     const SegmentBaker& segment, BoundRows rows,
                                     ErrorBoundScratch& sc, BakeProgress& progress) {
    SHPRT_CHECK(bound.table->frame == DirectionFrame::local || !bound.shadowed, unsupported,
                "a segment-baked error bound needs a local set (its rays' outcomes are read "
                "from each row's first coefficient)");
    const RowEstimator estimator(bound);
    const std::size_t KL = estimator.KL, S0 = estimator.S0, Smax = estimator.Smax;
    // Every direction of a local set has the same weight w and y₀₀ is constant, so a row's
    // first coefficient over a segment is w·y₀₀ times its visible rays (to rounding).
    const double per_ray = double(bound.table->weight.front()) * double(bound.Y[0]);
    const std::size_t start = active_rows(rows, height, Smax, {}, sc.active);
    std::uint64_t rays = 0;
    auto outcomes = [&](const float* G, std::size_t m, std::size_t length) {
        for (std::size_t i = 0; i < m; ++i) {
            const std::uint32_t j = sc.active[i];
            const auto seen = static_cast<std::uint32_t>(std::clamp<double>(
                std::nearbyint(double(G[i * KL]) / per_ray), 0.0, double(length)));
            rows.visible[j] += seen;
            rows.blocked[j] += std::uint32_t(length) - seen;
        }
    };
    for (std::size_t a = start, b = start == 0 ? S0 : 2 * start; a < Smax && !sc.active.empty();
         a = b, b = 2 * b) {
        const std::size_t m = sc.active.size(), length = b - a;
        sc.g.resize(m * KL);
        if (a == 0) {  // the first prefix: its two halves
            sc.g0.resize(m * KL);
            rays += segment(sc.active.data(), m, 0, length, sc.g.data(), sc.g0.data());
            if (bound.shadowed) {
                outcomes(sc.g0.data(), m, length / 2);
                outcomes(sc.g.data(), m, length - length / 2);
            }
        } else {
            rays += segment(sc.active.data(), m, a, b, sc.g.data(), nullptr);
            if (bound.shadowed) outcomes(sc.g.data(), m, length);
        }
        if (!progress.poll()) return rays;
        std::size_t kept = 0;
        for (std::size_t i = 0; i < m; ++i) {
            const std::uint32_t j = sc.active[i];
            if (estimator.update(a, b, Smax, sc.g.data() + i * KL, sc.g0.data() + i * KL, rows, j))
                sc.active[kept++] = j;
        }
        sc.active.resize(kept);
    }
    sc.out.resize(height * KL);
    estimator.finish(rows, height, sc.out.data());
    return rays;
}

}  // namespace shprt::detail

namespace shprt {

double open_transfer_norm(int coeffs) {
    double sum = 0;
    for (double z : clamped_cosine_zonal(sh_bands_for(coeffs))) sum += z * z;
    return std::sqrt(sum);
}

}  // namespace shprt
