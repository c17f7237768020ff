// The GPU bake's kernel body, transfer_sample() (bake/transfer_sample.hpp), run on the CPU: a loop
// over it plus a naive double-precision projection must reproduce the CPU bake (Embree + SGEMM)
// on the same direction set. This proves the GPU's math without a GPU: the kernel is nothing but
// this function per (vertex, sample), followed by an SGEMM.
//
// Tolerance. Where the flat BVH and Embree agree on a ray, W is the same; the coefficients then
// differ by the CPU SGEMM's float rounding only, bounded by float_dot_bounds (tests/bake/
// bake_test_util.hpp). Each ray on which the tracers disagree moves coefficient i by exactly
// W_s·|Y_si|, so the bound per vertex is float_dot_bounds + Σ_{disagreeing s} W_s·|Y_si|, and the
// disagreement rate must stay below 1e-3 (the 99.9 % agreement).
#include "bake_test_util.hpp"
#include "twins.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/bake/transfer_sample.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/bvh_build.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

namespace shprt {
namespace {

constexpr double kMaxDisagreementRate = 1e-3;  // flat BVH vs Embree, per ray (issue 5)
constexpr float kInf = std::numeric_limits<float>::infinity();

Vec3f direction(const DirectionSet& set, std::size_t s) {
    return {set.dirs[3 * s], set.dirs[3 * s + 1], set.dirs[3 * s + 2]};
}

struct Emulation {
    std::vector<float> w;         // W[v][s] from transfer_sample (flat BVH)
    std::vector<float> w_embree;  // the same W with Embree's visibility
    std::uint64_t rays = 0, disagreements = 0;
    std::uint64_t twin_rays = 0;  // of vertices the CPU bake copies from a twin (not cast there)
    std::vector<std::uint32_t> disagreements_per_vertex;
};

// W for every vertex and sample, as the kernel computes it, and as the CPU bake would with
// Embree's visibility (same cosine and weight, Embree's occluded()).
Emulation emulate(const Mesh& mesh, const DirectionSet& set, bool shadowed,
                  bool hemisphere = false) {
    const std::size_t V = mesh.vertex_count(), S = set.size();
    FlatBvh bvh;
    std::unique_ptr<Tracer> embree;
    if (shadowed) {
        bvh = build_flat_bvh(mesh);
        embree = make_embree_tracer(mesh);
    }
    const FlatBvhView view = shadowed ? bvh.view() : FlatBvhView{nullptr, nullptr, nullptr, 0, 0};
    Emulation e;
    e.w.resize(V * S);
    e.w_embree.resize(V * S);
    e.disagreements_per_vertex.assign(V, 0);
    const std::vector<bool> copied = test::twin_vertices(mesh, S);
    for (std::size_t v = 0; v < V; ++v) {
        const Vec3f p = mesh.positions[v], n = mesh.normals[v];
        const Vec3f origin = offset_ray_origin(p, n);
        for (std::size_t s = 0; s < S; ++s) {
            const Vec3f w = direction(set, s);
            bool ray_cast = false;
            const float value =
                transfer_sample(view, p, n, w, set.weights[s], shadowed, ray_cast, hemisphere);
            e.w[v * S + s] = value;
            e.w_embree[v * S + s] = value;
            if (!ray_cast) continue;
            ++e.rays;
            e.twin_rays += copied[v] ? 1 : 0;
            bool unused = false;
            const float unoccluded =
                transfer_sample(view, p, n, w, set.weights[s], false, unused, hemisphere);
            std::uint8_t occluded = 0;
            embree->occluded(origin, &w, 1, 0.0f, kInf, &occluded);
            e.w_embree[v * S + s] = occluded ? 0.0f : unoccluded;
            if (e.w_embree[v * S + s] != value) {
                ++e.disagreements;
                ++e.disagreements_per_vertex[v];
            }
        }
    }
    return e;
}

// C[v][i] = Σ_s W[v][s]·Y[s][i] in double: the naive projection.
std::vector<double> project_naive(const std::vector<float>& w, const std::vector<float>& Y,
                                  std::size_t V, std::size_t S, int K) {
    std::vector<double> c(V * K, 0.0);
    for (std::size_t v = 0; v < V; ++v)
        for (std::size_t s = 0; s < S; ++s) {
            const double ws = w[v * S + s];
            if (ws == 0.0) continue;
            for (int i = 0; i < K; ++i) c[v * K + i] += ws * double(Y[s * K + i]);
        }
    return c;
}

// Compares the emulated kernel + naive projection with the CPU bake, vertex by vertex, with the
// bound stated at the top; prints the maximum relative difference (max_i |ΔC_i| / max_i |C_i|).
// The emulated kernel's W projected in double against the CPU bake of `kind` (shadowed,
// unshadowed, or glossy: W without the cosine, projected on the pair-product table, F = K(K+1)/2
// columns), within the float bound of each column plus the exact effect of the rays on which
// the flat BVH and Embree disagree.
void compare_with_cpu_bake(const Mesh& mesh, const DirectionSet& set, int K_basis,
                           TransferKind kind) {
    const bool glossy = kind == TransferKind::glossy;
    const std::size_t V = mesh.vertex_count(), S = set.size();
    const Emulation e = emulate(mesh, set, kind != TransferKind::unshadowed, glossy);
    const std::vector<float> basis = basis_table(K_basis, set);
    const int K = glossy ? K_basis * (K_basis + 1) / 2 : K_basis;  // columns
    std::vector<float> Y = basis;
    if (glossy) {  // y_i·y_j for i ≤ j, packed row by row (docs/glossy.md), in float
        Y.assign(S * K, 0.0f);
        for (std::size_t s = 0; s < S; ++s) {
            int p = 0;
            for (int i = 0; i < K_basis; ++i)
                for (int j = i; j < K_basis; ++j, ++p)
                    Y[s * K + p] = basis[s * K_basis + i] * basis[s * K_basis + j];
        }
    }
    const std::vector<double> c = project_naive(e.w, Y, V, S, K);
    std::vector<double> bound(K, 0.0);  // test::float_dot_bounds for the table's columns
    for (std::size_t s = 0; s < S; ++s)
        for (int i = 0; i < K; ++i)
            bound[i] += double(set.weights[s]) * std::fabs(double(Y[s * K + i]));
    for (double& b : bound) b *= double(S + 8) * test::kFloatEps;

    BakeOptions options;
    options.K = K_basis;
    options.transfer = kind;
    const TransferSet cpu = bake(mesh, options, set);
    ASSERT_EQ(cpu.coeffs.size(), V * K);
    EXPECT_EQ(cpu.stats.rays_cast + e.twin_rays, e.rays)
        << "the kernel casts exactly the CPU bake's rays, and those of the twins it copies";

    double max_rel = 0, max_rel_agreeing = 0;
    std::size_t vertices_with_disagreement = 0;
    for (std::size_t v = 0; v < V; ++v) {
        double diff = 0, scale = 0;
        for (int i = 0; i < K; ++i) {
            // Exact effect of the rays on which the tracers disagree on coefficient i.
            double flips = 0;
            if (e.disagreements_per_vertex[v] > 0)
                for (std::size_t s = 0; s < S; ++s)
                    flips += std::fabs(double(e.w[v * S + s]) - double(e.w_embree[v * S + s])) *
                             std::fabs(double(Y[s * K + i]));
            const double d = std::fabs(c[v * K + i] - double(cpu.coeffs[v * K + i]));
            ASSERT_LE(d, bound[i] + flips * (1 + 1e-6))
                << "vertex " << v << " coefficient " << i << ": emulated " << c[v * K + i]
                << ", cpu bake " << cpu.coeffs[v * K + i] << ", " << e.disagreements_per_vertex[v]
                << " disagreeing rays";
            diff = std::max(diff, d);
            scale = std::max(scale, std::fabs(double(cpu.coeffs[v * K + i])));
        }
        const double rel = scale > 0 ? diff / scale : diff;
        max_rel = std::max(max_rel, rel);
        if (e.disagreements_per_vertex[v] == 0)
            max_rel_agreeing = std::max(max_rel_agreeing, rel);
        else
            ++vertices_with_disagreement;
    }
    const double rate = e.rays > 0 ? double(e.disagreements) / double(e.rays) : 0.0;
    std::printf(
        "[ emulated kernel vs CPU bake ] %s %s, V=%zu S=%zu columns=%d: %llu rays, %llu disagree "
        "with Embree (%.2e), %zu vertices affected; max relative coefficient difference "
        "%.3e (%.3e where visibility agrees)\n",
        to_string(kind), mesh.source.c_str(), V, S, K, static_cast<unsigned long long>(e.rays),
        static_cast<unsigned long long>(e.disagreements), rate, vertices_with_disagreement, max_rel,
        max_rel_agreeing);
    EXPECT_LE(rate, kMaxDisagreementRate);
    // Float SGEMM vs a double sum: (S + 8)·2^-24 of Σ weight·|Y| at most; far smaller in practice.
    EXPECT_LE(max_rel_agreeing, 1e-4);
}

TEST(TransferSample, UnoccludedValueIsTheClampedCosineTimesTheWeight) {
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 3, 2000);
    const FlatBvhView empty{nullptr, nullptr, nullptr, 0, 0};
    const Vec3f p{0.25f, -1.5f, 3.0f};
    const Vec3f n = normalize(Vec3f{0.3f, 0.8f, -0.2f});
    int above = 0;
    for (std::size_t s = 0; s < set.size(); ++s) {
        const Vec3f w = direction(set, s);
        bool ray_cast = true;
        const float value = transfer_sample(empty, p, n, w, set.weights[s], false, ray_cast);
        EXPECT_FALSE(ray_cast) << "unshadowed transfer casts no rays";
        // The CPU bake's formula, in the same order of operations.
        const float cosine = n.x * w.x + n.y * w.y + n.z * w.z;
        const float expected = cosine > 0.0f ? cosine * set.weights[s] : 0.0f;
        EXPECT_EQ(value, expected) << "sample " << s;
        const double exact = std::max(0.0, dot(cast<double>(n), cast<double>(w))) * set.weights[s];
        EXPECT_NEAR(value, exact, 1e-6 * set.weights[s]);
        above += value > 0.0f;
    }
    EXPECT_GT(above, 900);
    EXPECT_LT(above, 1100);
}

TEST(TransferSample, OpenSkyPlaneIsNeverOccluded) {
    const Mesh mesh = make_builtin("plane");
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 11, 512);
    const Emulation e = emulate(mesh, set, true);
    std::uint64_t zeroed = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (std::size_t s = 0; s < set.size(); ++s) {
            bool unused = false;
            const float unoccluded =
                transfer_sample(FlatBvhView{nullptr, nullptr, nullptr, 0, 0}, mesh.positions[v],
                                mesh.normals[v], direction(set, s), set.weights[s], false, unused);
            zeroed += e.w[v * set.size() + s] != unoccluded;
        }
    EXPECT_EQ(zeroed, 0u) << "a ray left the plane and hit it (self-intersection)";
    EXPECT_GT(e.rays, mesh.vertex_count() * set.size() / 3);
}

TEST(TransferSample, EmulatedKernelMatchesTheCpuBakeOnBoxOnPlane) {
    compare_with_cpu_bake(make_builtin("box_on_plane"),
                          make_direction_set(SamplerKind::uniform, 7, 256), 16,
                          TransferKind::shadowed);
}

TEST(TransferSample, EmulatedKernelMatchesTheCpuBakeInTheCorner) {
    compare_with_cpu_bake(make_builtin("corner"),
                          make_direction_set(SamplerKind::stratified, 5, 300), 25,
                          TransferKind::shadowed);
}

TEST(TransferSample, EmulatedKernelMatchesTheCpuBakeInTheRoom) {
    // The benchmark's scene: ~20 000 triangles of furniture, many grazing rays.
    compare_with_cpu_bake(make_builtin("room"), make_direction_set(SamplerKind::uniform, 1, 128),
                          16, TransferKind::shadowed);
}

TEST(TransferSample, EmulatedKernelMatchesTheCpuBakeUnshadowed) {
    compare_with_cpu_bake(make_builtin("sphere"), make_direction_set(SamplerKind::sobol, 2, 128), 9,
                          TransferKind::unshadowed);
}

// The GPU glossy bake's kernel (transfer_sample with `hemisphere`) and its pair-product SGEMM
// against the CPU glossy bake (weight_row with `hemisphere`).
TEST(TransferSample, EmulatedKernelMatchesTheCpuGlossyBake) {
    compare_with_cpu_bake(make_builtin("box_on_plane"),
                          make_direction_set(SamplerKind::sobol, 4, 256), 9, TransferKind::glossy);
}

TEST(TransferSample, HemisphereValueIsTheWeightAboveTheHorizon) {
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 5, 2000);
    const FlatBvhView empty{nullptr, nullptr, nullptr, 0, 0};
    const Vec3f n = normalize(Vec3f{-0.4f, 0.7f, 0.5f});
    int above = 0;
    for (std::size_t s = 0; s < set.size(); ++s) {
        const Vec3f w = direction(set, s);
        bool ray_cast = true;
        const float value =
            transfer_sample(empty, {0, 0, 0}, n, w, set.weights[s], false, ray_cast, true);
        EXPECT_FALSE(ray_cast);
        const float cosine = n.x * w.x + n.y * w.y + n.z * w.z;
        EXPECT_EQ(value, cosine > 0.0f ? set.weights[s] : 0.0f) << "sample " << s;
        above += value > 0.0f;
    }
    EXPECT_GT(above, 900);
    EXPECT_LT(above, 1100);
}

// The GPU kernel's body for a local set (local_transfer_sample, with the axes the kernel computes
// per sample) projected in double in the frame and rotated with the library's SH rotation,
// against the CPU local bake (trace_row, SGEMM onto the full bands, rotate_rows_to_world): the
// kernel casts exactly the CPU bake's rays along the same directions, so with Embree's visibility
// the coefficients agree to float rounding; and the flat BVH agrees with Embree on the rays.
void compare_local_with_cpu_bake(const Mesh& mesh, int K, std::uint32_t S) {
    BakeOptions options;
    options.K = K;
    options.samples = S;
    options.direction_frame = DirectionFrame::local;
    const DirectionSet set = bake_direction_set(options);
    const int KL = sh_count(sh_bands_for(K));
    const std::vector<float> Y = basis_table(KL, set);
    const FlatBvh bvh = build_flat_bvh(mesh);
    const std::unique_ptr<Tracer> embree = make_embree_tracer(mesh);
    const TransferSet cpu = bake(mesh, options, set);
    ASSERT_EQ(cpu.layout.K, K);

    // The open part exactly (docs/sampling.md, (3)), as the host applies it before the rotation:
    // δ = Q_S(cos) − c′_open, and each row less β·δ with β = ĉ′_00/c′_open,00.
    std::vector<double> delta = open_hemisphere_transfer(KL, HemisphereDensity::cosine);
    const double open00 = delta[0];
    for (int i = 0; i < KL; ++i) {
        double q = 0;
        for (std::size_t s = 0; s < S; ++s) q += double(set.weights[s]) * double(Y[s * KL + i]);
        delta[std::size_t(i)] = q - delta[std::size_t(i)];
    }
    std::uint64_t rays = 0, disagreements = 0, twin_rays = 0;
    const std::vector<bool> copied = test::twin_vertices(mesh, S);
    double max_rel = 0;
    std::vector<double> frame_row(KL), world_row(KL);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const Vec3f p = mesh.positions[v], n = mesh.normals[v];
        const LocalAxes axes = local_axes(n);
        const LocalFrame frame = local_frame(n);
        ASSERT_EQ(std::memcmp(&axes, static_cast<const LocalAxes*>(&frame), sizeof axes), 0)
            << "the kernel's axes must be the CPU bake's frame, bit for bit (vertex " << v << ")";
        std::fill(frame_row.begin(), frame_row.end(), 0.0);
        for (std::size_t s = 0; s < S; ++s) {
            const Vec3f l = direction(set, s);
            bool ray_cast = false;
            const float value =
                local_transfer_sample(bvh.view(), p, n, axes, l, set.weights[s], true, ray_cast);
            ASSERT_TRUE(ray_cast) << "every local sample is above the horizon";
            ++rays;
            twin_rays += copied[v] ? 1 : 0;
            const Vec3f w = to_world(axes, l);
            std::uint8_t occluded = 0;
            embree->occluded(offset_ray_origin(p, n), &w, 1, 0.0f, kInf, &occluded);
            const float embree_value = occluded ? 0.0f : set.weights[s];
            disagreements += value != embree_value;
            for (int i = 0; i < KL; ++i)
                frame_row[std::size_t(i)] += double(embree_value) * double(Y[s * KL + i]);
        }
        const double beta = frame_row[0] / open00;
        for (int i = 0; i < KL; ++i) frame_row[std::size_t(i)] -= beta * delta[std::size_t(i)];
        rotate_zyz_paper(0.0, frame.beta, frame.gamma, frame_row.data(), world_row.data(), KL);
        double diff = 0, scale = 0;
        for (int i = 0; i < K; ++i) {
            diff = std::max(diff, std::fabs(world_row[std::size_t(i)] - cpu.receiver(v)[i]));
            scale = std::max(scale, std::fabs(double(cpu.receiver(v)[i])));
        }
        max_rel = std::max(max_rel, scale > 0 ? diff / scale : diff);
    }
    const double rate = double(disagreements) / double(rays);
    std::printf(
        "[ emulated local kernel vs CPU local bake ] %s, K=%d S=%u: %llu rays, flat BVH vs Embree "
        "%.2e, max relative coefficient difference %.3e\n",
        mesh.source.c_str(), K, S, (unsigned long long)rays, rate, max_rel);
    EXPECT_EQ(cpu.stats.rays_cast + twin_rays, rays)
        << "the kernel casts exactly the CPU bake's rays, and those of the twins it copies";
    EXPECT_LE(rate, kMaxDisagreementRate);
    EXPECT_LE(max_rel, 1e-4);
}

TEST(TransferSample, EmulatedLocalKernelMatchesTheCpuLocalBake) {
    compare_local_with_cpu_bake(make_builtin("box_on_plane"), 16, 128);
    // K = 10 rotates the full 4 bands and keeps 10; the room's interpenetrating furniture.
    compare_local_with_cpu_bake(make_builtin("room"), 10, 32);
}

TEST(TransferSample, LocalValueIsTheWeightAndTheRayTheFramesDirection) {
    const DirectionSet set =
        make_local_direction_set(SamplerKind::sobol, 5, 256, HemisphereDensity::cosine);
    const FlatBvhView empty{nullptr, nullptr, nullptr, 0, 0};
    const Vec3f n = normalize(Vec3f{-0.4f, 0.7f, 0.5f});
    const LocalAxes axes = local_axes(n);
    for (std::size_t s = 0; s < set.size(); ++s) {
        bool ray_cast = true;
        const float value = local_transfer_sample(empty, {0, 0, 0}, n, axes, direction(set, s),
                                                  set.weights[s], false, ray_cast);
        EXPECT_FALSE(ray_cast) << "unshadowed transfer casts no rays";
        EXPECT_EQ(value, set.weights[s]) << "sample " << s;
        EXPECT_GT(dot(to_world(axes, direction(set, s)), n), -1e-6f)
            << "a local direction turned into the frame is above the horizon";
    }
}

}  // namespace
}  // namespace shprt
