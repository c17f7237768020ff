// Clustered principal component analysis (CPCA) of transfer rows: P.-P. Sloan, J. Hall, J. Hart,
// J. Snyder, "Clustered Principal Components for Precomputed Radiance Transfer", SIGGRAPH 2003.
//
// Each receiver's row x (D = layout.floats_per_receiver() floats: a vector, or a symmetric
// matrix's packed upper triangle) is approximated as
//
//     x ≈ mean[c] + Σ_{i<N} w_i · B[c][i],        c = the receiver's cluster, N = vectors,
//
// so that shading needs, per cluster, the light transformed once (mean·L and B_i·L) and per
// receiver only N weights: M·L = mean·L + Σ w_i (B_i·L). The fit runs in the Frobenius metric of
// the full K×K matrix (the packed off-diagonal entries weigh √2: they stand for two entries).
//
// Method (deterministic: the same input and seed give the same bits with any thread count):
//   1. k-means++ seeding (Arthur & Vassilvitskii 2007) from a std::mt19937_64 seeded with
//      `seed`: the first centre uniformly, each next one with probability ∝ the squared
//      distance to the nearest centre so far (ties and all-zero distances: the lowest unused row);
//   2. Lloyd iterations (at most `iterations`, until no receiver changes cluster): assignment to
//      the nearest centre (lowest index on ties), by ‖x‖² − 2 x·c + ‖c‖² with Eigen products over
//      fixed blocks of rows, then each centre the mean of its members (an emptied cluster keeps
//      its centre);
//   3. per cluster, PCA of its members about their mean: the eigenvectors of the smaller of
//      the Gram matrix A·Aᵀ and the covariance AᵀA (Eigen's SelfAdjointEigenSolver), the N with
//      the largest eigenvalues, each with its largest component positive; directions beyond the
//      cluster's rank are zero vectors;
//   4. weights w_i = B_iᵀ(x − mean) in the Frobenius metric.
// This is the non-iterative variant (cluster, then PCA); Sloan et al. also iterate the
// assignment by reconstruction error.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace shprt {

struct CpcaOptions {
    int clusters = 256;  // 1 ≤ clusters ≤ receivers
    int vectors = 8;     // 1 ≤ vectors ≤ D (floats per receiver)
    std::uint64_t seed = 1;
    int iterations = 16;  // Lloyd iterations at most, ≥ 0
    int threads = 0;      // 0 = all hardware threads
};

// The CPCA code of `transfer`'s rows. Throws Error(invalid_argument) naming the parameter for
// clusters outside [1, receivers], vectors outside [1, D], iterations < 0, or an empty set.
CpcaCode compress_cpca(const TransferSet& transfer, const CpcaOptions& options);

// The rows the code stands for: receivers × D floats, into `out` (resized). Throws
// Error(invalid_argument) when the code's arrays do not fit `D` or a cluster index is out of
// range (a file's code is checked by the reader with it).
void reconstruct_cpca(const CpcaCode& code, std::size_t D, std::vector<float>& out);

// Bytes a receiver costs in a CPCA file with `receivers` receivers, element size 4 (float32) or
// 2 (float16): its cluster index (4) and weights, plus its share of the means and bases.
double cpca_bytes_per_receiver(const CpcaCode& code, std::size_t D, std::size_t receivers,
                               int element_bytes);

// The error of an approximation of a transfer, measured on exit radiance (shprt compress).
// Test set: 8 SH lights (seeded; band l with amplitude 1/(1+l) around a positive constant) and,
// for matrices, 4 views per receiver: a Phong lobe (exponent 16) about the normal and about three
// directions 45° from it, plus the clamped cosine (the diffuse term); for vectors, E = t·L per
// channel. Each value e is ⟨lobe, M·L⟩ (matrices) or t·L (vectors).
struct TransferError {
    double relative_rmse = 0;  // sqrt(Σ (e − ê)² / Σ e²) over the whole scene
    // Per receiver: sqrt(mean over its values of (e − ê)²) / (the scene's RMS of e).
    std::vector<float> receiver_rmse;
    std::vector<std::size_t> worst;  // up to 10 receivers, the largest receiver_rmse first
};
// `approx` must have `exact`'s layout and receiver count; `normals` one per receiver.
TransferError transfer_error(const TransferSet& exact, const TransferSet& approx,
                             const std::vector<Vec3f>& normals, std::uint64_t seed = 1);
// The same views under one given light instead of the test lights (`shprt compress --light`):
// 3·K coefficients, channel-major RGB (an ShLight's), K the transfer's; colour c lights channel c
// (a grey transfer: each colour in turn).
TransferError transfer_error(const TransferSet& exact, const TransferSet& approx,
                             const std::vector<Vec3f>& normals, std::span<const float> light);

// What `shprt compress` does: the code of `transfer` (compress_cpca), stored as float16 when
// `half` (the code's floats rounded as a file stores them), the rows rebuilt from it, and the error
// of those rows against the input (transfer_error with `normals`, one per receiver).
struct CpcaResult {
    TransferSet compressed;  // the input's description, layout encoding f16 when half, the code in
                             // .cpca and the rebuilt rows in .coeffs; an interreflected input's
                             // direct part (.direct) kept as is (rounded to float16 when half);
                             // the probes (.probes) kept as they are (float32)
    TransferError error;
    std::optional<TransferError> light_error;  // under compress_transfer's `light`, if given
    double seconds_fit = 0, seconds_error = 0;
    double bytes_per_receiver = 0;           // the code (cpca_bytes_per_receiver)
    double raw_bytes_per_receiver = 0;       // the input's rows as float32
    double raw_full_bytes_per_receiver = 0;  // full K×K float32 matrices per channel (matrices),
                                             // else the rows as float32
    double direct_bytes_per_receiver = 0;    // the direct part kept beside the code (0: none)
};
// `light` (optional, 3·K floats as transfer_error takes): the error under it too, in
// CpcaResult::light_error.
CpcaResult compress_transfer(const TransferSet& transfer, const std::vector<Vec3f>& normals,
                             const CpcaOptions& options, bool half,
                             const std::vector<float>* light = nullptr);

// Transfer probes (transfer/probes.hpp) compressed the same way (`shprt compress --probe-cpca`,
// docs/probes.md): the rows are the valid probes' matrices, channels·K² floats each, in the
// Frobenius metric of the general (not symmetric) K×K matrices; invalid probes stay zero and
// take no row. The grid keeps float32 (it is small beside the receivers; --half does not touch
// it).
struct ProbeCpcaResult {
    ProbeGrid compressed;  // the input grid, the code in .cpca and the rebuilt matrices
    // ‖P − P̂‖_F / ‖P‖_F over the valid probes: the relative RMS error of the incident
    // radiance's SH, P·L, under lights of independent unit coefficients.
    double relative_rmse = 0;
    // sqrt(Σ ‖(P − P̂)·L‖² / Σ ‖P·L‖²) over the valid probes and channels, under compress_probes'
    // `light` (3·K floats, channel-major RGB, K the probes'; colour c lights channel c, a grey
    // grid each colour in turn), when given.
    std::optional<double> light_relative_rmse;
    double seconds_fit = 0;
    double bytes_per_probe = 0;      // the code, float32, per valid probe
    double raw_bytes_per_probe = 0;  // channels·K² float32
};
// Throws Error(invalid_argument) naming the parameter: a grid without probes or without a valid
// one, clusters outside [1, valid probes], vectors outside [1, channels·K²], iterations < 0.
ProbeCpcaResult compress_probes(const ProbeGrid& grid, const CpcaOptions& options,
                                const std::vector<float>* light = nullptr);
// grid.matrices rebuilt from grid.cpca (the valid probes' rows; invalid probes zero). Throws
// Error(invalid_argument) when the code does not fit the grid (a file's code is checked by the
// reader with it).
void reconstruct_probes(ProbeGrid& grid);

}  // namespace shprt
