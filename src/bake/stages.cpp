// The CPU bake's per-chunk stages (stages.hpp).
#include "bake/stages.hpp"

#include "shprt/sh/direction_order.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <cblas.h>

#include <algorithm>
#include <limits>
#include <mutex>

namespace shprt::detail {

DirectionTable make_direction_table(const DirectionSet& directions) {
    const std::size_t S = directions.size();
    DirectionTable t;
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
    t.trace_order = coherent_order(directions);
    t.trace_dirs.resize(S);
    for (std::size_t i = 0; i < S; ++i) t.trace_dirs[i] = t.dirs[t.trace_order[i]];
    return t;
}

void TraceScratch::reserve(std::size_t samples) {
    if (ray_dirs.size() >= samples) return;
    ray_dirs.resize(samples);
    ray_index.resize(samples);
    occluded.resize(samples);
}

void weight_row(Vec3f n, const DirectionTable& d, float* row, bool hemisphere) {
    const std::size_t S = d.size();
    const float* dx = d.x.data();
    const float* dy = d.y.data();
    const float* dz = d.z.data();
    const float* weight = d.weight.data();
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
    const std::size_t S = d.size();
    scratch.reserve(S);
    // Compaction of the above-horizon directions in the coherent trace order, branch-free: a
    // branch here mispredicts often (it cost more than 10% of the tracing time in the set's
    // random order).
    const std::uint32_t* order = d.trace_order.data();
    const Vec3f* dirs = d.trace_dirs.data();
    std::uint32_t m = 0;
    for (std::size_t i = 0; i < S; ++i) {
        const std::uint32_t s = order[i];
        scratch.ray_index[m] = s;
        scratch.ray_dirs[m] = dirs[i];
        m += row[s] != 0.0f ? 1u : 0u;
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
