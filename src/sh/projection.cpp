// Projection onto real SH by Monte Carlo or quadrature, and reconstruction.
//  * Sloan, Kautz, Snyder 2002, "Precomputed Radiance Transfer for Real-Time Rendering in
//    Dynamic, Low-Frequency Lighting Environments": c = Σ_s w_s f(d_s) y(d_s).
//  * Green 2003, "Spherical Harmonic Lighting: The Gritty Details": the basis table evaluated
//    once per direction and reused for every projected function.
#include "shprt/sh/projection.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/memory.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/sh/basis.hpp"

#include <array>
#include <cmath>
#include <cstddef>

namespace shprt {
namespace {

void check_k(int K, const char* what) {
    SHPRT_CHECK(K >= 1 && K <= kMaxBands * kMaxBands, invalid_argument,
                "{}: basis size K must be in [1, {}], got {}", what, kMaxBands * kMaxBands, K);
}

template <class Set>
void check_set(const Set& set, const char* what) {
    SHPRT_CHECK(set.dirs.size() == 3 * set.weights.size(), invalid_argument,
                "{}: malformed direction set ({} direction values for {} weights; need 3 per "
                "weight)",
                what, set.dirs.size(), set.weights.size());
}

Vec3d direction(const DirectionSet& set, std::size_t s) {
    const Vec3d d{set.dirs[3 * s], set.dirs[3 * s + 1], set.dirs[3 * s + 2]};
    return normalize(d);
}

Vec3d direction(const DirectionSetD& set, std::size_t s) {
    return {set.dirs[3 * s], set.dirs[3 * s + 1], set.dirs[3 * s + 2]};
}

template <class Set>
std::vector<double> project_impl(const std::function<double(const Vec3d&)>& f, int K,
                                 const Set& set) {
    check_k(K, "project");
    check_set(set, "project");
    SHPRT_CHECK(static_cast<bool>(f), invalid_argument, "project: empty function");
    std::vector<double> coeffs(K, 0.0), y(K);
    for (std::size_t s = 0; s < set.size(); ++s) {
        const Vec3d d = direction(set, s);
        const double wf = static_cast<double>(set.weights[s]) * f(d);
        sh_eval_k(K, d.x, d.y, d.z, y.data());
        for (int i = 0; i < K; ++i) coeffs[i] += wf * y[i];
    }
    return coeffs;
}

}  // namespace

std::vector<float> basis_table(int K, const DirectionSet& set) {
    check_k(K, "basis_table");
    check_set(set, "basis_table");
    std::vector<float> table;
    assign_huge(table, set.size() * static_cast<std::size_t>(K));
    // Rows are independent (the same bits on any thread); a bake's is up to 16 384 × 1 024
    // evaluations in double, which the bake's threads would otherwise wait for.
    const ShBasisEvaluator<double> eval(K);
    parallel_for(0, set.size(), 256, Split::automatic, [&](std::size_t first, std::size_t last) {
        std::vector<double> y(K);
        for (std::size_t s = first; s < last; ++s) {
            const Vec3d d = direction(set, s);
            eval(d.x, d.y, d.z, y.data());
            float* row = table.data() + s * K;
            for (int i = 0; i < K; ++i) row[i] = static_cast<float>(y[i]);
        }
    });
    return table;
}

std::vector<double> basis_table(int K, const DirectionSetD& set) {
    check_k(K, "basis_table");
    check_set(set, "basis_table");
    std::vector<double> table(set.size() * static_cast<std::size_t>(K));
    for (std::size_t s = 0; s < set.size(); ++s) {
        const Vec3d d = direction(set, s);
        sh_eval_k(K, d.x, d.y, d.z, table.data() + s * K);
    }
    return table;
}

std::vector<double> project(const std::function<double(const Vec3d&)>& f, int K,
                            const DirectionSet& set) {
    return project_impl(f, K, set);
}

std::vector<double> project(const std::function<double(const Vec3d&)>& f, int K,
                            const DirectionSetD& set) {
    return project_impl(f, K, set);
}

std::vector<double> project_with_table(const std::vector<float>& table, int K,
                                       const DirectionSet& set, const std::vector<float>& values) {
    check_k(K, "project_with_table");
    check_set(set, "project_with_table");
    SHPRT_CHECK(
        table.size() == set.size() * static_cast<std::size_t>(K) && values.size() == set.size(),
        invalid_argument,
        "project_with_table: need a table of S*K = {}*{} values and S values, got {} and "
        "{}",
        set.size(), K, table.size(), values.size());
    std::vector<double> coeffs(K, 0.0);
    for (std::size_t s = 0; s < set.size(); ++s) {
        const double wf = static_cast<double>(set.weights[s]) * values[s];
        const float* row = table.data() + s * K;
        for (int i = 0; i < K; ++i) coeffs[i] += wf * row[i];
    }
    return coeffs;
}

double sh_reconstruct(const double* coeffs, int K, const Vec3d& dir) {
    check_k(K, "sh_reconstruct");
    SHPRT_CHECK(coeffs != nullptr, invalid_argument, "sh_reconstruct: null coefficients");
    const double len = length(dir);
    SHPRT_CHECK(std::isfinite(len) && len > 0.0, invalid_argument,
                "sh_reconstruct: direction ({}, {}, {}) is zero or not finite", dir.x, dir.y,
                dir.z);
    const Vec3d d = dir / len;
    // Up to 32 bands on the stack (the transfer sizes); larger K allocates.
    std::array<double, 1024> small;
    std::vector<double> large;
    double* y = small.data();
    if (K > static_cast<int>(small.size())) {
        large.resize(K);
        y = large.data();
    }
    sh_eval_k(K, d.x, d.y, d.z, y);
    double sum = 0.0;
    for (int i = 0; i < K; ++i) sum += coeffs[i] * y[i];
    return sum;
}

}  // namespace shprt
