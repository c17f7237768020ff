// Projection of functions on the sphere onto the first K real SH coefficients (sh/basis.hpp
// conventions), and reconstruction.
//
//   c_i = ∫ f(ω) y_i(ω) dω ≈ Σ_s w_s f(d_s) y_i(d_s)
//
// with a DirectionSet (sampler.hpp): Monte Carlo (the paper's scheme: weights 4π/S, the basis
// table Y[S×K] evaluated once and shared by every function projected) or exact quadrature
// (Gauss–Legendre: exact when f·y_i is band-limited, e.g. quadrature_set_for_bands).
// K is any basis size 1 ≤ K ≤ kMaxBands², not only a square. Host code; single-threaded but for
// the float basis_table, whose rows run on the calling arena's threads (core/parallel.hpp).
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/sh/sampler.hpp"

#include <functional>
#include <vector>

namespace shprt {

// The paper's basis table: Y[s·K + i] = y_i(d_s), row-major S×K. Each direction is taken to
// double, renormalised (float directions are unit only to ~6e-8), evaluated with sh_eval_k in
// double and rounded to float. Throws Error(invalid_argument) when K is outside
// [1, kMaxBands²] or the set is malformed (dirs.size() ≠ 3·weights.size()). The rows are
// evaluated in parallel on the calling arena; the bits do not depend on the threads.
std::vector<float> basis_table(int K, const DirectionSet& set);
// Double table Y[S×K] of a double set (directions used as given, assumed unit).
std::vector<double> basis_table(int K, const DirectionSetD& set);

// c_i = Σ_s w_s f(d_s) y_i(d_s) for i < K, accumulated in double. For a float set, f and y are
// evaluated at the renormalised double direction (as in basis_table). Throws as basis_table.
std::vector<double> project(const std::function<double(const Vec3d&)>& f, int K,
                            const DirectionSet& set);
std::vector<double> project(const std::function<double(const Vec3d&)>& f, int K,
                            const DirectionSetD& set);

// The paper's projection against a precomputed table: c_i = Σ_s w_s · values[s] · Y[s·K + i],
// accumulated in double. `table` is basis_table(K, set) (S·K values), `values` holds f(d_s)
// (S values). This is the slow, obvious reference for the bake's GEMM. Throws
// Error(invalid_argument) on mismatched sizes.
std::vector<double> project_with_table(const std::vector<float>& table, int K,
                                       const DirectionSet& set, const std::vector<float>& values);

// Σ_{i<K} coeffs[i] · y_i(dir), in double. `dir` need not be unit (it is normalised) but must be
// finite and non-zero. Throws Error(invalid_argument) for K outside [1, kMaxBands²], a null
// `coeffs`, or a zero or non-finite `dir`.
double sh_reconstruct(const double* coeffs, int K, const Vec3d& dir);

}  // namespace shprt
