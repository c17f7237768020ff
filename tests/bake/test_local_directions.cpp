// The local direction set (DirectionFrame::local, docs/sampling.md "The local set"): one
// cosine-weighted set in every receiver's tangent frame, projected by the same GEMM and rotated to
// world space per receiver. Tested by identity (an unoccluded receiver's c00 is exact at any S),
// against the slow reference that evaluates the basis at the world directions (no rotation; K not
// a square), against the sphere set at high S within the noise of the sphere set itself (every
// kind), and for determinism.
#include "bake/bake_test_util.hpp"
#include "bake/linear_light.hpp"
#include "shprt/bake/bake_option_table.hpp"
#include "shprt/bake/request.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/zonal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace shprt {
namespace {

constexpr double kPi = 3.14159265358979323846;
// y_00·π: the c00 of an unoccluded receiver, ∫ max(0, n·w)·y_00 dw.
const double kUnoccludedC00 = kPi * 0.5 / std::sqrt(kPi);
// Float rounding of a sum of S equal terms and a rotation in double: relative.
constexpr double kC00Tolerance = 2e-6;
// Fast path (float GEMM, rotation in double) against the double reference, absolute, for
// coefficients of order 1 at S ≤ 512.
constexpr double kReferenceTolerance = 1e-4;

BakeOptions local_options(TransferKind kind, int K, std::uint32_t S) {
    BakeOptions o;
    o.transfer = kind;
    o.K = K;
    o.samples = S;
    o.threads = 2;
    o.direction_frame = DirectionFrame::local;
    return o;
}

// sqrt(Σ(a − b)² / Σ b²) over every float of two results.
double relative_rms(const std::vector<float>& a, const std::vector<float>& b) {
    EXPECT_EQ(a.size(), b.size());
    double num = 0, den = 0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        num += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
        den += double(b[i]) * b[i];
    }
    return std::sqrt(num / den);
}

// 40 receivers at one point with normals spread over the sphere (a spherical Fibonacci set).
void every_orientation(std::vector<Vec3f>& positions, std::vector<Vec3f>& normals) {
    for (int i = 0; i < 40; ++i) {
        const double z = 1 - (2 * i + 1) / 40.0, phi = 2.39996322972865332 * i;
        const double r = std::sqrt(1 - z * z);
        positions.push_back(Vec3f{0, 5, 0});
        normals.push_back(Vec3f{float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)});
    }
}

TEST(LocalDirections, SetsAreOnTheHemisphereWithTheirDensity) {
    for (const SamplerKind kind : kAllSamplerKinds) {
        const DirectionSet cosine =
            make_local_direction_set(kind, 3, 4096, HemisphereDensity::cosine);
        const DirectionSet uniform =
            make_local_direction_set(kind, 3, 4096, HemisphereDensity::uniform);
        double mean_c = 0, mean_u = 0;
        for (std::size_t s = 0; s < 4096; ++s) {
            const float* c = &cosine.dirs[3 * s];
            const float* u = &uniform.dirs[3 * s];
            ASSERT_GE(c[2], 0.0f);
            ASSERT_GE(u[2], 0.0f);
            EXPECT_NEAR(c[0] * c[0] + c[1] * c[1] + c[2] * c[2], 1.0, 1e-6);
            EXPECT_NEAR(u[0] * u[0] + u[1] * u[1] + u[2] * u[2], 1.0, 1e-6);
            mean_c += c[2] / 4096.0;
            mean_u += u[2] / 4096.0;
        }
        // E[cos θ] is 2/3 under cos θ/π and 1/2 under 1/(2π); the uniform sampler's standard
        // error at S = 4096 is about 0.004, the others' far less.
        const double tolerance = kind == SamplerKind::uniform ? 0.02 : 2e-3;
        EXPECT_NEAR(mean_c, 2.0 / 3.0, tolerance) << to_string(kind);
        EXPECT_NEAR(mean_u, 0.5, tolerance) << to_string(kind);
        EXPECT_FLOAT_EQ(cosine.weights[0], float(kPi / 4096));
        EXPECT_FLOAT_EQ(uniform.weights[0], float(2 * kPi / 4096));
    }
    // Nested like the sphere sets they map: the first 64 of Sobol's 4096 are Sobol's 64.
    const DirectionSet big =
        make_local_direction_set(SamplerKind::sobol, 3, 4096, HemisphereDensity::cosine);
    const DirectionSet small =
        make_local_direction_set(SamplerKind::sobol, 3, 64, HemisphereDensity::cosine);
    EXPECT_TRUE(std::equal(small.dirs.begin(), small.dirs.end(), big.dirs.begin()));
}

TEST(LocalDirections, FrameIsARotationThatTakesZToTheNormal) {
    for (const Vec3f n :
         {Vec3f{0, 0, 1}, Vec3f{0, 0, -1}, Vec3f{0, 1, 0}, Vec3f{1, 0, 0},
          normalize(Vec3f{0.3f, -0.5f, 0.8f}), normalize(Vec3f{-1e-4f, 2e-4f, -1})}) {
        const LocalFrame f = local_frame(n);
        EXPECT_NEAR(dot(f.t, f.b), 0.0, 1e-6);
        EXPECT_NEAR(dot(f.t, f.n), 0.0, 1e-6);
        EXPECT_NEAR(dot(f.b, f.n), 0.0, 1e-6);
        EXPECT_NEAR(dot(cross(f.t, f.b), f.n), 1.0, 1e-6);  // right-handed
        EXPECT_NEAR(f.n.x, n.x, 1e-6);
        EXPECT_NEAR(f.n.y, n.y, 1e-6);
        EXPECT_NEAR(f.n.z, n.z, 1e-6);
        // (β, γ) are n's polar angles: R = Rz(γ)·Ry(β) takes +z to n.
        EXPECT_NEAR(std::sin(f.beta) * std::cos(f.gamma), n.x, 1e-6);
        EXPECT_NEAR(std::sin(f.beta) * std::sin(f.gamma), n.y, 1e-6);
        EXPECT_NEAR(std::cos(f.beta), n.z, 1e-6);
    }
}

// Every local direction is above the horizon and weighs π/S, so an unoccluded receiver's c00 is
// π·y00 whatever S — the sphere set only gets it on average.
TEST(LocalDirections, UnoccludedReceiverC00IsExactAtAnyS) {
    const Mesh plane = make_builtin("plane");  // nothing above its vertices
    // Receivers of every orientation for the unshadowed bake (no rays, no occluders hit).
    std::vector<Vec3f> positions, normals;
    every_orientation(positions, normals);
    for (const std::uint32_t S : {1u, 7u, 64u}) {
        const TransferSet shadowed = bake(plane, local_options(TransferKind::shadowed, 16, S));
        for (std::size_t v = 0; v < plane.vertex_count(); ++v)
            ASSERT_NEAR(shadowed.receiver(v)[0], kUnoccludedC00, kC00Tolerance * kUnoccludedC00)
                << "S = " << S << ", vertex " << v;
        const TransferSet open = bake(plane,
                                      Receivers::all(ReceiverDomain::vertex, positions.data(),
                                                     normals.data(), positions.size()),
                                      local_options(TransferKind::unshadowed, 25, S));
        for (std::size_t v = 0; v < positions.size(); ++v)
            ASSERT_NEAR(open.receiver(v)[0], kUnoccludedC00, kC00Tolerance * kUnoccludedC00)
                << "S = " << S << ", receiver " << v;
        // Not a property of every set: the sphere set's c00 at S = 7 is off.
        BakeOptions sphere = local_options(TransferKind::shadowed, 16, S);
        sphere.direction_frame = DirectionFrame::sphere;
        if (S == 7) EXPECT_GT(std::fabs(bake(plane, sphere).receiver(0)[0] - kUnoccludedC00), 1e-3);
    }
}

// The fast path (GEMM in the frame, SH rotation) against bake_reference, which turns each local
// direction into world space and evaluates the basis there: vectors and matrices, K not a square
// (the full last band is rotated, then truncated), on a scene with occlusion.
TEST(LocalDirections, RotationPathEqualsTheWorldSpaceReferenceWithKNotASquare) {
    const Mesh scene = make_builtin("box_on_plane");
    const auto tracer = make_embree_tracer(scene);
    for (const auto& [kind, K, S] : {std::tuple{TransferKind::shadowed, 10, 256u},
                                     std::tuple{TransferKind::shadowed, 16, 256u},
                                     std::tuple{TransferKind::glossy, 5, 128u}}) {
        // The reference is the plain estimator: without the open part (OpenPartExactly below).
        BakeOptions options = local_options(kind, K, S);
        options.open_control = false;
        const DirectionSet set = bake_direction_set(options);
        const TransferSet fast = bake_with_tracer(scene, options, set, *tracer);
        const TransferSet slow = bake_reference(scene, options, set, *tracer);
        ASSERT_EQ(fast.coeffs.size(), slow.coeffs.size());
        double worst = 0, largest = 0;
        for (std::size_t i = 0; i < fast.coeffs.size(); ++i) {
            worst = std::max(worst, std::fabs(double(fast.coeffs[i]) - slow.coeffs[i]));
            largest = std::max(largest, std::fabs(double(slow.coeffs[i])));
        }
        EXPECT_LT(worst, kReferenceTolerance) << to_string(kind) << " K = " << K;
        EXPECT_GT(largest, 0.1);
        EXPECT_EQ(fast.stats.rays_cast, slow.stats.rays_cast);
        // Every direction is traced: S rays per vertex.
        EXPECT_EQ(fast.stats.rays_cast, std::uint64_t(S) * scene.vertex_count());
        // Occlusion happened: some vertex sees less than its unoccluded c00 (M00 for glossy:
        // 2π·y00² = 1/2 unoccluded).
        double least = 1e9;
        for (std::size_t v = 0; v < scene.vertex_count(); ++v)
            least = std::min(least, double(fast.receiver(v)[0]));
        EXPECT_LT(least, 0.8 * (kind == TransferKind::glossy ? 0.5 : kUnoccludedC00));
    }
    // K = 10 rotates the full 4 bands: its rows are the first 10 of K = 16's, bit for bit.
    const TransferSet k10 = bake(scene, local_options(TransferKind::shadowed, 10, 256));
    const TransferSet k16 = bake(scene, local_options(TransferKind::shadowed, 16, 256));
    for (std::size_t v = 0; v < scene.vertex_count(); ++v)
        ASSERT_EQ(std::memcmp(k10.receiver(v), k16.receiver(v), 10 * sizeof(float)), 0) << v;
}

// The open part exactly (docs/sampling.md): an open receiver's whole row, not only its c00, is
// its exact transfer (the clamped cosine turned to its normal: rotate_zonal) at any S; a closed
// receiver's row stays 0; and a scene with partial occlusion is estimated better than by the
// plain estimator at the same S, for vectors and glossy matrices.
TEST(LocalDirections, OpenPartExactly) {
    std::vector<Vec3f> positions, normals;
    every_orientation(positions, normals);
    const Mesh plane = make_builtin("plane");
    const Receivers open =
        Receivers::all(ReceiverDomain::vertex, positions.data(), normals.data(), positions.size());
    const int K = 25;
    const std::vector<double> zonal = clamped_cosine_zonal(5);
    for (const std::uint32_t S : {1u, 7u, 64u}) {
        BakeOptions options = local_options(TransferKind::unshadowed, K, S);
        const TransferSet got = bake(plane, open, options);
        options.open_control = false;
        const TransferSet plain = bake(plane, open, options);
        double worst = 0, worst_plain = 0;
        for (std::size_t v = 0; v < positions.size(); ++v) {
            double exact[25];
            rotate_zonal(zonal.data(), K, Vec3d{normals[v].x, normals[v].y, normals[v].z}, exact);
            for (int i = 0; i < K; ++i) {
                worst = std::max(worst, std::fabs(got.receiver(v)[i] - exact[i]));
                worst_plain = std::max(worst_plain, std::fabs(plain.receiver(v)[i] - exact[i]));
            }
        }
        EXPECT_LT(worst, 1e-5) << "S = " << S;
        EXPECT_GT(worst_plain, 1e-2) << "S = " << S;  // the plain estimator is not exact
    }
    // Occlusion: box_on_plane (the box's underside is closed, its top open, the plane around it
    // partly occluded), against a local bake of S = 16384 with another seed.
    const Mesh scene = make_builtin("box_on_plane");
    for (const auto& [kind, KK] :
         {std::pair{TransferKind::shadowed, 16}, std::pair{TransferKind::glossy, 4}}) {
        BakeOptions options = local_options(kind, KK, 64);
        const TransferSet got = bake(scene, options);
        options.open_control = false;
        const TransferSet plain = bake(scene, options);
        BakeOptions reference = local_options(kind, KK, 16384);
        reference.seed = 7;
        const TransferSet truth = bake(scene, reference);
        std::size_t closed = 0;
        for (std::size_t v = 0; v < scene.vertex_count(); ++v) {
            const std::size_t row = got.layout.floats_per_receiver();
            const bool zero = std::all_of(plain.coeffs.begin() + std::ptrdiff_t(v * row),
                                          plain.coeffs.begin() + std::ptrdiff_t((v + 1) * row),
                                          [](float c) { return c == 0.0f; });
            if (!zero) continue;
            ++closed;
            for (std::size_t i = 0; i < row; ++i) ASSERT_EQ(got.coeffs[v * row + i], 0.0f) << v;
        }
        EXPECT_GT(closed, 0u) << to_string(kind);
        const double error = relative_rms(got.coeffs, truth.coeffs);
        const double error_plain = relative_rms(plain.coeffs, truth.coeffs);
        // Measured: 0.73× (shadowed) and 0.95× (glossy) the plain estimator's error; the rest
        // is the visibility's edge, which the open part does not touch.
        EXPECT_LT(error, (kind == TransferKind::glossy ? 0.99 : 0.8) * error_plain)
            << to_string(kind);
    }
    // An open glossy receiver: its matrix is exact too, so the same at S = 7 as at S = 64.
    const TransferSet g7 = bake(plane, local_options(TransferKind::glossy, 9, 7));
    const TransferSet g64 = bake(plane, local_options(TransferKind::glossy, 9, 64));
    for (std::size_t i = 0; i < g7.coeffs.size(); ++i)
        ASSERT_NEAR(g7.coeffs[i], g64.coeffs[i], 1e-5) << i;
}

// At high S the local and the sphere set estimate the same integrals: their difference is no
// larger than the sphere set's own noise (two seeds of it), for every kind. A wrong rotation or
// weight would be a bias far above that.
struct KindCase {
    const char* name;
    TransferKind kind;
    int K;
    bool texels;
};

std::vector<float> rows_of(const Mesh& mesh, const BakeOptions& options, bool texels,
                           std::vector<float>* direct = nullptr) {
    if (!texels) {
        TransferSet t = bake(mesh, options);
        if (direct) *direct = t.direct;
        return t.coeffs;
    }
    const TexelSamples samples = rasterize_texels(mesh, 24, 24);
    HostSink sink;
    bake(BakeJob{&mesh, texel_receivers(samples), &sink, nullptr, nullptr, nullptr}, options);
    return sink.take_rows();
}

TEST(LocalDirections, AgreesWithTheSphereSetWithinItsNoiseForEveryKind) {
    const KindCase cases[] = {
        {"shadowed", TransferKind::shadowed, 9, false},
        {"glossy", TransferKind::glossy, 9, false},
        {"texels", TransferKind::shadowed, 9, true},
        {"interreflected", TransferKind::interreflected, 9, false},
    };
    for (const KindCase& c : cases) {
        const Mesh mesh = make_builtin(c.texels ? "quad_box" : "box_on_plane");
        BakeOptions local = local_options(c.kind, c.K, 4096);
        BakeOptions sphere = local;
        sphere.direction_frame = DirectionFrame::sphere;
        BakeOptions sphere2 = sphere;
        sphere2.seed = 2;
        std::vector<float> direct_l, direct_s, direct_s2;
        const std::vector<float> l = rows_of(mesh, local, c.texels, &direct_l);
        const std::vector<float> s = rows_of(mesh, sphere, c.texels, &direct_s);
        const std::vector<float> s2 = rows_of(mesh, sphere2, c.texels, &direct_s2);
        const double difference = relative_rms(l, s), noise = relative_rms(s2, s);
        EXPECT_LT(difference, 1.2 * noise)
            << c.name << ": local vs sphere " << difference << ", sphere seed 2 vs 1 " << noise;
        EXPECT_GT(noise, 1e-5) << c.name;            // the seeds do differ
        if (c.kind == TransferKind::interreflected)  // T_0 alone as well
            EXPECT_LT(relative_rms(direct_l, direct_s), 1.2 * relative_rms(direct_s2, direct_s));
        // And the local set is the less noisy: its own two seeds differ less than the sphere's.
        BakeOptions local2 = local;
        local2.seed = 2;
        const double local_noise = relative_rms(rows_of(mesh, local2, c.texels), l);
        EXPECT_LT(local_noise, noise) << c.name;
    }
}

TEST(LocalDirections, SameBitsForOneAndTwoThreadsAndForAShard) {
    const Mesh scene = make_builtin("box_on_plane");
    const Mesh sphere = make_builtin("sphere");
    for (const TransferKind kind : {TransferKind::shadowed, TransferKind::glossy}) {
        BakeOptions one = local_options(kind, kind == TransferKind::glossy ? 5 : 12, 200);
        one.threads = 1;
        one.chunk_receivers = 48;
        BakeOptions two = one;
        two.threads = 2;
        const TransferSet a = bake(scene, one), b = bake(scene, two);
        ASSERT_EQ(a.coeffs.size(), b.coeffs.size());
        EXPECT_EQ(std::memcmp(a.coeffs.data(), b.coeffs.data(), a.coeffs.size() * sizeof(float)), 0)
            << to_string(kind);
        // A range (a shard) gives the whole bake's rows; on the sphere, whose receivers all have
        // other normals (a row rotated with a neighbour's frame would show).
        const std::size_t first = 100, count = 150;
        const TransferSet whole = bake(sphere, two);
        const TransferSet part = bake(sphere, vertex_receivers(sphere).range(first, count), two);
        const std::size_t row = whole.layout.floats_per_receiver();
        EXPECT_EQ(std::memcmp(part.coeffs.data(), whole.coeffs.data() + first * row,
                              count * row * sizeof(float)),
                  0)
            << to_string(kind);
    }
}

TEST(LocalDirections, RecordedInTheFileAndAcceptedOnTheGpu) {
    const Mesh scene = make_builtin("box_on_plane");
    const std::string dir = ::testing::TempDir();
    const std::string local_path = dir + "/local_directions.shprt";
    const std::string sphere_path = dir + "/sphere_directions.shprt";
    BakeOptions options = local_options(TransferKind::shadowed, 4, 16);
    write_shprt(local_path, scene, bake(scene, options));
    EXPECT_EQ(read_shprt(local_path).transfer.direction_frame, DirectionFrame::local);
    options.direction_frame = DirectionFrame::sphere;
    write_shprt(sphere_path, scene, bake(scene, options));
    EXPECT_EQ(read_shprt(sphere_path).transfer.direction_frame, DirectionFrame::sphere);
    std::filesystem::remove(local_path);
    std::filesystem::remove(sphere_path);

    BakeRequest request;
    request.options = local_options(TransferKind::shadowed, 4, 16);
    request.options.device = Device::cuda;
    // The GPU bake has local sets (the kernel's body: TransferSample.EmulatedLocalKernel...).
    EXPECT_FALSE(request_refusal(request).has_value());
    // … and bakes an error bound with them (bake_gpu.cpp), but not with the sphere set, whose
    // receivers' visible rays it cannot read from their rows, nor for interreflected transfer.
    request.options.target_error = 0.01;
    EXPECT_FALSE(request_refusal(request).has_value());
    request.options.direction_frame = DirectionFrame::sphere;
    EXPECT_THAT(request_refusal(request).value_or(""),
                ::testing::HasSubstr("--target-error on the GPU takes a local direction set"));
    request.options.direction_frame = DirectionFrame::local;
    request.options.transfer = TransferKind::interreflected;
    EXPECT_THAT(request_refusal(request).value_or(""),
                ::testing::HasSubstr("interreflected transfer bakes on the CPU"));
    EXPECT_EQ(parse_direction_frame("local"), DirectionFrame::local);
    EXPECT_THROW(parse_direction_frame("tangent"), Error);
}

TEST(LocalDirections, TheDefaultAndACallersSetReadInItsOwnFrame) {
    // The local set is the default (docs/sampling.md, "Which to use"), and a set a caller makes
    // says which frame it is in: a sphere set given to a bake whose options name the local frame
    // is still read on the sphere, so no caller-made set changes meaning with the default.
    EXPECT_EQ(BakeOptions{}.direction_frame, DirectionFrame::local);
    // The command line's and Python's default (one table) is the library's.
    EXPECT_EQ(bake_options_from(BakeOptionChoice{}, Spelling::command_line).direction_frame,
              DirectionFrame::local);
    EXPECT_EQ(make_direction_set(SamplerKind::sobol, 1, 8).frame, DirectionFrame::sphere);
    EXPECT_EQ(make_local_direction_set(SamplerKind::sobol, 1, 8, HemisphereDensity::cosine).frame,
              DirectionFrame::local);
    const Mesh scene = make_builtin("box_on_plane");
    BakeOptions options;
    options.K = 9;
    options.samples = 64;
    const DirectionSet sphere = make_direction_set(options.sampler, options.seed, 64);
    const TransferSet given = bake(scene, options, sphere);
    EXPECT_EQ(given.direction_frame, DirectionFrame::sphere);
    BakeOptions on_sphere = options;
    on_sphere.direction_frame = DirectionFrame::sphere;
    EXPECT_EQ(given.coeffs, bake(scene, on_sphere).coeffs);
    const auto tracer = make_embree_tracer(scene);
    const TransferSet reference = bake_reference(scene, options, sphere, *tracer);
    EXPECT_EQ(reference.direction_frame, DirectionFrame::sphere);
    double worst = 0;
    for (std::size_t i = 0; i < given.coeffs.size(); ++i)
        worst = std::max(worst, std::fabs(double(given.coeffs[i]) - reference.coeffs[i]));
    EXPECT_LT(worst, 1e-4) << "the reference reads the set on the sphere too";
    // The default bake is the local one, and differs from the sphere bake at the same S.
    const TransferSet by_default = bake(scene, options);
    EXPECT_EQ(by_default.direction_frame, DirectionFrame::local);
    EXPECT_NE(by_default.coeffs, given.coeffs);
}

}  // namespace
}  // namespace shprt
