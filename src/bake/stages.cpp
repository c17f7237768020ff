// The CPU bake's per-chunk stages (stages.hpp).
#include "bake/stages.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/direction_order.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <cblas.h>

#include <algorithm>
#include <limits>
#include <mutex>

namespace shprt::detail {

DirectionTable make_direction_table(const DirectionSet& directions, DirectionFrame frame) {
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
    t.trace_order = coherent_order(directions);
    t.trace_dirs.resize(S);
    for (std::size_t i = 0; i < S; ++i) t.trace_dirs[i] = t.dirs[t.trace_order[i]];
    return t;
}

}  // namespace shprt::detail

namespace shprt {

DirectionSet bake_direction_set(const BakeOptions& options) {
    if (options.direction_frame == DirectionFrame::sphere)
        return make_direction_set(options.sampler, options.seed, options.samples);
    // Glossy transfer integrates V·y_i·y_j over the hemisphere without a cosine: a cosine density
    // would weigh each sample by 1/cos θ' (infinite variance at the horizon), so its local set is
    // uniform on the hemisphere.
    const HemisphereDensity density = options.transfer == TransferKind::glossy
                                          ? HemisphereDensity::uniform
                                          : HemisphereDensity::cosine;
    return make_local_direction_set(options.sampler, options.seed, options.samples, density);
}

}  // namespace shprt

namespace shprt::detail {

int projected_coeffs(const BakeOptions& options) {
    if (options.direction_frame == DirectionFrame::sphere) return options.K;
    return sh_count(sh_bands_for(options.K));
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
    const std::size_t S = d.size();
    scratch.reserve(S);
    // Compaction of the above-horizon directions in the coherent trace order, branch-free: a
    // branch here mispredicts often (it cost more than 10% of the tracing time in the set's
    // random order).
    const std::uint32_t* order = d.trace_order.data();
    const Vec3f* dirs = d.trace_dirs.data();
    std::uint32_t m = 0;
    if (d.frame == DirectionFrame::local) {
        // Every direction is above the horizon: no compaction, the frame turns them.
        const LocalFrame f = local_frame(n);
        for (std::size_t i = 0; i < S; ++i) {
            scratch.ray_index[i] = order[i];
            scratch.ray_dirs[i] = to_world(f, dirs[i]);
        }
        m = static_cast<std::uint32_t>(S);
    } else {
        for (std::size_t i = 0; i < S; ++i) {
            const std::uint32_t s = order[i];
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

void project_rows(const float* W, std::size_t count, std::size_t S, const float* Y, int K,
                  float* C) {
    project_rows(W, count, S, S, Y, K, C);
}

void project_rows(const float* W, std::size_t count, std::size_t S, std::size_t depth,
                  const float* Y, int K, float* C) {
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(count), K,
                static_cast<int>(depth), 1.0f, W, static_cast<int>(S), Y, K, 0.0f, C, K);
}

void rotate_rows_to_world(const Vec3f* normals, std::size_t count, int KL, int K, bool matrix,
                          const float* local, float* world) {
    const std::size_t local_columns =
        matrix ? std::size_t(KL) * std::size_t(KL + 1) / 2 : std::size_t(KL);
    const std::size_t world_columns =
        matrix ? std::size_t(K) * std::size_t(K + 1) / 2 : std::size_t(K);
    std::vector<double> in(KL), out(KL);
    std::vector<double> a, m;  // matrices: D·M' (column i = D·column i of M'), then D·M'·Dᵀ
    if (matrix) {
        a.resize(std::size_t(KL) * KL);
        m.resize(std::size_t(KL) * KL);
    }
    for (std::size_t j = 0; j < count; ++j) {
        const LocalFrame f = local_frame(normals[j]);
        const float* src = local + j * local_columns;
        float* dst = world + j * world_columns;
        if (!matrix) {
            for (int i = 0; i < KL; ++i) in[i] = src[i];
            rotate_zyz_paper(0.0, f.beta, f.gamma, in.data(), out.data(), KL);
            for (int i = 0; i < K; ++i) dst[i] = static_cast<float>(out[i]);
            continue;
        }
        // M' from its packed upper triangle; M' is symmetric, so its row i is its column i.
        std::size_t p = 0;
        for (int i = 0; i < KL; ++i)
            for (int k = i; k < KL; ++k, ++p)
                m[std::size_t(i) * KL + k] = m[std::size_t(k) * KL + i] = src[p];
        // a[r][i] = (D·M')[r][i]: rotate each column of M'.
        for (int i = 0; i < KL; ++i) {
            for (int r = 0; r < KL; ++r) in[r] = m[std::size_t(i) * KL + r];
            rotate_zyz_paper(0.0, f.beta, f.gamma, in.data(), out.data(), KL);
            for (int r = 0; r < KL; ++r) a[std::size_t(r) * KL + i] = out[r];
        }
        // (D·M'·Dᵀ)ᵀ = D·(D·M')ᵀ: column r of it is D·(row r of a), and it is symmetric.
        for (int r = 0; r < KL; ++r) {
            rotate_zyz_paper(0.0, f.beta, f.gamma, a.data() + std::size_t(r) * KL, out.data(), KL);
            for (int i = 0; i < KL; ++i) m[std::size_t(r) * KL + i] = out[i];
        }
        // Packed upper triangle of the leading K×K block; m[r][i] = M[i][r], symmetrised.
        p = 0;
        for (int i = 0; i < K; ++i)
            for (int k = i; k < K; ++k, ++p)
                dst[p] = static_cast<float>(
                    0.5 * (m[std::size_t(i) * KL + k] + m[std::size_t(k) * KL + i]));
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
