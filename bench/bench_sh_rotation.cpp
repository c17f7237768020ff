// SH rotation cost per bands count (4, 8, 16, 32), double unless noted:
//   * Ivanic–Ruedenberg: building the block matrices from a 3x3 matrix;
//   * the paper's factorisation Z(γ)·X(π/2)ᵀ·Z(β)·X(π/2)·Z(α): building the matrices from Euler
//     angles (R^x(π/2) blocks cached beforehand, as the paper precomputes them once), and
//     applying it directly to one vector without forming a matrix (how a light is rotated);
//   * applying a built rotation to one vector (double and float);
//   * the zonal fast path (a lobe rotated to a direction in O(K), float and double) against the
//     general route (build the rotation, apply it to the zonal vector).
// Each benchmark first checks what it times against an independent route (paper vs Ivanic,
// zonal fast path vs general rotation) and skips with an error if they disagree.
//
// Usage: bench_sh_rotation [Google Benchmark flags, e.g. --benchmark_min_time=0.2]
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/sh/zonal.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

namespace {

using namespace shprt;

constexpr double kAlpha = 0.7, kBeta = 1.9, kGamma = -2.3;
constexpr double kAgreeTol = 1e-10;

Mat3d bench_matrix() { return matrix_from_zyz(kAlpha, kBeta, kGamma); }

std::vector<double> bench_coeffs(int K) {
    std::vector<double> c(K);
    for (int i = 0; i < K; ++i) c[i] = std::sin(0.37 * i + 0.1);
    return c;
}

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
    double e = 0;
    for (std::size_t i = 0; i < a.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]));
    return e;
}

// Paper and Ivanic rotations of the same vector must agree before either is timed.
bool methods_agree(int bands) {
    const int K = sh_count(bands);
    const std::vector<double> c = bench_coeffs(K);
    std::vector<double> a(K), b(K), d(K);
    ShRotation::from_matrix(bench_matrix(), bands, RotationMethod::ivanic)
        .apply(c.data(), a.data(), K);
    ShRotation::from_zyz(kAlpha, kBeta, kGamma, bands, RotationMethod::paper)
        .apply(c.data(), b.data(), K);
    rotate_zyz_paper(kAlpha, kBeta, kGamma, c.data(), d.data(), K);
    return max_diff(a, b) < kAgreeTol && max_diff(a, d) < kAgreeTol;
}

void BM_IvanicBuild(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0));
    if (!methods_agree(bands)) return state.SkipWithError("paper and Ivanic disagree");
    const Mat3d R = bench_matrix();
    for (auto _ : state) {
        ShRotation rot = ShRotation::from_matrix(R, bands, RotationMethod::ivanic);
        benchmark::DoNotOptimize(rot.block(bands - 1));
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_PaperBuild(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0));
    if (!methods_agree(bands)) return state.SkipWithError("paper and Ivanic disagree");
    for (auto _ : state) {
        ShRotation rot = ShRotation::from_zyz(kAlpha, kBeta, kGamma, bands, RotationMethod::paper);
        benchmark::DoNotOptimize(rot.block(bands - 1));
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_PaperDirectApply(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0)), K = sh_count(bands);
    if (!methods_agree(bands)) return state.SkipWithError("paper and Ivanic disagree");
    const std::vector<double> c = bench_coeffs(K);
    std::vector<double> out(K);
    for (auto _ : state) {
        rotate_zyz_paper(kAlpha, kBeta, kGamma, c.data(), out.data(), K);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_ApplyMatrix(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0)), K = sh_count(bands);
    if (!methods_agree(bands)) return state.SkipWithError("paper and Ivanic disagree");
    const ShRotation rot = ShRotation::from_matrix(bench_matrix(), bands);
    const std::vector<double> c = bench_coeffs(K);
    std::vector<double> out(K);
    for (auto _ : state) {
        rot.apply(c.data(), out.data(), K);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_ApplyMatrixFloat(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0)), K = sh_count(bands);
    if (!methods_agree(bands)) return state.SkipWithError("paper and Ivanic disagree");
    const ShRotation rot = ShRotation::from_matrix(bench_matrix(), bands);
    const std::vector<double> cd = bench_coeffs(K);
    const std::vector<float> c(cd.begin(), cd.end());
    std::vector<float> out(K);
    for (auto _ : state) {
        rot.apply(c.data(), out.data(), K);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

// The zonal fast path must equal the general rotation of the zonal vector.
bool zonal_agrees(int bands, const std::vector<double>& z, Vec3d dir) {
    const int K = sh_count(bands);
    std::vector<double> full(K), general(K), fast(K);
    zonal_to_coeffs(z.data(), bands, full.data(), K);
    ShRotation::from_matrix(rotation_z_to(dir), bands).apply(full.data(), general.data(), K);
    rotate_zonal(z.data(), K, dir, fast.data());
    return max_diff(general, fast) < kAgreeTol;
}

const Vec3d kLobeDir = normalize(Vec3d{0.3, 0.8, -0.52});

void BM_ZonalFastPath(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0)), K = sh_count(bands);
    const std::vector<double> z = phong_lobe_zonal(bands, 16.0);
    if (!zonal_agrees(bands, z, kLobeDir)) return state.SkipWithError("zonal paths disagree");
    std::vector<double> out(K);
    for (auto _ : state) {
        rotate_zonal(z.data(), K, kLobeDir, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_ZonalFastPathFloat(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0)), K = sh_count(bands);
    const std::vector<double> zd = phong_lobe_zonal(bands, 16.0);
    if (!zonal_agrees(bands, zd, kLobeDir)) return state.SkipWithError("zonal paths disagree");
    const std::vector<float> z(zd.begin(), zd.end());
    const Vec3f dir = cast<float>(kLobeDir);
    std::vector<float> out(K);
    for (auto _ : state) {
        rotate_zonal(z.data(), K, dir, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_ZonalGeneralRoute(benchmark::State& state) {
    const int bands = static_cast<int>(state.range(0)), K = sh_count(bands);
    const std::vector<double> z = phong_lobe_zonal(bands, 16.0);
    if (!zonal_agrees(bands, z, kLobeDir)) return state.SkipWithError("zonal paths disagree");
    std::vector<double> full(K), out(K);
    zonal_to_coeffs(z.data(), bands, full.data(), K);
    for (auto _ : state) {
        ShRotation::from_matrix(rotation_z_to(kLobeDir), bands).apply(full.data(), out.data(), K);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

void bands_args(benchmark::internal::Benchmark* b) {
    for (int bands : {4, 8, 16, 32}) b->Arg(bands);
    b->ArgName("bands");
}

BENCHMARK(BM_IvanicBuild)->Apply(bands_args);
BENCHMARK(BM_PaperBuild)->Apply(bands_args);
BENCHMARK(BM_PaperDirectApply)->Apply(bands_args);
BENCHMARK(BM_ApplyMatrix)->Apply(bands_args);
BENCHMARK(BM_ApplyMatrixFloat)->Apply(bands_args);
BENCHMARK(BM_ZonalFastPath)->Apply(bands_args);
BENCHMARK(BM_ZonalFastPathFloat)->Apply(bands_args);
BENCHMARK(BM_ZonalGeneralRoute)->Apply(bands_args);

}  // namespace

BENCHMARK_MAIN();
