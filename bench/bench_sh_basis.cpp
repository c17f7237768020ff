// SH basis evaluation throughput on the host: directions per second filling the paper's basis
// table Y[S×K] (sh_eval_batch) at 4, 8, 16 and 32 bands, float and double; plus the library's
// basis_table (double evaluation rounded to float) and the sphere samplers.
// Every benchmark validates its output before timing it (finite values, and rows checked against
// the slow reference sh_eval_reference); a wrong result skips the benchmark with an error.
#include "shprt/sh/basis.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/sh/sampler.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

namespace shprt {
namespace {

constexpr std::uint32_t kDirections = 4096;  // table rows per iteration (paper-sized sets)

template <class T>
std::vector<T> directions() {
    const DirectionSetD set = make_direction_set_d(SamplerKind::uniform, 1, kDirections);
    return std::vector<T>(set.dirs.begin(), set.dirs.end());
}

// Empty string if `table` (S×K, from `dirs`) is finite and matches the reference on sampled rows.
template <class T>
std::string validate(const std::vector<T>& table, const std::vector<T>& dirs, int K) {
    for (T v : table)
        if (!std::isfinite(v)) return "non-finite basis value";
    // float: relative recurrence error grows with l; 32 bands stay well inside 1e-3 absolute.
    const double tol = sizeof(T) == sizeof(float) ? 1e-3 : 1e-10;
    for (std::uint32_t s = 0; s < kDirections; s += 97) {
        const double x = dirs[3 * s], y = dirs[3 * s + 1], z = dirs[3 * s + 2];
        const double theta = std::acos(std::fmax(-1.0, std::fmin(1.0, z))), phi = std::atan2(y, x);
        for (int i = 0; i < K; i += 7) {
            const int l = sh_band(i);
            const double ref = sh_eval_reference(l, i - l * (l + 1), theta, phi);
            if (std::abs(ref - static_cast<double>(table[s * K + i])) > tol)
                return "basis value differs from the reference at row " + std::to_string(s) +
                       ", index " + std::to_string(i);
        }
    }
    return {};
}

template <class T>
void BM_ShEvalTable(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0));
    const int K = sh_count(bands);
    const std::vector<T> dirs = directions<T>();
    std::vector<T> table(static_cast<std::size_t>(kDirections) * K);
    sh_eval_batch(K, dirs.data(), kDirections, table.data(), K);
    if (const std::string err = validate(table, dirs, K); !err.empty()) {
        state.SkipWithError(err.c_str());
        return;
    }
    for (auto _ : state) {
        sh_eval_batch(K, dirs.data(), kDirections, table.data(), K);
        benchmark::DoNotOptimize(table.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kDirections);
    state.counters["coeffs/s"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * kDirections * K, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ShEvalTable<float>)
    ->Name("sh_eval_table/float/bands")
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Arg(32);
BENCHMARK(BM_ShEvalTable<double>)
    ->Name("sh_eval_table/double/bands")
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Arg(32);

// The library's table builder (double evaluation, rounded to float, renormalised directions).
void BM_BasisTable(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0));
    const int K = sh_count(bands);
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 1, kDirections);
    std::vector<float> table = basis_table(K, set);
    const std::vector<float> dirs = set.dirs;
    if (const std::string err = validate(table, dirs, K); !err.empty()) {
        state.SkipWithError(err.c_str());
        return;
    }
    for (auto _ : state) {
        table = basis_table(K, set);
        benchmark::DoNotOptimize(table.data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kDirections);
}
BENCHMARK(BM_BasisTable)->Name("basis_table/bands")->Arg(4)->Arg(8)->Arg(16)->Arg(32);

// Sphere samplers, float, one direction per call as a GPU thread would compute it.
void BM_SphereDirection(benchmark::State& state) {
    const SamplerKind kind = kAllSamplerKinds[state.range(0)];
    state.SetLabel(to_string(kind));
    for (std::uint32_t s = 0; s < kDirections; ++s) {
        const Vec3f d = sphere_direction<float>(kind, 1, s, kDirections);
        if (!(std::abs(length(d) - 1.0f) < 1e-5f)) {
            state.SkipWithError("direction is not unit length");
            return;
        }
    }
    for (auto _ : state) {
        for (std::uint32_t s = 0; s < kDirections; ++s)
            benchmark::DoNotOptimize(sphere_direction<float>(kind, 1, s, kDirections));
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kDirections);
}
BENCHMARK(BM_SphereDirection)->Name("sphere_direction/float/kind")->DenseRange(0, 3);

}  // namespace
}  // namespace shprt

BENCHMARK_MAIN();
