// Clustered PCA of transfer rows (transfer/cpca.hpp).
//
// Implements P.-P. Sloan, J. Hall, J. Hart, J. Snyder, "Clustered Principal Components for
// Precomputed Radiance Transfer", SIGGRAPH 2003 (cluster, then PCA per cluster), seeded with
// k-means++ (D. Arthur, S. Vassilvitskii, "k-means++: The Advantages of Careful Seeding", SODA
// 2007).
#include "shprt/transfer/cpca.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/half.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace shprt {
namespace {

using MatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixD = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Rows per block of the assignment products: fixed, so the partition never depends on threads.
constexpr std::size_t kBlockRows = 256;

// The Frobenius metric's scale of each of a row's D floats: √2 for the off-diagonal entries of
// a packed symmetric matrix, 1 otherwise.
std::vector<float> metric_scale(const TransferLayout& layout) {
    const std::size_t D = layout.floats_per_receiver();
    std::vector<float> s(D, 1.0f);
    if (!is_glossy_matrix(layout)) return s;
    const int K = layout.K;
    std::size_t p = 0;
    for (int c = 0; c < layout.channels; ++c)
        for (int i = 0; i < K; ++i)
            for (int j = i; j < K; ++j, ++p) s[p] = i == j ? 1.0f : float(std::sqrt(2.0));
    return s;
}

double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

// 1. k-means++ seeding: C centres among the rows of X.
MatrixF seed_centres(const MatrixF& X, int C, std::uint64_t seed, Arena& arena) {
    const std::size_t N = std::size_t(X.rows());
    MatrixF centres(C, X.cols());
    std::vector<double> nearest(N, std::numeric_limits<double>::infinity());
    std::vector<char> used(N, 0);
    std::mt19937_64 rng(seed);
    std::size_t pick = std::min<std::size_t>(N - 1, std::size_t(uniform01(rng) * double(N)));
    for (int c = 0; c < C; ++c) {
        used[pick] = 1;
        centres.row(c) = X.row(pick);
        arena.execute([&] {
            parallel_for(0, N, 1024, Split::automatic, [&](std::size_t first, std::size_t last) {
                for (std::size_t i = first; i != last; ++i)
                    nearest[i] =
                        std::min(nearest[i], double((X.row(i) - centres.row(c)).squaredNorm()));
            });
        });
        if (c + 1 == C) break;
        const double total = std::accumulate(nearest.begin(), nearest.end(), 0.0);
        pick = N;
        if (total > 0) {
            const double target = uniform01(rng) * total;
            double run = 0;
            for (std::size_t i = 0; i < N; ++i) {
                run += nearest[i];
                if (run > target && nearest[i] > 0) {
                    pick = i;
                    break;
                }
            }
        }
        if (pick == N)  // all remaining rows coincide with a centre (or rounding): lowest unused
            pick = std::size_t(std::find(used.begin(), used.end(), 0) - used.begin());
        if (pick == N) pick = 0;
    }
    return centres;
}

// The nearest centre of row `row` (whose squared norm is `norm`), given its dot products with
// the centres (`dots`, one per centre) and their squared norms: by the expanded distance
// ‖x‖² − 2x·c + ‖c‖², which in float is off by at most about γ_D (‖x‖² + ‖c‖²) (Higham,
// "Accuracy and Stability of Numerical Algorithms", §3.1, for each of the three terms); every
// centre that may, within that rounding, be the nearest is compared by its exact distance
// (lowest index on ties) — near-equal rows would otherwise fall to the wrong one of their
// centres, and one cluster per receiver would not reproduce its rows.
int nearest_centre(const MatrixF& X, std::size_t row, float norm, const float* dots,
                   const MatrixF& centres, const Eigen::VectorXf& cnorm, float gamma) {
    const int C = int(centres.rows());
    auto expanded = [&](int c) { return norm - 2 * dots[c] + cnorm[c]; };
    auto slack = [&](int c) { return gamma * (norm + cnorm[c]); };
    int best = 0;
    float best_d = std::numeric_limits<float>::infinity();
    for (int c = 0; c < C; ++c) {
        const float d = expanded(c);
        if (d < best_d) {
            best_d = d;
            best = c;
        }
    }
    const float limit = best_d + slack(best);
    double best_exact = std::numeric_limits<double>::infinity();
    for (int c = 0; c < C; ++c) {
        if (expanded(c) - slack(c) > limit) continue;
        const double e = (X.row(row).cast<double>() - centres.row(c).cast<double>()).squaredNorm();
        if (e < best_exact) {
            best_exact = e;
            best = c;
        }
    }
    return best;
}

// 2. Lloyd iterations from `centres`: each row's cluster (one product per block of rows).
std::vector<std::uint32_t> lloyd(const MatrixF& X, const Eigen::VectorXf& norms, MatrixF centres,
                                 int iterations, Arena& arena) {
    const std::size_t N = std::size_t(X.rows()), D = std::size_t(X.cols());
    const int C = int(centres.rows());
    const float gamma = 3.0f * float(D + 2) * std::numeric_limits<float>::epsilon();
    std::vector<std::uint32_t> assign(N, 0);
    const std::size_t blocks = (N + kBlockRows - 1) / kBlockRows;
    for (int it = 0; it <= iterations; ++it) {
        const Eigen::VectorXf cnorm = centres.rowwise().squaredNorm();
        std::vector<char> changed(blocks, 0);
        arena.execute([&] {
            parallel_for(
                0, blocks, 1, Split::fixed, [&](std::size_t first_block, std::size_t last_block) {
                    for (std::size_t b = first_block; b != last_block; ++b) {
                        const std::size_t first = b * kBlockRows;
                        const std::size_t count = std::min(kBlockRows, N - first);
                        const MatrixF dots = X.middleRows(first, count) * centres.transpose();
                        for (std::size_t i = 0; i < count; ++i) {
                            const std::size_t row = first + i;
                            const int best = nearest_centre(X, row, norms[row], dots.row(i).data(),
                                                            centres, cnorm, gamma);
                            if (assign[row] != std::uint32_t(best) || it == 0) changed[b] = 1;
                            assign[row] = std::uint32_t(best);
                        }
                    }
                });
        });
        const bool any = std::find(changed.begin(), changed.end(), 1) != changed.end();
        if (!any || it == iterations) break;
        MatrixD sums = MatrixD::Zero(C, D);
        std::vector<std::size_t> counts(C, 0);
        for (std::size_t i = 0; i < N; ++i) {
            sums.row(assign[i]) += X.row(i).cast<double>();
            ++counts[assign[i]];
        }
        for (int c = 0; c < C; ++c)
            if (counts[c] > 0) centres.row(c) = (sums.row(c) / double(counts[c])).cast<float>();
    }
    return assign;
}

// 3. Cluster c of `code` from its members `m`: the mean (from the original rows, so a
// one-member cluster is exact), the principal directions and the members' weights.
void fit_cluster(const float* rows, std::size_t D, const std::vector<float>& scale, int c,
                 const std::vector<std::size_t>& m, CpcaCode& code) {
    const int V = code.vectors;
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(D);
    for (std::size_t i : m)
        for (std::size_t d = 0; d < D; ++d) mean[d] += rows[i * D + d];
    mean /= double(m.size());
    float* out_mean = code.means.data() + std::size_t(c) * D;
    for (std::size_t d = 0; d < D; ++d) out_mean[d] = float(mean[d]);
    MatrixD A(m.size(), D);  // centred members, Frobenius metric
    for (std::size_t k = 0; k < m.size(); ++k)
        for (std::size_t d = 0; d < D; ++d)
            A(k, d) = (double(rows[m[k] * D + d]) - double(out_mean[d])) * scale[d];
    MatrixD B = MatrixD::Zero(V, D);  // rows: orthonormal directions
    if (m.size() > 1) {
        const bool gram = m.size() <= D;
        const MatrixD S = gram ? MatrixD(A * A.transpose()) : MatrixD(A.transpose() * A);
        Eigen::SelfAdjointEigenSolver<MatrixD> eig(S);
        const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
        const double tiny = 1e-12 * std::max(1.0, lambda[lambda.size() - 1]);
        for (int v = 0; v < V && v < lambda.size(); ++v) {
            const Eigen::Index e = lambda.size() - 1 - v;
            if (lambda[e] <= tiny) break;
            Eigen::VectorXd dir = gram ? Eigen::VectorXd(A.transpose() * eig.eigenvectors().col(e))
                                       : Eigen::VectorXd(eig.eigenvectors().col(e));
            dir.normalize();
            Eigen::Index at = 0;
            dir.cwiseAbs().maxCoeff(&at);
            if (dir[at] < 0) dir = -dir;
            B.row(v) = dir.transpose();
        }
    }
    // 4. weights, and the directions stored in the original coordinates.
    for (std::size_t k = 0; k < m.size(); ++k) {
        const Eigen::VectorXd w = B * A.row(k).transpose();
        for (int v = 0; v < V; ++v) code.weights[m[k] * V + v] = float(w[v]);
    }
    float* out_basis = code.basis.data() + std::size_t(c) * V * D;
    for (int v = 0; v < V; ++v)
        for (std::size_t d = 0; d < D; ++d)
            out_basis[std::size_t(v) * D + d] = float(B(v, d) / scale[d]);
}

// The code of N rows of D floats (row-major), in the metric `scale` (one factor per float);
// the options already checked.
CpcaCode cpca_of_rows(const float* rows, std::size_t N, std::size_t D,
                      const std::vector<float>& scale, const CpcaOptions& options) {
    const int C = options.clusters, V = options.vectors;
    Arena arena(options.threads);
    MatrixF X(N, D);
    for (std::size_t r = 0; r < N; ++r)
        for (std::size_t d = 0; d < D; ++d) X(r, d) = rows[r * D + d] * scale[d];
    const Eigen::VectorXf norms = X.rowwise().squaredNorm();

    const std::vector<std::uint32_t> assign =
        lloyd(X, norms, seed_centres(X, C, options.seed, arena), options.iterations, arena);

    std::vector<std::vector<std::size_t>> members(C);
    for (std::size_t i = 0; i < N; ++i) members[assign[i]].push_back(i);
    CpcaCode code;
    code.clusters = C;
    code.vectors = V;
    code.seed = options.seed;
    code.cluster = assign;
    code.means.assign(std::size_t(C) * D, 0.0f);
    code.basis.assign(std::size_t(C) * V * D, 0.0f);
    code.weights.assign(N * std::size_t(V), 0.0f);
    arena.execute([&] {
        parallel_for(0, std::size_t(C), 1, Split::automatic,
                     [&](std::size_t first, std::size_t last) {
                         for (int c = int(first); c != int(last); ++c)
                             if (!members[c].empty())
                                 fit_cluster(rows, D, scale, c, members[c], code);
                     });
    });
    return code;
}

}  // namespace

CpcaCode compress_cpca(const TransferSet& transfer, const CpcaOptions& options) {
    const std::size_t N = transfer.receiver_count();
    const std::size_t D = transfer.layout.floats_per_receiver();
    SHPRT_CHECK(N >= 1 && D >= 1, invalid_argument, "CPCA of an empty transfer");
    SHPRT_CHECK(options.clusters >= 1 && std::size_t(options.clusters) <= N, invalid_argument,
                "CPCA clusters = {} must be 1 to the receiver count {}", options.clusters, N);
    SHPRT_CHECK(
        options.vectors >= 1 && std::size_t(options.vectors) <= D, invalid_argument,
        "CPCA vectors = {} must be 1 to {} (the floats per receiver: {})", options.vectors, D,
        is_glossy_matrix(transfer.layout) ? "K(K+1)/2 for a symmetric matrix" : "K per channel");
    SHPRT_CHECK(options.iterations >= 0, invalid_argument, "CPCA iterations = {} must be ≥ 0",
                options.iterations);
    return cpca_of_rows(transfer.coeffs.data(), N, D, metric_scale(transfer.layout), options);
}

void reconstruct_cpca(const CpcaCode& code, std::size_t D, std::vector<float>& out) {
    const std::size_t N = code.cluster.size();
    validate(code, N, D);
    const std::size_t V = std::size_t(code.vectors);
    out.assign(N * D, 0.0f);
    for (std::size_t r = 0; r < N; ++r) {
        const std::size_t c = code.cluster[r];
        float* x = out.data() + r * D;
        const float* mean = code.means.data() + c * D;
        // Accumulate in double, in a fixed order: the mean, then each direction.
        for (std::size_t d = 0; d < D; ++d) {
            double s = mean[d];
            for (std::size_t v = 0; v < V; ++v)
                s += double(code.weights[r * V + v]) * double(code.basis[(c * V + v) * D + d]);
            x[d] = float(s);
        }
    }
}

double cpca_bytes_per_receiver(const CpcaCode& code, std::size_t D, std::size_t receivers,
                               int element_bytes) {
    const double shared =
        double(code.clusters) * double(D) * double(1 + code.vectors) * element_bytes;
    return 4.0 + double(code.vectors) * element_bytes +
           shared / double(std::max<std::size_t>(1, receivers));
}

namespace {

// transfer_error under `lights`: each K coefficients (one for every colour) or 3·K (channel-major
// RGB; a grey transfer is then lit by each colour in turn).
TransferError error_under(const TransferSet& exact, const TransferSet& approx,
                          const std::vector<Vec3f>& normals,
                          const std::vector<std::vector<double>>& lights) {
    SHPRT_CHECK(exact.layout == approx.layout || (exact.layout.K == approx.layout.K &&
                                                  exact.layout.shape == approx.layout.shape &&
                                                  exact.layout.channels == approx.layout.channels),
                invalid_argument, "transfer_error: the two transfers have different layouts");
    const std::size_t N = exact.receiver_count();
    SHPRT_CHECK(approx.receiver_count() == N && normals.size() == N, invalid_argument,
                "transfer_error: {} vs {} receivers and {} normals", N, approx.receiver_count(),
                normals.size());
    const TransferLayout& layout = exact.layout;
    const int K = layout.K;
    const int bands = sh_bands_for(K);
    const bool matrix = is_matrix(layout);
    for (const std::vector<double>& light : lights)
        SHPRT_CHECK(light.size() == std::size_t(K) || light.size() == 3 * std::size_t(K),
                    invalid_argument, "transfer_error: a light of {} coefficients for K = {}",
                    light.size(), K);
    // The (transfer channel, light colour) pairs lit: colour c of an RGB light lights channel c,
    // or the one grey channel.
    const auto colours = [&](const std::vector<double>& light, int c) {
        const bool rgb = light.size() == 3 * std::size_t(K);
        return std::pair{rgb ? (layout.channels == 3 ? c : 0) : 0,
                         rgb ? (layout.channels == 3 ? c + 1 : 3) : 1};
    };
    const std::vector<double> phong = phong_lobe_zonal(bands, 16.0);
    const std::vector<double> cosine = clamped_cosine_zonal(bands);

    std::vector<double> err2(N, 0.0), ref2(N, 0.0);
    std::vector<int> values(N, 0);
    parallel_for(0, N, 256, Split::automatic, [&](std::size_t first, std::size_t last) {
        std::vector<double> Me(std::size_t(K) * K), Ma(std::size_t(K) * K), lobe(K);
        std::vector<std::vector<double>> lobes;
        for (std::size_t r = first; r != last; ++r) {
            for (int c = 0; c < layout.channels; ++c) {
                const float* e = exact.receiver(r, c);
                const float* a = approx.receiver(r, c);
                if (!matrix) {
                    for (const std::vector<double>& light : lights) {
                        const auto [first_colour, end_colour] = colours(light, c);
                        for (int lc = first_colour; lc < end_colour; ++lc) {
                            const double* L = light.data() + std::size_t(lc) * K;
                            double se = 0, sa = 0;
                            for (int i = 0; i < K; ++i) {
                                se += double(e[i]) * L[i];
                                sa += double(a[i]) * L[i];
                            }
                            err2[r] += (se - sa) * (se - sa);
                            ref2[r] += se * se;
                            ++values[r];
                        }
                    }
                    continue;
                }
                // Unpack both matrices (symmetric packed or full row-major).
                unpack_matrix(layout, e, Me.data());
                unpack_matrix(layout, a, Ma.data());
                // The views: Phong 16 about n and three directions 45° from it, and the cosine.
                const Vec3d n = normalize(cast<double>(normals[r]));
                const Vec3d t =
                    normalize(cross(std::fabs(n.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0}, n));
                const Vec3d b = cross(n, t);
                lobes.assign(5, std::vector<double>(K));
                const double h = std::sqrt(0.5);
                const Vec3d dirs[4] = {n, n * h + t * h, n * h - t * 0.5 * h + b * (0.866 * h),
                                       n * h - t * 0.5 * h - b * (0.866 * h)};
                for (int v = 0; v < 4; ++v)
                    rotate_zonal(phong.data(), K, normalize(dirs[v]), lobes[v].data());
                rotate_zonal(cosine.data(), K, n, lobes[4].data());
                std::vector<double> te(K), ta(K);
                for (const std::vector<double>& light : lights) {
                    const auto [first_colour, end_colour] = colours(light, c);
                    for (int lc = first_colour; lc < end_colour; ++lc) {
                        const double* L = light.data() + std::size_t(lc) * K;
                        for (int i = 0; i < K; ++i) {
                            te[i] = ta[i] = 0;
                            for (int j = 0; j < K; ++j) {
                                te[i] += Me[i * K + j] * L[j];
                                ta[i] += Ma[i * K + j] * L[j];
                            }
                        }
                        for (const std::vector<double>& g : lobes) {
                            double se = 0, sa = 0;
                            for (int i = 0; i < K; ++i) {
                                se += g[i] * te[i];
                                sa += g[i] * ta[i];
                            }
                            err2[r] += (se - sa) * (se - sa);
                            ref2[r] += se * se;
                            ++values[r];
                        }
                    }
                }
            }
        }
    });
    double total_err = 0, total_ref = 0, total_values = 0;
    for (std::size_t r = 0; r < N; ++r) {
        total_err += err2[r];
        total_ref += ref2[r];
        total_values += values[r];
    }
    TransferError out;
    out.relative_rmse = total_ref > 0 ? std::sqrt(total_err / total_ref) : std::sqrt(total_err);
    const double rms = total_ref > 0 ? std::sqrt(total_ref / total_values) : 1.0;
    out.receiver_rmse.resize(N);
    for (std::size_t r = 0; r < N; ++r)
        out.receiver_rmse[r] = float(std::sqrt(err2[r] / std::max(1, values[r])) / rms);
    std::vector<std::size_t> order(N);
    std::iota(order.begin(), order.end(), 0);
    const std::size_t top = std::min<std::size_t>(10, N);
    std::partial_sort(order.begin(), order.begin() + top, order.end(),
                      [&](std::size_t a, std::size_t b) {
                          return out.receiver_rmse[a] > out.receiver_rmse[b] ||
                                 (out.receiver_rmse[a] == out.receiver_rmse[b] && a < b);
                      });
    out.worst.assign(order.begin(), order.begin() + top);
    return out;
}

}  // namespace

TransferError transfer_error(const TransferSet& exact, const TransferSet& approx,
                             const std::vector<Vec3f>& normals, std::uint64_t seed) {
    const int K = exact.layout.K;
    constexpr int kLights = 8;
    std::mt19937_64 rng(seed);
    std::vector<std::vector<double>> lights(kLights, std::vector<double>(std::size_t(K)));
    for (int l = 0; l < kLights; ++l)
        for (int i = 0; i < K; ++i) {
            const int band = int(std::sqrt(double(i)));
            lights[std::size_t(l)][std::size_t(i)] =
                (i == 0 ? 3.0 : 0.0) + (2 * uniform01(rng) - 1) / (1.0 + band);
        }
    return error_under(exact, approx, normals, lights);
}

TransferError transfer_error(const TransferSet& exact, const TransferSet& approx,
                             const std::vector<Vec3f>& normals, std::span<const float> light) {
    SHPRT_CHECK(light.size() == 3 * std::size_t(exact.layout.K), invalid_argument,
                "transfer_error: a light of {} coefficients for transfer of K = {} (3 K)",
                light.size(), exact.layout.K);
    return error_under(exact, approx, normals, {std::vector<double>(light.begin(), light.end())});
}

CpcaResult compress_transfer(const TransferSet& transfer, const std::vector<Vec3f>& normals,
                             const CpcaOptions& options, bool half,
                             const std::vector<float>* light) {
    const std::size_t N = transfer.receiver_count();
    const std::size_t D = transfer.layout.floats_per_receiver();
    CpcaResult out;
    auto start = Clock::now();
    CpcaCode code = compress_cpca(transfer, options);
    out.seconds_fit = seconds_since(start);
    if (half) {
        for (std::vector<float>* a : {&code.weights, &code.means, &code.basis})
            for (float& x : *a) x = half_to_float(float_to_half(x));
    }
    static_cast<TransferInfo&>(out.compressed) = transfer;
    out.compressed.layout.encoding = half ? TransferEncoding::f16 : TransferEncoding::f32;
    const int element_bytes = bytes_per_value(out.compressed.layout.encoding);
    reconstruct_cpca(code, D, out.compressed.coeffs);
    out.compressed.cpca = std::move(code);
    // The direct part is small (one channel of vectors) and is what "direct only" shows: kept,
    // in the file's encoding.
    out.compressed.direct = transfer.direct;
    // Transfer probes are carried as they are (float32, not clustered): a grid is small beside
    // the receivers' rows.
    out.compressed.probes = transfer.probes;
    if (half)
        for (float& x : out.compressed.direct) x = half_to_float(float_to_half(x));
    out.direct_bytes_per_receiver =
        N > 0 ? double(out.compressed.direct.size()) * element_bytes / double(N) : 0.0;
    start = Clock::now();
    out.error = transfer_error(transfer, out.compressed, normals, options.seed);
    if (light) out.light_error = transfer_error(transfer, out.compressed, normals, *light);
    out.seconds_error = seconds_since(start);
    out.bytes_per_receiver = cpca_bytes_per_receiver(out.compressed.cpca, D, N, element_bytes);
    out.raw_bytes_per_receiver = 4.0 * double(D);
    out.raw_full_bytes_per_receiver =
        !is_matrix(transfer.layout)
            ? 4.0 * double(D)
            : 4.0 * transfer.layout.channels * double(transfer.layout.K) * transfer.layout.K;
    return out;
}

ProbeCpcaResult compress_probes(const ProbeGrid& grid, const CpcaOptions& options,
                                const std::vector<float>* light) {
    SHPRT_CHECK(!grid.empty(), invalid_argument, "CPCA of probes: the file has no probes");
    grid.validate();
    const std::size_t D = std::size_t(grid.channels) * std::size_t(grid.K) * std::size_t(grid.K);
    std::vector<float> rows;  // the valid probes' matrices, in probe order
    for (std::size_t p = 0; p < grid.count(); ++p)
        if (grid.valid[p]) rows.insert(rows.end(), grid.matrix(p), grid.matrix(p) + D);
    const std::size_t N = rows.size() / D;
    SHPRT_CHECK(N >= 1, invalid_argument, "CPCA of probes: no probe is valid");
    SHPRT_CHECK(options.clusters >= 1 && std::size_t(options.clusters) <= N, invalid_argument,
                "probe CPCA clusters = {} must be 1 to the valid probes, {}", options.clusters, N);
    SHPRT_CHECK(options.vectors >= 1 && std::size_t(options.vectors) <= D, invalid_argument,
                "probe CPCA vectors = {} must be 1 to {} (channels x K x K = {} x {} x {})",
                options.vectors, D, grid.channels, grid.K, grid.K);
    SHPRT_CHECK(options.iterations >= 0, invalid_argument, "CPCA iterations = {} must be ≥ 0",
                options.iterations);
    if (light)
        SHPRT_CHECK(light->size() == 3 * std::size_t(grid.K), invalid_argument,
                    "probe CPCA: the light has {} floats, not 3 x K = {}", light->size(),
                    3 * grid.K);
    ProbeCpcaResult out;
    const auto start = Clock::now();
    out.compressed = grid;
    out.compressed.cpca = cpca_of_rows(rows.data(), N, D, std::vector<float>(D, 1.0f), options);
    out.seconds_fit = seconds_since(start);
    reconstruct_probes(out.compressed);

    // The errors, over the valid probes, in double.
    const int K = grid.K, channels = grid.channels;
    double diff2 = 0, norm2 = 0, light_diff2 = 0, light_norm2 = 0;
    for (std::size_t p = 0; p < grid.count(); ++p) {
        if (!grid.valid[p]) continue;
        for (int c = 0; c < channels; ++c) {
            const float* exact = grid.matrix(p, c);
            const float* approx = out.compressed.matrix(p, c);
            for (std::size_t k = 0; k < std::size_t(K) * std::size_t(K); ++k) {
                const double d = double(exact[k]) - double(approx[k]);
                diff2 += d * d;
                norm2 += double(exact[k]) * double(exact[k]);
            }
            if (!light) continue;
            // A grey grid is lit by each colour in turn; an RGB one by its own colour.
            for (int colour = channels == 1 ? 0 : c; colour < (channels == 1 ? 3 : c + 1);
                 ++colour) {
                const float* L = light->data() + std::size_t(colour) * std::size_t(K);
                for (int i = 0; i < K; ++i) {
                    double e = 0, a = 0;
                    for (int j = 0; j < K; ++j) {
                        e += double(exact[i * K + j]) * double(L[j]);
                        a += double(approx[i * K + j]) * double(L[j]);
                    }
                    light_diff2 += (e - a) * (e - a);
                    light_norm2 += e * e;
                }
            }
        }
    }
    out.relative_rmse = norm2 > 0 ? std::sqrt(diff2 / norm2) : 0.0;
    if (light)
        out.light_relative_rmse = light_norm2 > 0 ? std::sqrt(light_diff2 / light_norm2) : 0.0;
    out.bytes_per_probe = cpca_bytes_per_receiver(out.compressed.cpca, D, N, 4);
    out.raw_bytes_per_probe = 4.0 * double(D);
    return out;
}

void reconstruct_probes(ProbeGrid& grid) {
    const std::size_t D = std::size_t(grid.channels) * std::size_t(grid.K) * std::size_t(grid.K);
    std::size_t valid = 0;
    for (std::uint8_t v : grid.valid) valid += v;
    validate(grid.cpca, valid, D);
    std::vector<float> rows;
    reconstruct_cpca(grid.cpca, D, rows);
    grid.matrices.assign(grid.count() * D, 0.0f);
    for (std::size_t p = 0, r = 0; p < grid.count(); ++p)
        if (grid.valid[p]) {
            std::copy_n(rows.data() + r * D, D, grid.matrices.data() + p * D);
            ++r;
        }
}

}  // namespace shprt
