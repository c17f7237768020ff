// Interreflected transfer (bake/interreflect.hpp, docs/interreflection.md), against things that
// do not share its code:
//   * N = 0 is the shadowed bake, bit for bit, in each of the three channels;
//   * same seed → same bits for 1 and 2 threads;
//   * the spherical cavity (a sphere seen from inside, a cap cut away): every point of a sphere
//     sees any part of it with a view factor equal to that part's share of the area, so the
//     direct irradiance under a constant sky L is the same everywhere, E_0 = π·L·f (f: the share
//     of the cosine-weighted hemisphere that leaves through the opening), and each bounce
//     multiplies it by ρ(1 − f): E_N = E_0·Σ_{b≤N} (ρ(1−f))^b. With ρ = 1 that is the white
//     furnace: E_N rises with N at every vertex and tends to π·L;
//   * a brute-force Monte Carlo path tracer written here (the tracer's closest hits, cosine-
//     sampled directions, the hit's vertex chosen with probability = its barycentric), at N = 1
//     and 3, RGB albedo, a non-constant light;
//   * one-sided surfaces: rays that hit a back face bring nothing (and do with two_sided).
#include "bake_test_util.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/bake/transfer_sample.hpp"
#include "shprt/bake/transport_build.hpp"
#include "shprt/core/error.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/trace/bvh_build.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace shprt {
namespace {

constexpr double kPi = std::numbers::pi;

// The irradiance of channel c of vertex v under a constant sky of radiance 1: only the DC term
// counts, l_0 = 2√π.
double constant_sky_E(const TransferSet& t, std::size_t v, int c) {
    return double(t.receiver(v, c)[0]) * 2.0 * std::sqrt(kPi);
}

// E_N of the open cavity's closed form at a vertex whose direct irradiance under the unit sky is
// E0 (f = E0/π its opening's share): E_0·Σ_{b≤N} (ρ(1−f))^b.
double cavity_closed_form(double E0, double rho, int N) {
    const double r = rho * (1.0 - E0 / kPi);
    double expect = 0, term = E0;
    for (int b = 0; b <= N; ++b, term *= r) expect += term;
    return expect;
}

BakeOptions ir_options(int K, std::uint32_t samples, int bounces) {
    BakeOptions o;
    o.transfer = TransferKind::interreflected;
    o.K = K;
    o.samples = samples;
    o.seed = 3;
    o.threads = 2;
    o.bounces = bounces;
    return o;
}

// The analytic checks below test the operator and the iteration, not the final gather's noise
// or the sources' cells: the vertices alone are the bounce sources and every direction builds A
// (the discretisation of docs/interreflection.md's derivation, step 4). The leaky room
// (test_leaky_room.cpp) tests the default sources against a renderer.
BakeOptions exact_options(int K, std::uint32_t samples, int bounces) {
    BakeOptions o = ir_options(K, samples, bounces);
    o.indirect_samples = samples;
    o.source_spacing = std::numeric_limits<float>::infinity();
    return o;
}

TEST(Interreflect, ZeroBouncesIsTheShadowedBakeBitForBit) {
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions shadowed = ir_options(16, 256, 0);
    shadowed.transfer = TransferKind::shadowed;
    const TransferSet direct = bake(mesh, shadowed);
    const TransferSet ir = bake(mesh, ir_options(16, 256, 0));
    ASSERT_EQ(ir.layout.channels, 3);
    ASSERT_EQ(ir.kind, TransferKind::interreflected);
    ASSERT_EQ(ir.receiver_count(), mesh.vertex_count());
    ASSERT_EQ(ir.direct.size(), direct.coeffs.size());
    EXPECT_EQ(std::memcmp(ir.direct.data(), direct.coeffs.data(), direct.coeffs.size() * 4), 0);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(std::memcmp(ir.receiver(v, c), direct.receiver(v), 16 * sizeof(float)), 0)
                << "vertex " << v << " channel " << c;
    // With bounces, the direct part is still the shadowed bake's.
    const TransferSet ir3 = bake(mesh, ir_options(16, 256, 3));
    EXPECT_EQ(std::memcmp(ir3.direct.data(), direct.coeffs.data(), direct.coeffs.size() * 4), 0);
    EXPECT_EQ(ir3.interreflection.bounces, 3);
    EXPECT_GT(ir3.interreflection.operator_nnz, 0u);
}

// --target-error on interreflected transfer (docs/sampling.md, "Where it runs"): the direct part
// T_0 is the error-bounded shadowed bake, bit for bit, with its estimates in the file; the final
// gather takes the prefix the receivers needed (their mean, rounded up to a power of two) divided
// by kIndirectSampleShare, of the same nested set — the operator of a fixed bake of that many
// samples. On a room built like real assets (overlapping panels, parts through the floor).
TEST(Interreflect, ErrorBoundedDirectPartAndAGatherFromTheSameNestedSet) {
    const Mesh mesh = make_builtin("leaky_room");
    BakeOptions options = ir_options(16, 1, 2);  // samples: the bound's set is max_samples
    options.target_error = 0.03;
    options.max_samples = 2048;
    BakeOptions shadowed = options;
    shadowed.transfer = TransferKind::shadowed;
    shadowed.bounces = 0;
    // One tracer for every bake: Embree's quality follows S, and a closest hit on a shared edge
    // may name either triangle, which moves a few of the operator's entries.
    const auto tracer = make_embree_tracer(mesh);
    const auto bake_on = [&](const BakeOptions& o) {
        HostSink rows, direct_rows;
        BakeJob job{&mesh, vertex_receivers(mesh), &rows, nullptr, tracer.get(), &direct_rows};
        TransferSet t;
        static_cast<TransferInfo&>(t) = bake(job, o);
        t.coeffs = rows.take_rows();
        t.direct = direct_rows.take_rows();
        rows.take_estimates(t);
        return t;
    };
    const TransferSet direct = bake_on(shadowed);
    const TransferSet ir = bake_on(options);
    ASSERT_EQ(ir.direct.size(), direct.coeffs.size());
    EXPECT_EQ(std::memcmp(ir.direct.data(), direct.coeffs.data(), direct.coeffs.size() * 4), 0);
    EXPECT_EQ(ir.receiver_samples, direct.receiver_samples);
    EXPECT_EQ(ir.receiver_error, direct.receiver_error);
    EXPECT_EQ(ir.target_error, 0.03);

    const std::size_t base = gather_base_of(direct.receiver_samples);
    EXPECT_LT(base, 2048u) << "the receivers needed less than the most";
    EXPECT_EQ(ir.interreflection.indirect_samples, base / kIndirectSampleShare);
    // The operator is a fixed bake's of `base` samples: the same gather, the same sources.
    const TransferSet fixed = bake_on(ir_options(16, std::uint32_t(base), 2));
    EXPECT_EQ(fixed.interreflection.indirect_samples, ir.interreflection.indirect_samples);
    EXPECT_EQ(fixed.interreflection.operator_nnz, ir.interreflection.operator_nnz);
    EXPECT_EQ(fixed.interreflection.operator_rays, ir.interreflection.operator_rays);
    // And the light it adds is the fixed bake's within the direct parts' difference.
    double bounced = 0, differ = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c) {
            const double a = ir.receiver(v, c)[0] - ir.direct[v * 16];
            const double b = fixed.receiver(v, c)[0] - fixed.direct[v * 16];
            bounced += b * b;
            differ += (a - b) * (a - b);
        }
    EXPECT_GT(bounced, 0);
    EXPECT_LT(std::sqrt(differ / bounced), 0.1) << "the bounced c00, relative RMS";
}

TEST(Interreflect, SameBitsForAnyThreadCount) {
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions one = ir_options(9, 256, 3);
    one.threads = 1;
    BakeOptions two = one;
    two.threads = 2;
    const TransferSet a = bake(mesh, one), b = bake(mesh, two);
    ASSERT_EQ(a.coeffs.size(), b.coeffs.size());
    EXPECT_EQ(std::memcmp(a.coeffs.data(), b.coeffs.data(), a.coeffs.size() * 4), 0);
    EXPECT_EQ(a.interreflection.operator_nnz, b.interreflection.operator_nnz);
}

// From the second bounce on the light is carried in the first bounce_coeffs coefficients: those
// are the whole bake's bits, and every later coefficient is T_0 plus the first bounce alone — the
// bits of a one-bounce bake. Each bounce's product computes the same sums either way.
TEST(Interreflect, LaterBouncesCarryTheFirstBounceCoeffs) {
    Mesh mesh = make_builtin("box_on_plane");
    for (Vec3f& rho : mesh.albedo) rho = Vec3f{0.9f, 0.5f, 0.2f};
    const int K = 25, narrow = 4;
    BakeOptions o = ir_options(K, 256, 3);
    o.bounce_coeffs = K;
    const TransferSet all = bake(mesh, o);
    o.bounce_coeffs = narrow;
    const TransferSet cut = bake(mesh, o);
    BakeOptions once = ir_options(K, 256, 1);
    const TransferSet one = bake(mesh, once);
    EXPECT_EQ(all.interreflection.bounce_coeffs, std::uint64_t(K));
    EXPECT_EQ(cut.interreflection.bounce_coeffs, std::uint64_t(narrow));
    EXPECT_EQ(one.interreflection.bounce_coeffs, std::uint64_t(kDefaultBounceCoeffs));
    std::size_t differ = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(std::memcmp(cut.receiver(v, c), all.receiver(v, c), narrow * sizeof(float)),
                      0)
                << "vertex " << v << " channel " << c;
            ASSERT_EQ(std::memcmp(cut.receiver(v, c) + narrow, one.receiver(v, c) + narrow,
                                  (K - narrow) * sizeof(float)),
                      0)
                << "vertex " << v << " channel " << c;
            for (int k = narrow; k < K; ++k)
                differ += all.receiver(v, c)[k] != cut.receiver(v, c)[k];
        }
    EXPECT_GT(differ, 0u) << "the later bounces added nothing past the first coefficients";
    // The default is kDefaultBounceCoeffs, or K when that is smaller; more than K is refused.
    EXPECT_EQ(bake(mesh, ir_options(9, 64, 2)).interreflection.bounce_coeffs, 9u);
    o.bounce_coeffs = K + 1;
    EXPECT_THROW(bake(mesh, o), Error);
}

// A memory budget that A does not fit: its blocks past the budget are spilled to a temporary file
// and read back memory-mapped; the result is the in-memory bake's, bit for bit, whether every block
// spills (a budget of 1 byte) or some do, and nothing is left in the spill directory.
TEST(Interreflect, SpilledOperatorGivesTheSameBits) {
    Mesh mesh = make_builtin("box_on_plane");
    for (Vec3f& rho : mesh.albedo) rho = Vec3f{0.9f, 0.5f, 0.2f};  // three different channels
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("shprt_spill_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    BakeOptions o = ir_options(9, 256, 3);
    o.threads = 2;
    o.chunk_receivers = 32;  // several blocks, so that a budget can keep some
    const TransferSet whole = bake(mesh, o);
    EXPECT_EQ(whole.stats.operator_bytes_spilled, 0u);
    const std::uint64_t A = whole.interreflection.operator_bytes;
    const std::uint64_t rest = estimate_bake_peak_bytes(mesh.triangle_count(), mesh.vertex_count(),
                                                        o, true, bake_bounce_source_count(mesh, o));
    for (const std::uint64_t budget : {std::uint64_t(1), rest + A / 2}) {
        SCOPED_TRACE("budget " + std::to_string(budget));
        BakeOptions spilling = o;
        spilling.memory_budget = budget;
        spilling.spill_directory = dir.string();
        const TransferSet t = bake(mesh, spilling);
        ASSERT_EQ(t.coeffs.size(), whole.coeffs.size());
        EXPECT_EQ(std::memcmp(t.coeffs.data(), whole.coeffs.data(), t.coeffs.size() * 4), 0);
        EXPECT_EQ(t.direct, whole.direct);
        EXPECT_EQ(t.interreflection.operator_nnz, whole.interreflection.operator_nnz);
        EXPECT_GT(t.stats.operator_bytes_spilled, 0u);
        if (budget == 1)
            EXPECT_EQ(t.stats.operator_bytes_spilled, A);
        else
            EXPECT_LT(t.stats.operator_bytes_spilled, A);
        EXPECT_TRUE(std::filesystem::is_empty(dir)) << "the spill file was left behind";
    }
    // A budget A fits: nothing spills.
    BakeOptions roomy = o;
    roomy.memory_budget = rest + 2 * A;
    roomy.spill_directory = dir.string();
    EXPECT_EQ(bake(mesh, roomy).stats.operator_bytes_spilled, 0u);
    std::filesystem::remove_all(dir);
}

// The progress of an interreflected bake: T_0's and the bounce sources' stages name what follows
// outside their totals (ProgressInfo::then), the bounces' stage names nothing after it.
TEST(Interreflect, TracingProgressNamesTheBouncesThatFollow) {
    const Mesh mesh = make_builtin("box_on_plane");
    for (const bool converge : {false, true}) {
        BakeOptions o = ir_options(4, 64, 3);
        o.converge = converge;
        std::vector<std::pair<std::string, std::string>> seen;  // stage, then
        o.progress = [&](const ProgressInfo& p) {
            seen.emplace_back(std::string(p.stage), std::string(p.then));
            return true;
        };
        bake(mesh, o);
        bool direct = false, tracing = false, bounces = false;
        for (const auto& [stage, then] : seen) {
            if (stage == "bake") {  // T_0, then the bounce sources' rays, then the bounces
                direct = true;
                EXPECT_EQ(then,
                          converge ? "bounce sources + bounces" : "bounce sources + 3 bounces");
            } else if (stage == "bounce sources") {
                tracing = true;
                EXPECT_EQ(then, converge ? "bounces" : "3 bounces");
            } else {
                bounces = true;
                EXPECT_EQ(stage, "bounces");
                EXPECT_EQ(then, "");
            }
        }
        EXPECT_TRUE(direct);
        EXPECT_TRUE(tracing);
        EXPECT_TRUE(bounces);
    }
}

TEST(Interreflect, ClosestHitsAreIntersect) {
    const Mesh mesh = make_builtin("box_on_plane");
    const auto tracer = make_embree_tracer(mesh);
    const DirectionSet d = make_direction_set(SamplerKind::sobol, 1, 600);
    std::vector<Vec3f> dirs;
    for (std::size_t s = 0; s < d.size(); ++s)
        dirs.push_back({d.dirs[3 * s], d.dirs[3 * s + 1], d.dirs[3 * s + 2]});
    const Vec3f origin{0.7f, 0.3f, -1.1f};
    std::vector<Hit> hits(dirs.size());
    constexpr float kInf = std::numeric_limits<float>::infinity();
    tracer->closest_hits(origin, dirs.data(), int(dirs.size()), 0.0f, kInf, hits.data());
    int hit_count = 0;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        const Hit one = tracer->intersect(origin, dirs[i], 0.0f, kInf);
        ASSERT_EQ(hits[i].hit, one.hit) << i;
        if (!one.hit) continue;
        ++hit_count;
        EXPECT_EQ(hits[i].triangle, one.triangle);
        EXPECT_EQ(hits[i].t, one.t);
    }
    EXPECT_GT(hit_count, 100);
}

// A triangle's grid (transport_build.hpp): every point (i, j), i + j ≤ n, has its own index —
// the corners the triangle's vertices, the others base .. base + own − 1 — and the cell that holds
// (u, v) gives weights that sum to 1, are not negative, and rebuild the point from its corners.
TEST(Interreflect, GridCellsInterpolateThePoint) {
    const std::uint32_t tri[3] = {7, 3, 5};
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (const std::uint32_t n : {1u, 2u, 3u, 7u, 40u}) {
        const std::uint32_t base = 100;
        std::vector<std::uint32_t> seen;
        for (std::uint32_t j = 0; j <= n; ++j)
            for (std::uint32_t i = 0; i + j <= n; ++i)
                seen.push_back(grid_point_index(tri, base, n, i, j));
        std::sort(seen.begin(), seen.end());
        ASSERT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end()) << "n = " << n;
        ASSERT_EQ(seen.size(), 3 + grid_own_points(n));
        EXPECT_EQ(seen[0], 3u);
        EXPECT_EQ(seen[2], 7u);
        if (n > 1) EXPECT_EQ(seen.back(), base + grid_own_points(n) - 1);
        for (int k = 0; k < 2000; ++k) {
            float u = u01(rng), v = u01(rng);
            if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
            const GridCell c = grid_cell(n, u, v);
            float sum = 0, x = 0, y = 0;
            for (int q = 0; q < 3; ++q) {
                EXPECT_GE(c.weight[q], -1e-5f);
                ASSERT_LE(c.i[q] + c.j[q], n);
                sum += c.weight[q];
                x += c.weight[q] * float(c.i[q]) / float(n);
                y += c.weight[q] * float(c.j[q]) / float(n);
            }
            EXPECT_NEAR(sum, 1.0f, 1e-5f);
            EXPECT_NEAR(x, u, 1e-5f) << "n = " << n;
            EXPECT_NEAR(y, v, 1e-5f) << "n = " << n;
        }
    }
}

// The GPU's build of one block of A (transport_build.hpp; src/bake/cuda/transport_kernels.cu) run
// on the host: the kernels' per-index steps in loops, std::stable_sort for cub's (stable) radix
// sort of the keys with their indices, std::exclusive_scan for cub's scan of the kept flags.
TransportOperator::Block device_build_on_host(const Mesh& mesh, const BounceSources& sources,
                                              const DirectionSet& d, bool two_sided,
                                              std::size_t first, std::size_t count,
                                              const SampleHit* hits) {
    TransportBuildView b;
    b.mesh = sources.view(mesh);
    b.normals = sources.normals.data();
    b.dirs = d.dirs.data();
    b.weights = d.weights.data();
    b.hits = hits;
    b.first = std::uint32_t(first);
    b.count = std::uint32_t(count);
    b.samples = std::uint32_t(d.size());
    b.vertices = std::uint32_t(sources.size());
    b.two_sided = two_sided;
    const std::size_t n = b.entries();
    std::vector<std::uint64_t> keys(n);
    std::vector<std::uint32_t> order(n), kept(n), slot(n);
    std::vector<float> values(3 * n), sums(3 * n);
    for (std::uint32_t i = 0; i < count * d.size(); ++i)
        transport_sample_entries(b, i, keys.data(), order.data(), values.data());
    EXPECT_LT(b.no_entry(), std::uint64_t(1) << transport_key_bits(b));
    std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs(n);
    for (std::size_t e = 0; e < n; ++e) pairs[e] = {keys[e], order[e]};
    std::stable_sort(pairs.begin(), pairs.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t e = 0; e < n; ++e) std::tie(keys[e], order[e]) = pairs[e];
    for (std::uint32_t p = 0; p < n; ++p)
        transport_run_sum(p, std::uint32_t(n), keys.data(), order.data(), values.data(),
                          b.no_entry(), sums.data(), kept.data());
    std::exclusive_scan(kept.begin(), kept.end(), slot.begin(), 0u);
    const std::uint32_t nnz = n ? slot[n - 1] + kept[n - 1] : 0;
    TransportOperator::Block out;
    out.first = first;
    std::vector<std::uint64_t> out_keys(nnz);
    out.column.resize(nnz);
    for (auto& v : out.values) v.resize(nnz);
    for (std::uint32_t p = 0; p < n; ++p)
        transport_compact(p, keys.data(), kept.data(), slot.data(), sums.data(), b.vertices,
                          out_keys.data(), out.column.data(), out.values[0].data(),
                          out.values[1].data(), out.values[2].data());
    out.row_start.resize(count + 1);
    for (std::uint32_t j = 0; j <= count; ++j)
        out.row_start[j] = transport_row_start(j, out_keys.data(), nnz, b.vertices);
    return out;
}

// The GPU bake's path to A, emulated on the CPU: the kernel's closest_hit_sample over the flat
// BVH (its W is transfer_sample's, bit for bit) gives sample-major hit records, and the device
// build's steps (device_build_on_host) turn them into the same bits as build_transport_operator
// with a tracer over the same flat BVH — for the vertices alone, their back copies, and bounce
// sources with cells (the mapping of a hit to its cell is the shared transport_hit_entries).
TEST(Interreflect, KernelHitRecordsGiveTheOperatorsBits) {
    Mesh mesh = make_builtin("box_on_plane");
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        mesh.albedo[v] = {0.9f, 0.5f, float(v % 5) / 5.0f};
    const DirectionSet d = make_direction_set(SamplerKind::sobol, 4, 300);
    const std::size_t S = d.size();
    const FlatBvh bvh = build_flat_bvh(mesh);
    const auto tracer = make_flat_bvh_tracer(mesh);
    TransportOptions to;
    to.rows_per_block = 37;  // blocks that do not divide V
    constexpr float kVertices = std::numeric_limits<float>::infinity();
    for (const auto& [two_sided, spacing] :
         {std::pair{false, kVertices}, std::pair{true, kVertices}, std::pair{true, 0.1f}}) {
        to.two_sided = two_sided;
        const BounceSources sources = make_bounce_sources(mesh, spacing, two_sided);
        const TransportOperator A = spacing == kVertices
                                        ? build_transport_operator(mesh, d, *tracer, to)
                                        : build_source_operator(mesh, sources, d, *tracer, to);
        ASSERT_EQ(A.vertices, sources.size());
        ASSERT_GT(A.nnz(), 0u);
        std::size_t hits_seen = 0;
        for (const TransportOperator::Block& b : A.blocks) {
            const std::size_t count = b.rows();
            std::vector<SampleHit> hits(S * count);
            for (std::size_t j = 0; j < count; ++j) {
                const std::size_t v = b.first + j;
                const Vec3f p = sources.positions[v], n = sources.normals[v];
                for (std::size_t s = 0; s < S; ++s) {
                    const Vec3f w{d.dirs[3 * s], d.dirs[3 * s + 1], d.dirs[3 * s + 2]};
                    bool cast = false, cast2 = false;
                    const float value = closest_hit_sample(bvh.view(), p, n, w, d.weights[s], cast,
                                                           hits[s * count + j]);
                    const float shadowed =
                        transfer_sample(bvh.view(), p, n, w, d.weights[s], true, cast2);
                    ASSERT_EQ(value, shadowed) << v << " " << s;
                    ASSERT_EQ(cast, cast2);
                    hits_seen += hits[s * count + j].triangle != kNoTriangle;
                }
            }
            const TransportOperator::Block got =
                device_build_on_host(mesh, sources, d, two_sided, b.first, count, hits.data());
            EXPECT_EQ(got.first, b.first);
            EXPECT_EQ(got.row_start, b.row_start) << "block at " << b.first;
            EXPECT_EQ(got.column, b.column) << "block at " << b.first;
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(got.values[c], b.values[c]) << "block at " << b.first << " channel " << c;
        }
        EXPECT_GT(hits_seen, 1000u);
    }
}

// White furnace: ρ = 1 in a cavity under a constant sky of 1: E_N rises with N at every vertex
// and tends to π (to the direction set's cosine quadrature error).
TEST(Interreflect, WhiteFurnaceCavityTendsToPiMonotonically) {
    const Mesh cavity = test::spherical_cavity(3, 0.5, {1, 1, 1});
    std::vector<std::vector<double>> E;  // [N][v]
    for (int N : {0, 1, 2, 4, 8}) {
        const TransferSet t = bake(cavity, exact_options(1, 4096, N));
        std::vector<double> e(cavity.vertex_count());
        for (std::size_t v = 0; v < e.size(); ++v) e[v] = constant_sky_E(t, v, 0);
        E.push_back(e);
    }
    for (std::size_t n = 1; n < E.size(); ++n)
        for (std::size_t v = 0; v < cavity.vertex_count(); ++v)
            ASSERT_GT(E[n][v], E[n - 1][v]) << "step " << n << " vertex " << v;
    BakeOptions conv = exact_options(1, 4096, 0);
    conv.converge = true;
    conv.tolerance = 1e-6;
    const TransferSet t = bake(cavity, conv);
    EXPECT_TRUE(t.interreflection.converged);
    EXPECT_GT(t.interreflection.bounces, 20);
    double worst = 0;
    for (std::size_t v = 0; v < cavity.vertex_count(); ++v)
        worst = std::max(worst, std::abs(constant_sky_E(t, v, 0) - kPi) / kPi);
    // Named tolerance: the 4096-direction Sobol set integrates the clamped cosine to ~1e-3; the
    // rim vertices' rays graze the cut edge.
    EXPECT_LT(worst, 0.01) << "E_inf should be pi at every vertex";
    EXPECT_GT(E[4][0], E[0][0] * 2.0);  // the bounces matter here (f ≈ 0.25)
}

// The analytic cavity with albedo ρ = (0.3, 0.6, 0.9): E_N = E_0·Σ_{b≤N} (ρ(1−f))^b per channel
// and E_∞ = E_0 / (1 − ρ(1 − f)), with f = E_0/π measured from T_0 at each vertex.
TEST(Interreflect, SphericalCavityMatchesTheClosedForm) {
    const Vec3f rho{0.3f, 0.6f, 0.9f};
    const Mesh cavity = test::spherical_cavity(3, 0.5, rho);
    for (int N : {1, 3}) {
        const TransferSet t = bake(cavity, exact_options(1, 4096, N));
        double worst = 0;
        for (std::size_t v = 0; v < cavity.vertex_count(); ++v) {
            const double E0 = double(t.direct[v]) * 2.0 * std::sqrt(kPi);
            for (int c = 0; c < 3; ++c) {
                const double expect = cavity_closed_form(E0, rho[c], N);
                worst = std::max(worst, std::abs(constant_sky_E(t, v, c) - expect) / expect);
            }
        }
        // Named tolerance: f varies by about 1% over the vertices (flat triangles, a jagged cut),
        // and the closed form takes each vertex's own f for the whole cavity.
        EXPECT_LT(worst, 0.02) << "N = " << N;
    }
    BakeOptions conv = exact_options(1, 4096, 0);
    conv.converge = true;
    const TransferSet t = bake(cavity, conv);
    EXPECT_TRUE(t.interreflection.converged);
    double worst = 0;
    for (std::size_t v = 0; v < cavity.vertex_count(); ++v) {
        const double E0 = double(t.direct[v]) * 2.0 * std::sqrt(kPi);
        const double f = E0 / kPi;
        for (int c = 0; c < 3; ++c) {
            const double expect = E0 / (1.0 - double(rho[c]) * (1.0 - f));
            worst = std::max(worst, std::abs(constant_sky_E(t, v, c) - expect) / expect);
        }
    }
    EXPECT_LT(worst, 0.03);
}

// The same closed form with the default discretisation's pieces: bounce sources on cells of
// 0.1 m (two to three per edge of the icosphere's triangles, so most sources are the cells' own
// points, traced with a quarter of the receivers' directions) and the final gather's prefix.
TEST(Interreflect, GridSourcesMatchTheClosedForm) {
    const Vec3f rho{0.3f, 0.6f, 0.9f};
    const Mesh cavity = test::spherical_cavity(3, 0.5, rho);
    BakeOptions o = ir_options(1, 4096, 3);
    o.source_spacing = 0.1f;
    o.indirect_samples = 2048;
    const TransferSet t = bake(cavity, o);
    EXPECT_GT(t.interreflection.sources, 3 * cavity.vertex_count());
    EXPECT_EQ(t.interreflection.invalid_sources, 0u);
    double sum2 = 0, worst = 0;
    for (std::size_t v = 0; v < cavity.vertex_count(); ++v) {
        const double E0 = double(t.direct[v]) * 2.0 * std::sqrt(kPi);
        for (int c = 0; c < 3; ++c) {
            const double expect = cavity_closed_form(E0, rho[c], 3);
            const double e = (constant_sky_E(t, v, c) - expect) / expect;
            sum2 += e * e;
            worst = std::max(worst, std::abs(e));
        }
    }
    const double rms = std::sqrt(sum2 / double(3 * cavity.vertex_count()));
    // Named tolerances: the closed form's 1 % (each vertex's own f, as above) plus the final
    // gather's noise at 2048 directions (about 1 % RMS of the bounces, 2.5 % at the worst vertex).
    EXPECT_LT(rms, 0.01);
    EXPECT_LT(worst, 0.035);
}

// One-sided surfaces: a floor under a panel whose front faces up sees only the panel's back, so
// nothing bounces down; two-sided, the panel's underside sends the panel's light.
TEST(Interreflect, BackFacesBringNothingUnlessTwoSided) {
    MeshBuilder b;
    b.add_rect(Axis::y, 0.0, +1, {-2, 2, -2, 2}, 0.5, {0.8f, 0.8f, 0.8f});
    b.add_rect(Axis::y, 0.5, +1, {-1, 1, -1, 1}, 0.5, {0.8f, 0.8f, 0.8f});
    const Mesh mesh = b.take_mesh("test:panel");
    const TransferSet one = bake(mesh, ir_options(4, 512, 2));
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 4; ++i)
                ASSERT_EQ(one.receiver(v, c)[i], one.direct[v * 4 + i]) << v;
    EXPECT_EQ(one.interreflection.operator_nnz, 0u);
    BakeOptions two_sided = ir_options(4, 512, 2);
    two_sided.two_sided = true;
    const TransferSet two = bake(mesh, two_sided);
    EXPECT_GT(two.interreflection.operator_nnz, 0u);
    // Two-sided, the panel's underside sends the ground's light back: the ground gains.
    double with = 0, without = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        with += constant_sky_E(two, v, 0);
        without += double(two.direct[v * 4]) * 2.0 * std::sqrt(kPi);
    }
    EXPECT_GT(with, without * 1.001);
}

// The independent estimate: a path tracer over the same discretisation (radiance at a hit is the
// barycentric mix of its vertices', chosen stochastically) with the same tracer, cosine-sampled
// directions from the vertex's offset origin, under a band-limited light (so that the bake's
// E = Σ_i c_T[i]·l_i is exact but for its own sampling). Returns E and its standard error per
// channel.
struct Estimate {
    double E[3], sigma[3];
};

Estimate path_trace(const Mesh& mesh, const Tracer& tracer, std::size_t v0, int N, int K,
                    const std::vector<double>& light, int paths, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    double sum[3] = {}, sum2[3] = {};
    std::vector<double> y(K);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (int p = 0; p < paths; ++p) {
        std::size_t x = v0;
        double throughput[3] = {1, 1, 1};
        double value[3] = {0, 0, 0};
        for (int depth = 0; depth <= N; ++depth) {
            // Cosine-weighted direction about n (Malley): pdf cos/π.
            const Vec3d n = cast<double>(mesh.normals[x]);
            const Vec3d a = std::abs(n.x) > 0.5 ? Vec3d{0, 1, 0} : Vec3d{1, 0, 0};
            const Vec3d t1 = normalize(cross(a, n));
            const Vec3d t2 = cross(n, t1);
            const double r = std::sqrt(u01(rng)), phi = 2 * kPi * u01(rng);
            const double z = std::sqrt(std::max(0.0, 1 - r * r));
            const Vec3d w = t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) + n * z;
            const Vec3f wf = cast<float>(w);
            const Hit h = tracer.intersect(offset_ray_origin(mesh.positions[x], mesh.normals[x]),
                                           wf, 0.0f, kInf);
            if (!h.hit) {  // escapes: π·L(ω) estimates ∫ L cos dω
                sh_eval_k<double>(K, w.x, w.y, w.z, y.data());
                for (int c = 0; c < 3; ++c) {
                    double L = 0;
                    for (int i = 0; i < K; ++i) L += light[c * K + i] * y[i];
                    value[c] = throughput[c] * kPi * L;
                }
                break;
            }
            if (depth == N) break;
            const auto& tri = mesh.triangles[h.triangle];
            const Vec3f p0 = mesh.positions[tri[0]];
            const Vec3f face = cross(mesh.positions[tri[1]] - p0, mesh.positions[tri[2]] - p0);
            if (dot(face, wf) >= 0.0f) break;  // a back face sends nothing
            const double bary[3] = {1.0 - h.u - h.v, h.u, h.v};
            // ρ(h)/π · T(h) with pdf cos/π: the weight is ρ(h); T(h) = Σ b_k T(k), one k drawn.
            for (int c = 0; c < 3; ++c) {
                double rho = 0;
                for (int k = 0; k < 3; ++k) rho += bary[k] * double(mesh.albedo[tri[k]][c]);
                throughput[c] *= rho;
            }
            const double pick = u01(rng);
            x = pick < bary[0] ? tri[0] : (pick < bary[0] + bary[1] ? tri[1] : tri[2]);
        }
        for (int c = 0; c < 3; ++c) {
            sum[c] += value[c];
            sum2[c] += value[c] * value[c];
        }
    }
    Estimate e{};
    for (int c = 0; c < 3; ++c) {
        e.E[c] = sum[c] / paths;
        const double var = std::max(0.0, sum2[c] / paths - e.E[c] * e.E[c]);
        e.sigma[c] = std::sqrt(var / paths);
    }
    return e;
}

TEST(Interreflect, AgreesWithABruteForcePathTracer) {
    // A box on a floor, coloured: the floor reddish, the box bluish.
    Mesh mesh = make_builtin("box_on_plane");
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        mesh.albedo[v] =
            mesh.positions[v].y > 1e-4f ? Vec3f{0.2f, 0.4f, 0.9f} : Vec3f{0.9f, 0.6f, 0.3f};
    const int K = 9;
    // A band-limited sky: a constant plus linear and quadratic terms per channel.
    const std::vector<double> light = {3.5, 0.4, 1.2, 0.3, 0.1, 0.2, 0.3, 0.1, 0.2,   // R
                                       3.0, 0.2, 1.0, 0.1, 0.2, 0.1, 0.2, 0.2, 0.1,   // G
                                       2.5, 0.1, 0.8, 0.2, 0.1, 0.3, 0.1, 0.1, 0.3};  // B
    const auto tracer = make_embree_tracer(mesh);
    // Receivers where the bounces matter: floor vertices at the foot of the box, box vertices
    // near the floor.
    std::vector<std::size_t> probes, floor_probes;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const Vec3f p = mesh.positions[v];
        const bool floor_near_box =
            p.y == 0.0f && std::abs(p.x) > 0.5f && std::abs(p.x) < 0.8f && std::abs(p.z) < 0.3f;
        const bool box_low = p.y > 0.05f && p.y < 0.3f && std::abs(p.z) < 0.3f &&
                             std::abs(std::abs(p.x) - 0.5f) < 1e-4f;
        if (floor_near_box && floor_probes.size() < 2) floor_probes.push_back(v);
        if (box_low && probes.size() < 2) probes.push_back(v);
    }
    probes.insert(probes.end(), floor_probes.begin(), floor_probes.end());
    ASSERT_EQ(probes.size(), 4u);
    for (int N : {1, 3}) {
        BakeOptions o = exact_options(K, 16384, N);
        const TransferSet t =
            bake_with_tracer(mesh, o, make_direction_set(o.sampler, o.seed, 16384), *tracer);
        for (std::size_t v : probes) {
            const Estimate e = path_trace(mesh, *tracer, v, N, K, light, 200000, 17 + v);
            for (int c = 0; c < 3; ++c) {
                double E = 0;
                for (int i = 0; i < K; ++i) E += double(t.receiver(v, c)[i]) * light[c * K + i];
                // Named tolerance: 4 standard errors of the path tracer plus 0.5% for the bake's
                // own 16384-direction quadrature.
                const double tol = 4 * e.sigma[c] + 0.005 * std::abs(e.E[c]);
                EXPECT_NEAR(E, e.E[c], tol) << "N = " << N << " vertex " << v << " channel " << c
                                            << " sigma " << e.sigma[c];
            }
        }
    }
}

// The AVX2 kernel and Eigen's product give the same bits (same multiplies and adds, same order),
// for any thread count, with K not a multiple of the vector width.
TEST(Interreflect, KernelsGiveTheSameBits) {
    Mesh mesh = make_builtin("box_on_plane");
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        mesh.albedo[v] = {0.9f, 0.5f, float(v % 7) / 7.0f};
    const auto tracer = make_embree_tracer(mesh);
    const DirectionSet d = make_direction_set(SamplerKind::sobol, 1, 256);
    TransportOptions to;
    to.threads = 2;
    const TransportOperator A = build_transport_operator(mesh, d, *tracer, to);
    ASSERT_GT(A.nnz(), 0u);
    for (int K : {1, 13, 16}) {
        std::vector<float> x(mesh.vertex_count() * 3 * std::size_t(K));
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = float(i % 101) * 0.01f - 0.3f;
        std::vector<float> eigen1(x.size()), eigen2(x.size());
        apply_transport(A, x.data(), eigen1.data(), K, 1, TransportKernel::eigen);
        apply_transport(A, x.data(), eigen2.data(), K, 2, TransportKernel::eigen);
        EXPECT_EQ(std::memcmp(eigen1.data(), eigen2.data(), x.size() * 4), 0) << K;
        if (!__builtin_cpu_supports("avx2")) continue;
        std::vector<float> avx1(x.size()), avx2(x.size());
        apply_transport(A, x.data(), avx1.data(), K, 1, TransportKernel::avx2);
        apply_transport(A, x.data(), avx2.data(), K, 2, TransportKernel::avx2);
        EXPECT_EQ(std::memcmp(avx1.data(), eigen1.data(), x.size() * 4), 0) << K;
        EXPECT_EQ(std::memcmp(avx2.data(), eigen1.data(), x.size() * 4), 0) << K;
    }
}

TEST(Interreflect, RefusesWhatItCannotDo) {
    const Mesh mesh = make_builtin("plane");
    BakeOptions o = ir_options(4, 64, 1);
    EXPECT_THROW(bake(mesh, vertex_receivers(mesh).range(0, 10), o), Error);
    o.bounces = -1;
    EXPECT_THROW(bake(mesh, o), Error);
    o.bounces = 1;
    o.tolerance = 0;
    EXPECT_THROW(bake(mesh, o), Error);
}

}  // namespace
}  // namespace shprt
