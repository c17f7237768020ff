// The CPU bake's per-chunk stages (stages.hpp).
#include "bake/stages.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/host.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/direction_order.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <cblas.h>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <numeric>

namespace shprt::detail {

DirectionTable make_direction_table(const DirectionSet& directions, DirectionFrame frame,
                                    std::size_t first_prefix) {
    const std::size_t S = directions.size();
    DirectionTable t;
    t.frame = frame;
    t.x.resize(S);
    t.y.resize(S);
    t.z.resize(S);
    t.weight.resize(S);
    t.dirs.resize(S);
    for (std::size_t s = 0; s < S; ++s) {
        t.x[s] = directions.dirs[3 * s];
        t.y[s] = directions.dirs[3 * s + 1];
        t.z[s] = directions.dirs[3 * s + 2];
        t.weight[s] = directions.weights[s];
        t.dirs[s] = Vec3f{t.x[s], t.y[s], t.z[s]};
    }
    t.trace_order =
        first_prefix > 0 ? coherent_order(directions, first_prefix) : coherent_order(directions);
    t.trace_dirs.resize(S);
    for (std::size_t i = 0; i < S; ++i) t.trace_dirs[i] = t.dirs[t.trace_order[i]];
    return t;
}

}  // namespace shprt::detail

namespace shprt {

DirectionSet bake_direction_set(const BakeOptions& options) {
    if (options.direction_frame == DirectionFrame::sphere)
        return make_direction_set(options.sampler, options.seed, options.samples);
    // A kind without the cosine (glossy: V·y_i·y_j over the hemisphere): a cosine density
    // would weigh each sample by 1/cos θ' (infinite variance at the horizon), so its local set is
    // uniform on the hemisphere.
    const HemisphereDensity density =
        kind_row(options.transfer).cosine ? HemisphereDensity::cosine : HemisphereDensity::uniform;
    return make_local_direction_set(options.sampler, options.seed, options.samples, density);
}

}  // namespace shprt

namespace shprt::detail {

int projected_coeffs(const BakeOptions& options) {
    if (options.direction_frame == DirectionFrame::sphere || options.K < 1) return options.K;
    return sh_count(sh_bands_for(options.K));
}

void TraceScratch::reserve(std::size_t samples) {
    if (ray_dirs.size() >= samples) return;
    ray_dirs.resize(samples);
    ray_index.resize(samples);
    occluded.resize(samples);
}

void weight_row(Vec3f n, const DirectionTable& d, float* row, bool hemisphere) {
    weight_row(n, d, DirectionRange{0, d.size()}, row, hemisphere);
}

void weight_row(Vec3f n, const DirectionTable& d, DirectionRange range, float* row,
                bool hemisphere) {
    const std::size_t S = range.end - range.begin;
    const float* dx = d.x.data() + range.begin;
    const float* dy = d.y.data() + range.begin;
    const float* dz = d.z.data() + range.begin;
    const float* weight = d.weight.data() + range.begin;
    if (d.frame == DirectionFrame::local) {
        std::copy(weight, weight + S, row);
        return;
    }
    // Written with max and a select, not branches, so that the loops compile to SIMD.
    if (hemisphere) {
        for (std::size_t s = 0; s < S; ++s)
            row[s] = n.x * dx[s] + n.y * dy[s] + n.z * dz[s] > 0.0f ? weight[s] : 0.0f;
        return;
    }
    for (std::size_t s = 0; s < S; ++s) {
        const float cosine = n.x * dx[s] + n.y * dy[s] + n.z * dz[s];
        row[s] = std::max(cosine, 0.0f) * weight[s];
    }
}

std::vector<float> pair_product_table(const std::vector<float>& Y, std::size_t S, int K) {
    const std::size_t F = std::size_t(K) * std::size_t(K + 1) / 2;
    std::vector<float> P(S * F);
    for (std::size_t s = 0; s < S; ++s) {
        const float* y = Y.data() + s * std::size_t(K);
        float* p = P.data() + s * F;
        for (int i = 0; i < K; ++i)
            for (int j = i; j < K; ++j) *p++ = y[i] * y[j];
    }
    return P;
}

std::uint32_t trace_row(const Tracer& tracer, Vec3f p, Vec3f n, const DirectionTable& d, float* row,
                        TraceScratch& scratch) {
    return trace_row(tracer, p, n, d, DirectionRange{0, d.size()}, row, scratch);
}

std::uint32_t trace_row(const Tracer& tracer, Vec3f p, Vec3f n, const DirectionTable& d,
                        DirectionRange range, float* row, TraceScratch& scratch) {
    const std::size_t S = range.end - range.begin;
    scratch.reserve(S);
    // Compaction of the above-horizon directions in the coherent trace order, branch-free: a
    // branch here mispredicts often (it cost more than 10% of the tracing time in the set's
    // random order). The range's positions of the order hold its indices (make_direction_table),
    // which index `row` from range.begin.
    const std::uint32_t* order = d.trace_order.data() + range.begin;
    const Vec3f* dirs = d.trace_dirs.data() + range.begin;
    const std::uint32_t base = static_cast<std::uint32_t>(range.begin);
    std::uint32_t m = 0;
    if (d.frame == DirectionFrame::local) {
        // Every direction is above the horizon: no compaction, the frame turns them.
        const LocalFrame f = local_frame(n);
        for (std::size_t i = 0; i < S; ++i) {
            scratch.ray_index[i] = order[i] - base;
            scratch.ray_dirs[i] = to_world(f, dirs[i]);
        }
        m = static_cast<std::uint32_t>(S);
    } else {
        for (std::size_t i = 0; i < S; ++i) {
            const std::uint32_t s = order[i] - base;
            scratch.ray_index[m] = s;
            scratch.ray_dirs[m] = dirs[i];
            m += row[s] != 0.0f ? 1u : 0u;
        }
    }
    if (m == 0) return 0;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    tracer.occluded(offset_ray_origin(p, n), scratch.ray_dirs.data(), static_cast<int>(m), 0.0f,
                    kInf, scratch.occluded.data());
    constexpr float kKeep[2] = {1.0f, 0.0f};  // visible, occluded; branch-free
    for (std::uint32_t r = 0; r < m; ++r)
        row[scratch.ray_index[r]] *= kKeep[scratch.occluded[r] & 1u];
    return m;
}

void find_twins(const Vec3f* positions, const Vec3f* normals, std::size_t count,
                std::vector<std::uint32_t>& twin) {
    // Sorted by a hash of the position's and the normal's bits, then by index; within a run of
    // equal hashes each receiver is compared bit for bit with the run's firsts before it.
    auto same = [&](std::uint32_t a, std::uint32_t b) {
        return std::memcmp(&positions[a], &positions[b], sizeof(Vec3f)) == 0 &&
               std::memcmp(&normals[a], &normals[b], sizeof(Vec3f)) == 0;
    };
    struct Entry {
        std::uint64_t hash;
        std::uint32_t index;
    };
    std::vector<Entry> e(count);
    for (std::size_t j = 0; j < count; ++j)
        e[j] = {fnv1a64(&normals[j], sizeof(Vec3f), fnv1a64(&positions[j], sizeof(Vec3f))),
                static_cast<std::uint32_t>(j)};
    std::sort(e.begin(), e.end(), [](const Entry& a, const Entry& b) {
        return a.hash != b.hash ? a.hash < b.hash : a.index < b.index;
    });
    twin.resize(count);
    std::iota(twin.begin(), twin.end(), std::uint32_t(0));
    for (std::size_t run = 0, end = 0; run < count; run = end) {
        for (end = run + 1; end < count && e[end].hash == e[run].hash;) ++end;
        for (std::size_t i = run + 1; i < end; ++i)
            for (std::size_t k = run; k < i; ++k)
                if (twin[e[k].index] == e[k].index && same(e[k].index, e[i].index)) {
                    twin[e[i].index] = e[k].index;
                    break;
                }
    }
}

CrossTwins find_cross_twins(const Vec3f* positions, const Vec3f* normals, std::size_t count,
                            std::size_t lead, std::size_t chunk, std::size_t max_reps) {
    CrossTwins t;
    std::vector<std::uint32_t> first;  // per receiver: the first with its position and normal
    find_twins(positions, normals, count, first);
    std::vector<std::uint8_t> shared(count, 0);  // a first that another chunk shares
    for (std::size_t j = 0; j < count; ++j)
        if ((lead + first[j]) / chunk != (lead + j) / chunk) shared[first[j]] = 1;
    t.slot.assign(count, CrossTwins::kNoSlot);
    for (std::size_t j = 0; j < count && t.reps.size() < max_reps; ++j)
        if (shared[j]) {
            t.slot[j] = static_cast<std::uint32_t>(t.reps.size());
            t.reps.push_back(static_cast<std::uint32_t>(j));
        }
    for (std::size_t j = 0; j < count; ++j) t.slot[j] = t.slot[first[j]];
    return t;
}

SharedVisibility::SharedVisibility(const Vec3f* positions, const Vec3f* normals, std::size_t origin,
                                   std::size_t count, std::size_t chunk,
                                   const DirectionTable& table, std::size_t first_segment)
    : origin_(origin),
      words_((table.size() + 63) / 64),
      first_segment_(first_segment),
      table_(&table) {
    // Segments are whole words of bits (S0 a multiple of 64, or the whole table), so no two
    // threads ever write one word: each segment is written once, under its slot's lock.
    assert(first_segment % 64 == 0 || first_segment >= table.size());
    twins_ = find_cross_twins(positions + origin, normals + origin, count, 0, chunk,
                              kCrossTwinBytes / (words_ * sizeof(std::uint64_t)));
    bits_.assign(twins_.reps.size() * words_, 0);
    segments_.assign(twins_.reps.size(), 0);
    locks_ = std::make_unique<std::mutex[]>(twins_.reps.size());
}

std::uint32_t SharedVisibility::slot(std::size_t r) const {
    return r >= origin_ && r - origin_ < twins_.slot.size() ? twins_.slot[r - origin_]
                                                            : CrossTwins::kNoSlot;
}

std::uint32_t SharedVisibility::mask(std::uint32_t slot, const Tracer& tracer, Vec3f p, Vec3f n,
                                     DirectionRange range, float* row, TraceScratch& scratch) {
    // The table's segments: [0, S0), [S0, 2·S0), [2·S0, 4·S0), …
    const unsigned segment =
        range.begin == 0 ? 0u : 1u + unsigned(std::countr_zero(range.begin / first_segment_));
    const std::size_t length = range.end - range.begin;
    std::uint64_t* bits = bits_.data() + std::size_t(slot) * words_;
    std::uint32_t cast = 0;
    {
        const std::lock_guard<std::mutex> lock(locks_[slot]);
        if ((segments_[slot] >> segment & 1u) == 0) {
            thread_local std::vector<float> traced;
            traced.assign(row, row + length);
            cast = trace_row(tracer, p, n, *table_, range, traced.data(), scratch);
            for (std::size_t i = 0; i < length; ++i) {
                const std::size_t s = range.begin + i;
                bits[s >> 6] |= std::uint64_t(traced[i] != 0.0f) << (s & 63);
            }
            segments_[slot] |= 1u << segment;
        }
    }
    for (std::size_t i = 0; i < length; ++i) {
        const std::size_t s = range.begin + i;
        if ((bits[s >> 6] >> (s & 63) & 1u) == 0) row[i] = 0.0f;
    }
    return cast;
}

std::vector<std::uint8_t> traced_receivers(const Vec3f* positions, const Vec3f* normals,
                                           std::size_t count, std::size_t chunk, std::size_t S) {
    const std::size_t words = (S + 63) / 64;
    const CrossTwins cross = find_cross_twins(positions, normals, count, 0, chunk,
                                              kCrossTwinBytes / (words * sizeof(std::uint64_t)));
    std::vector<std::uint8_t> traced(count, 0);
    std::vector<std::uint32_t> twin;
    for (std::size_t first = 0; first < count; first += chunk) {
        const std::size_t height = std::min(chunk, count - first);
        find_twins(positions + first, normals + first, height, twin);
        for (std::size_t j = 0; j < height; ++j) {
            const std::size_t r = first + j;
            const std::uint32_t slot = cross.slot[r];
            traced[r] = twin[j] == j && (slot == CrossTwins::kNoSlot || cross.reps[slot] == r);
        }
    }
    return traced;
}

void project_rows(const float* W, std::size_t count, std::size_t S, const float* Y, int K,
                  float* C) {
    project_rows(W, count, S, S, Y, K, C);
}

void project_rows(const float* W, std::size_t count, std::size_t S, std::size_t depth,
                  const float* Y, int K, float* C) {
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(count), K,
                static_cast<int>(depth), 1.0f, W, static_cast<int>(S), Y, K, 0.0f, C, K);
}

namespace {

void sum_rows_portable(const float* Y, int stride, const std::uint32_t* rows, std::size_t n,
                       float* out, int K) {
    std::fill_n(out, K, 0.0f);
    for (std::size_t q = 0; q < n; ++q) {
        const float* y = Y + std::size_t(rows[q]) * std::size_t(stride);
        for (int k = 0; k < K; ++k) out[k] += y[k];
    }
}

#if defined(__x86_64__)
// The rows are scattered over the table: each kernel fetches the one kPrefetch ahead while it
// adds this one.
constexpr std::size_t kPrefetch = 8;

// Columns [0, K) of rows `stride` floats apart: 64 at a time in eight registers of sums, then 8,
// then one.
__attribute__((target("avx2"))) void sum_rows_avx2(const float* Y, int stride,
                                                   const std::uint32_t* rows, std::size_t n,
                                                   float* out, int K) {
    const std::size_t step = std::size_t(stride);
    int k = 0;
    for (; k + 64 <= K; k += 64) {
        __m256 a[8];
        for (auto& v : a) v = _mm256_setzero_ps();
        for (std::size_t q = 0; q < n; ++q) {
            if (q + kPrefetch < n) {
                const auto* next = reinterpret_cast<const char*>(
                    Y + std::size_t(rows[q + kPrefetch]) * step + std::size_t(k));
                for (int line = 0; line < 4; ++line) _mm_prefetch(next + 64 * line, _MM_HINT_T0);
            }
            const float* y = Y + std::size_t(rows[q]) * step + std::size_t(k);
            for (int i = 0; i < 8; ++i) a[i] = _mm256_add_ps(a[i], _mm256_loadu_ps(y + 8 * i));
        }
        for (int i = 0; i < 8; ++i) _mm256_storeu_ps(out + k + 8 * i, a[i]);
    }
    for (; k + 8 <= K; k += 8) {
        __m256 a = _mm256_setzero_ps();
        for (std::size_t q = 0; q < n; ++q)
            a = _mm256_add_ps(a, _mm256_loadu_ps(Y + std::size_t(rows[q]) * step + std::size_t(k)));
        _mm256_storeu_ps(out + k, a);
    }
    if (k < K) sum_rows_portable(Y + k, stride, rows, n, out + k, K - k);
}

// 256 columns at a time in sixteen registers (a whole row of the room's K = 256, read once),
// the rest with AVX2.
__attribute__((target("avx512f"))) void sum_rows_avx512(const float* Y, int stride,
                                                        const std::uint32_t* rows, std::size_t n,
                                                        float* out, int K) {
    const std::size_t step = std::size_t(stride);
    int k = 0;
    for (; k + 256 <= K; k += 256) {
        __m512 a[16];
        for (auto& v : a) v = _mm512_setzero_ps();
        for (std::size_t q = 0; q < n; ++q) {
            if (q + kPrefetch < n) {
                const auto* next = reinterpret_cast<const char*>(
                    Y + std::size_t(rows[q + kPrefetch]) * step + std::size_t(k));
                for (int line = 0; line < 16; ++line) _mm_prefetch(next + 64 * line, _MM_HINT_T0);
            }
            const float* y = Y + std::size_t(rows[q]) * step + std::size_t(k);
            for (int i = 0; i < 16; ++i) a[i] = _mm512_add_ps(a[i], _mm512_loadu_ps(y + 16 * i));
        }
        for (int i = 0; i < 16; ++i) _mm512_storeu_ps(out + k + 16 * i, a[i]);
    }
    if (k < K) sum_rows_avx2(Y + k, stride, rows, n, out + k, K - k);
}
#endif

}  // namespace

void sum_rows(const float* Y, int K, const std::uint32_t* rows, std::size_t n, float* out,
              SumKernel kernel) {
#if defined(__x86_64__)
    if (kernel == SumKernel::automatic)
        kernel = cpu_has_avx512f() ? SumKernel::avx512
                 : cpu_has_avx2()  ? SumKernel::avx2
                                   : SumKernel::portable;
    SHPRT_CHECK(kernel != SumKernel::avx512 || cpu_has_avx512f(), unsupported,
                "this CPU has no AVX-512F");
    SHPRT_CHECK(kernel != SumKernel::avx2 || cpu_has_avx2(), unsupported, "this CPU has no AVX2");
    if (kernel == SumKernel::avx512) return sum_rows_avx512(Y, K, rows, n, out, K);
    if (kernel == SumKernel::avx2) return sum_rows_avx2(Y, K, rows, n, out, K);
#else
    SHPRT_CHECK(kernel == SumKernel::automatic || kernel == SumKernel::portable, unsupported,
                "SIMD sums are for x86-64");
#endif
    sum_rows_portable(Y, K, rows, n, out, K);
}

void project_visibility_rows(const float* W, std::size_t count, std::size_t S, std::size_t depth,
                             const float* Y, int K, const float* T, float w, float* C) {
    thread_local std::vector<std::uint64_t> mask;  // bit s: direction s visible
    thread_local std::vector<std::uint32_t> list;
    const std::size_t words = (depth + 63) / 64;
    if (mask.size() < words) mask.resize(words);
    if (list.size() < depth) list.resize(depth);
    for (std::size_t r = 0; r < count; ++r) {
        const float* row = W + r * S;
        std::size_t v = 0;
        for (std::size_t i = 0; i < words; ++i) {
            std::uint64_t m = 0;
            const std::size_t first = 64 * i, n = std::min<std::size_t>(64, depth - first);
            std::size_t s = 0;
#if defined(__SSE2__)
            for (; s + 4 <= n; s += 4) {
                const __m128 x = _mm_loadu_ps(row + first + s);
                m |= std::uint64_t(_mm_movemask_ps(_mm_cmpneq_ps(x, _mm_setzero_ps()))) << s;
            }
#endif
            for (; s < n; ++s) m |= std::uint64_t(row[first + s] != 0.0f) << s;
            mask[i] = m;
            v += std::size_t(std::popcount(m));
        }
        // The shorter list, in increasing order: the visible directions, or the blocked ones.
        const bool blocked = v > depth - v;
        std::size_t n = 0;
        for (std::size_t i = 0; i < words; ++i) {
            std::uint64_t m = blocked ? ~mask[i] : mask[i];
            if (64 * (i + 1) > depth) m &= (std::uint64_t(1) << (depth - 64 * i)) - 1;
            for (; m != 0; m &= m - 1)
                list[n++] = std::uint32_t(64 * i + std::size_t(std::countr_zero(m)));
        }
        float* c = C + r * std::size_t(K);
        sum_rows(Y, K, list.data(), n, c);
        if (blocked)
            for (int k = 0; k < K; ++k) c[k] = w * (T[k] - c[k]);
        else
            for (int k = 0; k < K; ++k) c[k] = w * c[k];
    }
}

std::vector<double> column_sums(const float* Y, std::size_t depth, int K) {
    std::vector<double> sum(std::size_t(K), 0.0);
    for (std::size_t s = 0; s < depth; ++s)
        for (std::size_t k = 0; k < std::size_t(K); ++k)
            sum[k] += double(Y[s * std::size_t(K) + k]);
    return sum;
}

std::vector<float> segment_sums(const float* Y, std::size_t depth, int K) {
    const std::vector<double> sum = column_sums(Y, depth, K);
    return std::vector<float>(sum.begin(), sum.end());
}

float common_weight(const DirectionTable& table) {
    if (table.weight.empty()) return 0.0f;
    const float w = table.weight.front();
    for (float x : table.weight)
        if (x != w) return 0.0f;
    return w;
}

OpenControl make_open_control(const float* weights, const float* Y, std::size_t count, double scale,
                              int KL, bool matrix) {
    OpenControl c;
    c.delta = open_hemisphere_transfer(
        KL, matrix ? HemisphereDensity::uniform : HemisphereDensity::cosine);
    const std::size_t F = c.delta.size();
    c.open0 = c.delta[0];
    std::vector<double> q(F, 0.0);
    for (std::size_t s = 0; s < count; ++s) {
        const double w = double(weights[s]) * scale;
        const float* y = Y + s * F;
        for (std::size_t i = 0; i < F; ++i) q[i] += w * double(y[i]);
    }
    for (std::size_t i = 0; i < F; ++i) c.delta[i] = q[i] - c.delta[i];
    return c;
}

OpenControl open_control_from_sums(const std::vector<double>& sums, double weight_scale,
                                   const std::vector<double>& open) {
    SHPRT_CHECK(sums.size() == open.size(), invalid_argument,
                "open control: {} column sums for {} columns", sums.size(), open.size());
    OpenControl c;
    c.open0 = open[0];
    c.delta.resize(open.size());
    for (std::size_t i = 0; i < open.size(); ++i) c.delta[i] = weight_scale * sums[i] - open[i];
    return c;
}

void apply_open_control(const OpenControl& control, float* rows, std::size_t count) {
    const std::size_t F = control.delta.size();
    if (F == 0) return;  // no control (a sphere set, or open_control off)
    for (std::size_t j = 0; j < count; ++j) {
        float* row = rows + j * F;
        const double beta = double(row[0]) / control.open0;
        for (std::size_t i = 0; i < F; ++i)
            row[i] = static_cast<float>(double(row[i]) - beta * control.delta[i]);
    }
}

namespace {

// D(R) for a receiver's frame R = Rz(γ)·Ry(β), applied band by band as the paper's factorisation
// Z(γ)·Xᵀ·Z(β)·X (rotate_zyz_paper with α = 0, whose Z(α) is the identity): the X = D(Rx(π/2))
// blocks fetched once for all receivers, cos mθ and sin mθ by angle addition from one cosine and
// sine (no trigonometric call per band). Full bands only (`coeffs` = bands²).
class FrameRotation {
public:
    explicit FrameRotation(int coeffs) : m_bands(sh_bands_for(coeffs)), m_x(m_bands) {
        std::size_t size = 0;
        for (int l = 0; l < m_bands; ++l) size += std::size_t(2 * l + 1) * std::size_t(2 * l + 1);
        m_xt.resize(size);
        std::size_t offset = 0;
        for (int l = 0; l < m_bands; ++l) {
            const int n = 2 * l + 1;
            m_x[l] = rotation_x90_block(l);
            for (int r = 0; r < n; ++r)
                for (int c = 0; c < n; ++c)
                    m_xt[offset + std::size_t(c) * n + r] = m_x[l][r * n + c];
            offset += std::size_t(n) * n;
        }
    }
    void set(const LocalFrame& f) {
        multiples(std::cos(f.beta), std::sin(f.beta), m_cb, m_sb);
        multiples(std::cos(f.gamma), std::sin(f.gamma), m_cg, m_sg);
    }
#if defined(__x86_64__)
    // set() for eight receivers, receiver k in lane k of apply8.
    void set8(const Vec3f* normals) {
        for (int k = 0; k < 8; ++k) {
            set(local_frame(normals[k]));
            for (int m = 0; m < m_bands; ++m) {
                m_lanes[(4 * m + 0) * 8 + k] = m_cb[m], m_lanes[(4 * m + 1) * 8 + k] = m_sb[m];
                m_lanes[(4 * m + 2) * 8 + k] = m_cg[m], m_lanes[(4 * m + 3) * 8 + k] = m_sg[m];
            }
        }
    }
    // apply() for eight receivers at once, receiver k in lane k (in[i·8 + k], out[i·8 + k]): each
    // lane runs apply()'s products and sums in apply()'s order, without fused multiply-adds
    // (stages.cpp is built with -ffp-contract=off), so its bits are apply()'s.
    __attribute__((target("avx512f"))) void apply8(const double* in, double* out) const {
        __m512d v[2 * kMaxComputeBands + 1];
        const double* xt = m_xt.data();
        for (int l = 0; l < m_bands; ++l) {
            const int n = 2 * l + 1;
            const double* x = m_x[l];
            for (int r = 0; r < n; ++r) v[r] = dot8(x + std::size_t(r) * n, in + 8 * l * l, n);
            z_rotate8(0, l, v);
            __m512d w[2 * kMaxComputeBands + 1];
            for (int c = 0; c < n; ++c)
                w[c] = dot8(xt + std::size_t(c) * n, reinterpret_cast<const double*>(v), n);
            xt += std::size_t(n) * n;
            z_rotate8(2, l, w);
            for (int c = 0; c < n; ++c) _mm512_storeu_pd(out + 8 * (l * l + c), w[c]);
        }
    }
#endif
    // out = D·in over every band; in and out do not overlap.
    void apply(const double* in, double* out) const {
        double v[2 * kMaxComputeBands + 1];
        const double* xt = m_xt.data();
        for (int l = 0; l < m_bands; ++l) {
            const int n = 2 * l + 1;
            const double* x = m_x[l];
            const double* u = in + l * l;
            for (int r = 0; r < n; ++r) v[r] = dot(x + std::size_t(r) * n, u, n);  // v = X·u
            z_rotate(m_cb, m_sb, l, v);
            double* w = out + l * l;
            for (int c = 0; c < n; ++c) w[c] = dot(xt + std::size_t(c) * n, v, n);  // w = Xᵀ·v
            xt += std::size_t(n) * n;
            z_rotate(m_cg, m_sg, l, w);
        }
    }

private:
    // Σ a[i]·b[i] in four independent sums: one chain of dependent additions runs at the adder's
    // latency (measured 3x slower here; the loop is not vectorised at -O2).
    static double dot(const double* a, const double* b, int n) {
        double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
        int i = 0;
        for (; i + 4 <= n; i += 4) {
            s0 += a[i] * b[i];
            s1 += a[i + 1] * b[i + 1];
            s2 += a[i + 2] * b[i + 2];
            s3 += a[i + 3] * b[i + 3];
        }
        for (; i < n; ++i) s0 += a[i] * b[i];
        return (s0 + s1) + (s2 + s3);
    }
#if defined(__x86_64__)
    __attribute__((target("avx512f"))) static __m512d term8(const double* a, const double* b,
                                                            int i) {
        return _mm512_mul_pd(_mm512_set1_pd(a[i]), _mm512_loadu_pd(b + 8 * i));
    }
    // dot() in each lane: a[i] times lane values b[i·8 + k].
    __attribute__((target("avx512f"))) static __m512d dot8(const double* a, const double* b,
                                                           int n) {
        __m512d s0 = _mm512_setzero_pd(), s1 = s0, s2 = s0, s3 = s0;
        int i = 0;
        for (; i + 4 <= n; i += 4) {
            s0 = _mm512_add_pd(s0, term8(a, b, i));
            s1 = _mm512_add_pd(s1, term8(a, b, i + 1));
            s2 = _mm512_add_pd(s2, term8(a, b, i + 2));
            s3 = _mm512_add_pd(s3, term8(a, b, i + 3));
        }
        for (; i < n; ++i) s0 = _mm512_add_pd(s0, term8(a, b, i));
        return _mm512_add_pd(_mm512_add_pd(s0, s1), _mm512_add_pd(s2, s3));
    }
    // z_rotate() in each lane, with set8's angles (first = 0: β's, 2: γ's).
    __attribute__((target("avx512f"))) void z_rotate8(int first, int l, __m512d* v) const {
        for (int m = 1; m <= l; ++m) {
            const __m512d c = _mm512_loadu_pd(m_lanes.data() + (4 * m + first) * 8);
            const __m512d s = _mm512_loadu_pd(m_lanes.data() + (4 * m + first + 1) * 8);
            const __m512d p = v[l + m], q = v[l - m];
            v[l + m] = _mm512_sub_pd(_mm512_mul_pd(c, p), _mm512_mul_pd(s, q));
            v[l - m] = _mm512_add_pd(_mm512_mul_pd(s, p), _mm512_mul_pd(c, q));
        }
    }
#endif
    void multiples(double c1, double s1, double* c, double* s) const {
        c[0] = 1.0, s[0] = 0.0;
        for (int m = 1; m < m_bands; ++m) {
            c[m] = c[m - 1] * c1 - s[m - 1] * s1;
            s[m] = s[m - 1] * c1 + c[m - 1] * s1;
        }
    }
    // v ← Z·v for one band (rows m and −m mix; sh/rotation.hpp's rotate_z).
    static void z_rotate(const double* c, const double* s, int l, double* v) {
        for (int m = 1; m <= l; ++m) {
            const double p = v[l + m], q = v[l - m];
            v[l + m] = c[m] * p - s[m] * q;
            v[l - m] = s[m] * p + c[m] * q;
        }
    }

    int m_bands;
    std::vector<const double*> m_x;  // X = D(Rx(π/2)) per band (the library's cache)
    std::vector<double> m_xt;        // Xᵀ of every band, one after another
    double m_cb[kMaxComputeBands], m_sb[kMaxComputeBands], m_cg[kMaxComputeBands],
        m_sg[kMaxComputeBands];
    std::vector<double> m_lanes = std::vector<double>(4 * 8 * kMaxComputeBands);  // set8's
};

}  // namespace

void rotate_rows_to_world(const Vec3f* normals, std::size_t count, int KL, int K, bool matrix,
                          const float* local, float* world, RotationKernel kernel) {
    const std::size_t L = std::size_t(KL);
    const std::size_t local_columns = matrix ? L * (L + 1) / 2 : L;
    const std::size_t world_columns =
        matrix ? std::size_t(K) * std::size_t(K + 1) / 2 : std::size_t(K);
    FrameRotation rotation(KL);
    std::vector<double> in(L), out(L);
    std::vector<double> a, m;  // matrices: D·M' (column i = D·column i of M'), then D·M'·Dᵀ
    if (matrix) {
        a.resize(L * L);
        m.resize(L * L);
    }
    std::size_t j = 0;
#if defined(__x86_64__)
    if (kernel == RotationKernel::automatic)
        kernel = cpu_has_avx512f() ? RotationKernel::avx512 : RotationKernel::portable;
    SHPRT_CHECK(kernel != RotationKernel::avx512 || cpu_has_avx512f(), unsupported,
                "this CPU has no AVX-512F");
    if (kernel == RotationKernel::avx512 && !matrix) {
        // Eight receivers at a time, receiver k in lane k.
        std::vector<double> in8(8 * L), out8(8 * L);
        for (; j + 8 <= count; j += 8) {
            rotation.set8(normals + j);
            for (std::size_t k = 0; k < 8; ++k)
                for (std::size_t i = 0; i < L; ++i)
                    in8[i * 8 + k] = local[(j + k) * local_columns + i];
            rotation.apply8(in8.data(), out8.data());
            for (std::size_t k = 0; k < 8; ++k)
                for (int i = 0; i < K; ++i)
                    world[(j + k) * world_columns + std::size_t(i)] =
                        static_cast<float>(out8[std::size_t(i) * 8 + k]);
        }
    }
#else
    SHPRT_CHECK(kernel != RotationKernel::avx512, unsupported, "AVX-512 is for x86-64");
#endif
    for (; j < count; ++j) {
        rotation.set(local_frame(normals[j]));
        const float* src = local + j * local_columns;
        float* dst = world + j * world_columns;
        if (!matrix) {
            for (std::size_t i = 0; i < L; ++i) in[i] = src[i];
            rotation.apply(in.data(), out.data());
            for (int i = 0; i < K; ++i) dst[i] = static_cast<float>(out[i]);
            continue;
        }
        // M' from its packed upper triangle; M' is symmetric, so its row i is its column i.
        std::size_t p = 0;
        for (std::size_t i = 0; i < L; ++i)
            for (std::size_t k = i; k < L; ++k, ++p) m[i * L + k] = m[k * L + i] = src[p];
        // a[r][i] = (D·M')[r][i]: rotate each column of M'.
        for (std::size_t i = 0; i < L; ++i) {
            rotation.apply(m.data() + i * L, out.data());
            for (std::size_t r = 0; r < L; ++r) a[r * L + i] = out[r];
        }
        // (D·M'·Dᵀ)ᵀ = D·(D·M')ᵀ: column r of it is D·(row r of a), and it is symmetric.
        for (std::size_t r = 0; r < L; ++r) rotation.apply(a.data() + r * L, m.data() + r * L);
        // Packed upper triangle of the leading K×K block; m[r][i] = M[i][r], symmetrised.
        p = 0;
        for (std::size_t i = 0; i < std::size_t(K); ++i)
            for (std::size_t k = i; k < std::size_t(K); ++k, ++p)
                dst[p] = static_cast<float>(0.5 * (m[i * L + k] + m[k * L + i]));
    }
}

namespace {
// The scopes alive and the count the first one saved (stages.hpp: SingleThreadedBlas).
std::mutex g_blas_mutex;
int g_blas_scopes = 0;
int g_blas_saved_threads = 1;
}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
    const std::lock_guard lock(g_blas_mutex);
    if (g_blas_scopes++ == 0) {
        g_blas_saved_threads = openblas_get_num_threads();
        openblas_set_num_threads(1);
    }
}
SingleThreadedBlas::~SingleThreadedBlas() {
    const std::lock_guard lock(g_blas_mutex);
    if (--g_blas_scopes == 0) openblas_set_num_threads(g_blas_saved_threads);
}

}  // namespace shprt::detail
