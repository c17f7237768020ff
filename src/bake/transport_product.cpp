// The bounces' sparse × dense products (interreflect.hpp: apply_transport; bake_internal.hpp:
// apply_transport_rows): A's blocks of compressed rows times the sources' rows of transfer, by an
// AVX2 kernel or by Eigen, with the same bits either way.
#include "bake/bake_internal.hpp"
#include "bake/bake_progress.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/host.hpp"
#include "shprt/core/parallel.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <Eigen/SparseCore>

#include <immintrin.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {
namespace {

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
                                                         const detail::BounceRows& p, float* acc) {
    const std::size_t in_stride = std::size_t(p.in_channels) * std::size_t(p.in_K);
    const std::size_t in_step = p.in_channels == 3 ? std::size_t(p.in_K) : 0;
    const std::size_t out_stride = 3 * std::size_t(p.out_K);
    const int width = p.columns;
    const int vec_end = width / 8 * 8;
    const float* v0 = A.channel(0);
    const float* v1 = A.channel(1);
    const float* v2 = A.channel(2);
    const std::int32_t* starts = A.starts();
    const std::int32_t* columns = A.columns();
    for (std::size_t r = 0; r < A.rows(); ++r) {
        std::fill_n(acc, 3 * std::size_t(width), 0.0f);
        for (std::int32_t q = starts[r]; q < starts[r + 1]; ++q) {
            const float* x = p.in + std::size_t(columns[std::size_t(q)]) * in_stride;
            const float a[3] = {v0[q], v1[q], v2[q]};
            for (int c = 0; c < 3; ++c) {
                const float* xc = x + std::size_t(c) * in_step;
                float* yc = acc + std::size_t(c) * std::size_t(width);
                const __m256 av = _mm256_set1_ps(a[c]);
                int k = 0;
                for (; k < vec_end; k += 8)
                    _mm256_storeu_ps(yc + k,
                                     _mm256_add_ps(_mm256_loadu_ps(yc + k),
                                                   _mm256_mul_ps(av, _mm256_loadu_ps(xc + k))));
                for (; k < width; ++k) yc[k] = yc[k] + a[c] * xc[k];
            }
        }
        float* y = p.out + (A.first + r - p.first) * out_stride;
        for (int c = 0; c < 3; ++c)
            std::copy_n(acc + std::size_t(c) * std::size_t(width), width,
                        y + std::size_t(c) * std::size_t(p.out_K));
    }
}

// Multiply-adds below which a product runs on the calling thread (apply_transport_rows).
constexpr std::uint64_t kSerialWork = std::uint64_t(1) << 18;

}  // namespace

namespace detail {

// The products of apply_transport and of the bounces (detail::BounceRows: which rows, which
// columns, which layouts), with an optional progress reporter counting rows. Each output row is
// its own sum over its row's entries in column order from zero: the bits never depend on the
// blocks, the threads, the kernel, the layouts or how many columns are computed.
void apply_transport_rows(const TransportOperator& A, const BounceRows& p, int threads,
                          TransportKernel kernel, BakeProgress* progress) {
    const auto N = static_cast<Eigen::Index>(A.vertices);
    const bool avx2 =
        kernel == TransportKernel::avx2 || (kernel == TransportKernel::automatic && cpu_has_avx2());
    SHPRT_CHECK(!avx2 || cpu_has_avx2(), unsupported, "this CPU has no AVX2");
    const auto eigen_block = [&](const TransportOperator::Block& b) {
        const auto rows = static_cast<Eigen::Index>(b.rows());
        const Eigen::Index out_stride = 3 * Eigen::Index(p.out_K);
        for (int c = 0; c < 3; ++c) {
            const SparseMap a(rows, N, Eigen::Index(b.nnz()), b.starts(), b.columns(),
                              b.channel(c));
            const DenseMap x(p.in + (p.in_channels == 3 ? c * p.in_K : 0), N, p.columns,
                             Eigen::OuterStride<>(p.in_channels * Eigen::Index(p.in_K)));
            DenseOut y(p.out + Eigen::Index(b.first - p.first) * out_stride + c * p.out_K, rows,
                       p.columns, Eigen::OuterStride<>(out_stride));
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
            acc.resize(3 * std::size_t(p.columns));
            transport_rows_avx2(b, p, acc.data());
        }
        if (progress) {
            progress->add(b.rows(), 0);
            progress->poll();
        }
    };
    // The blocks that hold rows [first, end) (A's blocks are in row order; both are block ends).
    std::size_t from = 0;
    while (from < A.blocks.size() && A.blocks[from].first < p.first) ++from;
    std::size_t to = from;
    while (to < A.blocks.size() && A.blocks[to].first < p.end) ++to;
    // A product too small to share (fewer multiply-adds than kSerialWork) stays on this thread:
    // a fork and join per bounce costs more than it saves, and far more when another process
    // holds the cores and a worker waits for a time slice (a thousand bounces of a small scene
    // took seconds, not a tenth of one, beside a busy neighbour). Same bits either way.
    std::uint64_t work = 0;
    for (std::size_t b = from; b < to; ++b) work += A.blocks[b].nnz();
    work *= 3 * std::uint64_t(p.columns);
    if (thread_count(threads) == 1 || to - from == 1 || work < kSerialWork) {
        for (std::size_t b = from; b < to; ++b) run_block(A.blocks[b]);
        return;
    }
    parallel_each(threads, to - from, [&](std::size_t b) { run_block(A.blocks[from + b]); });
}

}  // namespace detail

void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads) {
    apply_transport(A, in, out, K, threads, TransportKernel::automatic);
}

void apply_transport(const TransportOperator& A, const float* in, float* out, int K, int threads,
                     TransportKernel kernel, int columns) {
    const int width = columns > 0 && columns < K ? columns : K;
    detail::apply_transport_rows(A, detail::BounceRows{in, 3, K, 0, A.vertices, out, K, width},
                                 threads, kernel, nullptr);
}

}  // namespace shprt
