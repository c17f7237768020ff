// CPU shading (shade/shade.hpp): white furnace through bake → file → light → shade, irradiance
// of a linear sky with its truncation error, the glossy term against brute-force integrals over
// directions, K' truncation, RGB transfer channels, input checks.
#include "shade_test_util.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/shade/sun_shade.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

namespace shprt {
namespace {

// float32 coefficients and a double dot product: E is exact to a few float ulps of π.
constexpr double kFloatTolerance = 2e-6;
// A sun kept out of the SH sum against the all-SH shading of a 15° sun at K = 256 (16 bands): the
// RMS of the difference over the RMS of the traced sun. Measured 0.079, 0.018 and 0.0050 at
// K = 16, 64 and 256 (ShadeSun.SplitEqualsAllShAsTheBandsGrow prints them); the bounced sun is
// 0.108 of the direct.
constexpr double kSunSplitTolerance = 0.01;
// Glossy term vs brute force: float32 coefficients (~3e-6 observed) plus the lobe's truncation.
constexpr double kGlossyTolerance = 2e-5;

// Monte Carlo with the paper's uniform set: per vertex, E = (4π/S)·Σ_j max(0, n·ω_j); its
// standard deviation is σ = π·sqrt(5/3)/sqrt(S) (E[X²] = 16π²·(1/4π)·(2π/3), Var = 5π²/3).
double furnace_sigma(std::uint32_t samples) {
    return kPi * std::sqrt(5.0 / 3.0) / std::sqrt(double(samples));
}

TEST(ShadeFurnace, AnalyticUnoccludedTransferGivesPiForEveryBasisSize) {
    // With a constant sky only c_0 of the light is non-zero, so E = T_0·sqrt(4π) and the SH
    // truncation of the clamped cosine contributes nothing: the bound is 0 for every K ≥ 1
    // (T_0 = sqrt(π)/2 exactly); only float rounding remains.
    const Mesh sphere = make_builtin("sphere");
    for (int K : {1, 4, 9, 16, 48, 64}) {
        const TransferSet t = test::analytic_transfer(sphere, K);
        const ShLight light = make_light({"constant"}, K);
        const ShadeResult r = shade_vertices(sphere, t, light, {});
        for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
            for (int c = 0; c < 3; ++c) {
                ASSERT_NEAR(r.irradiance[v][c], kPi, kFloatTolerance * kPi)
                    << "K " << K << " v " << v;
                // L = albedo/π · E = albedo.
                ASSERT_NEAR(r.radiance[v][c], sphere.albedo[v][c], 1e-6) << "K " << K;
            }
        }
    }
}

TEST(ShadeFurnace, BakedSphereThroughFileGivesPiWithinMonteCarloError) {
    test::TempDir dir;
    const Mesh sphere = make_builtin("sphere");
    BakeOptions options;
    options.transfer = TransferKind::unshadowed;
    options.K = 16;
    options.samples = 4096;
    options.sampler = SamplerKind::uniform;
    options.seed = 7;
    write_shprt(dir.file("sphere.shprt"), sphere, bake(sphere, options));
    const ShprtFile file = read_shprt(dir.file("sphere.shprt"));
    const ShLight light = make_light({"constant"}, file.transfer.layout.K);
    const ShadeResult r = shade_vertices(file.mesh, file.transfer, light, {});

    const double bound = 5 * furnace_sigma(options.samples);  // 5σ = 0.32 for S = 4096
    double mean = 0;
    for (std::size_t v = 0; v < file.mesh.vertex_count(); ++v) {
        ASSERT_NEAR(r.irradiance[v].x, kPi, bound) << "vertex " << v;
        ASSERT_EQ(r.irradiance[v].x, r.irradiance[v].y);  // white light, grey transfer
        mean += r.irradiance[v].x;
    }
    mean /= double(file.mesh.vertex_count());
    // All vertices share one direction set and their normals cover the sphere evenly, so the
    // average over vertices is π up to the normals' discretisation, far below σ.
    EXPECT_NEAR(mean, kPi, 0.01 * kPi);
}

TEST(ShadeFurnace, QuadratureBakeGivesPiAtEveryVertexShadowedOrNot) {
    // An exact product quadrature in place of Monte Carlo: the only error left is the
    // quadrature of the kink of max(0, n·ω), well below 1e-3 with 64 × 128 nodes. The sphere is
    // convex, so the shadowed bake sees no occluder either.
    const Mesh sphere = make_builtin("sphere");
    const DirectionSet quad = gauss_legendre_set(64, 128);
    for (TransferKind kind : {TransferKind::unshadowed, TransferKind::shadowed}) {
        for (int K : {16, 48}) {
            BakeOptions options;
            options.transfer = kind;
            options.K = K;
            const TransferSet t = bake(sphere, options, quad);
            const ShadeResult r = shade_vertices(sphere, t, make_light({"constant"}, K), {});
            for (std::size_t v = 0; v < sphere.vertex_count(); ++v)
                ASSERT_NEAR(r.irradiance[v].x, kPi, 1e-3 * kPi) << to_string(kind) << " K " << K;
        }
    }
}

TEST(ShadeIrradiance, LinearSkyIsExactFromFourCoefficientsAndOffByTheTruncationBelow) {
    // Sky L(ω) = 1 + a·ω. Irradiance at normal n: π + (2π/3)·a·n, exact once band 1 is present
    // (K ≥ 4: the sky has no higher bands, so truncating the transfer costs nothing). With K = 1
    // the clamped cosine loses its band-1 part and the error is exactly (2π/3)·|a·n|.
    const Mesh sphere = make_builtin("sphere");
    const Vec3d a{0.3, -0.5, 0.2};
    ShLight light = ShLight::zero(16);
    double y[4];
    const Vec3d axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double b[4][3];  // y_i(ω) = b_i·ω for i = 1..3 (linear in ω)
    for (int k = 0; k < 3; ++k) {
        sh_eval_k(4, axes[k].x, axes[k].y, axes[k].z, y);
        for (int i = 1; i < 4; ++i) b[i][k] = y[i];
    }
    for (int c = 0; c < 3; ++c) {
        light.channel(c)[0] = static_cast<float>(std::sqrt(4 * kPi));
        // ∫ (a·ω)(b·ω) dω = (4π/3) a·b.
        for (int i = 1; i < 4; ++i)
            light.channel(c)[i] =
                static_cast<float>(4 * kPi / 3 * (a.x * b[i][0] + a.y * b[i][1] + a.z * b[i][2]));
    }
    const TransferSet t16 = test::analytic_transfer(sphere, 16);
    const ShadeResult full = shade_vertices(sphere, t16, light, {});
    ShadeOptions truncated;
    truncated.K_used = 1;
    const ShadeResult k1 = shade_vertices(sphere, t16, light, truncated);
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        const double an = dot(a, cast<double>(sphere.normals[v]));
        ASSERT_NEAR(full.irradiance[v].x, kPi + 2 * kPi / 3 * an, 1e-5) << v;
        ASSERT_NEAR(k1.irradiance[v].x, kPi, 1e-5) << v;
        ASSERT_NEAR(std::abs(k1.irradiance[v].x - full.irradiance[v].x), 2 * kPi / 3 * std::abs(an),
                    1e-5);
    }
}

// The glossy term by brute force for one vertex with unit normal n and view direction w:
//   A = ∫ P(r·ω) L(ω) dω,  B = ∫ max(0, n·ω) P(r·ω) dω,  L_S = A·B / max(n·w, kMinCosEta)
// with P the normalised Phong lobe ((s+1)/2π) max(0, cos)^s, r the reflection of w. Midpoint
// rule in z = cos θ about r (A) or n (B) on the upper hemisphere × uniform φ: the integrands are
// smooth there (the lobe's cut-off is of order s), so the rule converges far below 1e-6.
Vec3d glossy_brute_force(const ShLight& light, int light_nonzero, Vec3d n, Vec3d w, double s) {
    const Vec3d r = n * (2 * dot(n, w)) - w;
    auto frame = [](Vec3d z, Vec3d& x, Vec3d& y) {
        const Vec3d h = std::abs(z.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
        x = normalize(cross(h, z));
        y = cross(z, x);
    };
    const int nz = 1500, nphi = 96;
    const double lobe_norm = (s + 1) / (2 * kPi);
    Vec3d x, y;
    // A, about r (the lobe vanishes on the lower hemisphere of r).
    frame(r, x, y);
    Vec3d A{0, 0, 0};
    std::vector<double> basis(light_nonzero);
    for (int i = 0; i < nz; ++i) {
        const double z = (i + 0.5) / nz, st = std::sqrt(1 - z * z);
        const double lobe = lobe_norm * std::pow(z, s);
        for (int k = 0; k < nphi; ++k) {
            const double phi = 2 * kPi * (k + 0.5) / nphi;
            const Vec3d d = x * (st * std::cos(phi)) + y * (st * std::sin(phi)) + r * z;
            sh_eval_k(light_nonzero, d.x, d.y, d.z, basis.data());
            for (int c = 0; c < 3; ++c) {
                double L = 0;
                for (int j = 0; j < light_nonzero; ++j) L += light.channel(c)[j] * basis[j];
                A[c] += lobe * L;
            }
        }
    }
    A = A * (2 * kPi / nphi / nz);
    // B, about n (the clamped cosine vanishes below n's horizon).
    frame(n, x, y);
    double B = 0;
    for (int i = 0; i < nz; ++i) {
        const double z = (i + 0.5) / nz, st = std::sqrt(1 - z * z);
        for (int k = 0; k < nphi * 4; ++k) {
            const double phi = 2 * kPi * (k + 0.5) / (nphi * 4);
            const Vec3d d = x * (st * std::cos(phi)) + y * (st * std::sin(phi)) + n * z;
            const double rd = dot(r, d);
            if (rd > 0) B += z * lobe_norm * std::pow(rd, s);
        }
    }
    B *= 2 * kPi / (nphi * 4) / nz;
    const double cos_eta = std::max(dot(n, w), kMinCosEta);
    return A * (B / cos_eta);
}

TEST(ShadeGlossy, MatchesBruteForceIntegralsOverDirections) {
    // One vertex on a tilted plane; unshadowed analytic transfer with 16 bands; a band-limited
    // light (4 bands, zero-padded to K = 256 so the lobe keeps 16 bands). Then Σ c_s c_L equals
    // A up to the lobe's truncation beyond band 15 (for s = 8 its z_l fall like exp(−l²/2s):
    // negligible), and Σ c_T c_s equals B up to the same truncation.
    Mesh mesh;
    const Vec3f n = normalize(Vec3f{0.2f, 1.0f, -0.3f});
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    mesh.normals = {n, n, n};
    mesh.albedo = {{0.5f, 0.6f, 0.7f}, {0.5f, 0.6f, 0.7f}, {0.5f, 0.6f, 0.7f}};
    mesh.triangles = {{0, 1, 2}};
    const int K = 256, light_nonzero = 16;
    const TransferSet t = test::analytic_transfer(mesh, K);
    const ShLight light = test::smooth_light(K, light_nonzero, 3);
    const double s = 8;
    // Views: near the normal, oblique, and grazing (n·w < kMinCosEta: the clamp is active).
    for (const Vec3f eye :
         {Vec3f{0.3f, 3.0f, 0.1f}, Vec3f{2.0f, 1.5f, -1.0f}, Vec3f{-3.0f, 0.1f, 2.0f}}) {
        ShadeOptions options;
        options.k = 0;  // pure glossy: L = L_S
        options.gloss = s;
        options.eye = eye;
        const ShadeResult r = shade_vertices(mesh, t, light, options);
        const Vec3d w = normalize(cast<double>(eye - mesh.positions[0]));
        const Vec3d expected = glossy_brute_force(light, light_nonzero, cast<double>(n), w, s);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(r.radiance[0][c], expected[c],
                        kGlossyTolerance * std::abs(expected[c]) + 1e-7)
                << "eye " << eye.x << "," << eye.y << "," << eye.z << " channel " << c;
        // The mix: L = k·L_D + (1−k)·L_S.
        options.k = 0.3;
        const ShadeResult mixed = shade_vertices(mesh, t, light, options);
        for (int c = 0; c < 3; ++c) {
            const double L_D = mesh.albedo[0][c] / kPi * r.irradiance[0][c];
            EXPECT_NEAR(mixed.radiance[0][c], 0.3 * L_D + 0.7 * r.radiance[0][c], 1e-5);
        }
    }
}

TEST(ShadeGlossy, NarrowLobeOnAnUnoccludedSurfaceSeesTheLightInTheMirrorDirection) {
    // For a narrow lobe, A → L(r) and B → cos η, so L_S → L(r): the paper's visibility estimate
    // is 1 where nothing occludes. With s = 50 and 24 bands the lobe is resolved (z_24/z_0 ≈
    // exp(−24²/2s) ≈ 0.3 %); the light has bands 0 and 1 only.
    Mesh mesh;
    const Vec3f n{0, 1, 0};
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    mesh.normals = {n, n, n};
    mesh.albedo = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
    mesh.triangles = {{0, 1, 2}};
    const int K = 24 * 24;
    const ShLight light = test::smooth_light(K, 4, 5);
    ShadeOptions options;
    options.k = 0;
    options.gloss = 50;
    options.eye = {1.0f, 1.2f, 0.5f};
    const ShadeResult r = shade_vertices(mesh, test::analytic_transfer(mesh, K), light, options);
    const Vec3d w = normalize(cast<double>(options.eye));
    const Vec3d mirror = cast<double>(n) * (2 * dot(cast<double>(n), w)) - w;
    const Vec3d L = light_radiance(light, mirror);
    // The lobe blurs band 1 by g_1 ≈ exp(−2/2s) (−2 %), and B/cos η ≈ E[cos α] = (s+1)/(s+2)
    // (−2 %): L_S is within 4 % of L(r).
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.radiance[0][c], L[c], 0.04 * L[c]);
}

TEST(Shade, BasisSizeTruncationEqualsTruncatedInputs) {
    const Mesh sphere = make_builtin("sphere");
    const int K = 36, Kp = 11;
    const TransferSet t = test::analytic_transfer(sphere, K);
    const ShLight light = test::smooth_light(K, K, 9);
    ShadeOptions options;
    options.k = 0.4;
    options.gloss = 5;
    options.eye = {2, 3, 4};
    options.K_used = Kp;
    const ShadeResult truncated = shade_vertices(sphere, t, light, options);
    // The same with inputs cut to K'.
    const TransferSet tp = test::analytic_transfer(sphere, Kp);
    ShLight lp = ShLight::zero(Kp);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < Kp; ++i) lp.channel(c)[i] = light.channel(c)[i];
    options.K_used = 0;
    const ShadeResult direct = shade_vertices(sphere, tp, lp, options);
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c) {
            ASSERT_FLOAT_EQ(truncated.irradiance[v][c], direct.irradiance[v][c]);
            ASSERT_FLOAT_EQ(truncated.radiance[v][c], direct.radiance[v][c]);
        }
    EXPECT_EQ(effective_basis_size(t, light, 0), K);
    EXPECT_EQ(effective_basis_size(t, light, Kp), Kp);
    EXPECT_EQ(effective_basis_size(t, lp, 0), Kp);
    EXPECT_EQ(effective_basis_size(t, light, 1000), K);
}

TEST(Shade, RgbTransferUsesChannelCForColourC) {
    const Mesh sphere = make_builtin("sphere");
    const double scale[3] = {0.5, 1.0, 2.0};
    const TransferSet grey = test::analytic_transfer(sphere, 16);
    const TransferSet rgb = test::analytic_transfer(sphere, 16, 3, scale);
    const ShLight light = test::smooth_light(16, 16, 2);
    ShadeOptions options;
    options.k = 0.5;
    options.eye = {0, 0, 5};
    const ShadeResult g = shade_vertices(sphere, grey, light, options);
    const ShadeResult c = shade_vertices(sphere, rgb, light, options);
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v)
        for (int ch = 0; ch < 3; ++ch) {
            ASSERT_NEAR(c.irradiance[v][ch], scale[ch] * g.irradiance[v][ch], 1e-5);
            // L_D and L_S are both linear in the transfer.
            ASSERT_NEAR(c.radiance[v][ch], scale[ch] * g.radiance[v][ch], 1e-5);
        }
}

TEST(Shade, ResultDoesNotDependOnTheThreadCount) {
    // Per-vertex work only: a second run gives the same bits (TBB may split differently).
    const Mesh sphere = make_builtin("sphere");
    const TransferSet t = test::analytic_transfer(sphere, 25);
    const ShLight light = test::smooth_light(25, 25, 4);
    ShadeOptions options;
    options.k = 0.2;
    options.eye = {1, 2, 3};
    const ShadeResult a = shade_vertices(sphere, t, light, options);
    const ShadeResult b = shade_vertices(sphere, t, light, options);
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) ASSERT_EQ(a.radiance[v], b.radiance[v]);
}

TEST(Shade, BadInputThrows) {
    const Mesh sphere = make_builtin("sphere");
    const TransferSet t = test::analytic_transfer(sphere, 9);
    const ShLight light = make_light({"constant"}, 9);
    ShadeOptions bad_k;
    bad_k.k = 1.5;
    EXPECT_THROW(shade_vertices(sphere, t, light, bad_k), Error);
    ShadeOptions bad_gloss;
    bad_gloss.gloss = -1;
    bad_gloss.k = 0.5;
    EXPECT_THROW(shade_vertices(sphere, t, light, bad_gloss), Error);
    ShadeOptions bad_K;
    bad_K.K_used = -2;
    EXPECT_THROW(shade_vertices(sphere, t, light, bad_K), Error);
    TransferSet short_t = t;
    short_t.coeffs.pop_back();
    EXPECT_THROW(shade_vertices(sphere, short_t, light, {}), Error);
    TransferSet two_channels = t;
    two_channels.layout.channels = 2;
    EXPECT_THROW(shade_vertices(sphere, two_channels, light, {}), Error);
    Mesh no_albedo = sphere;
    no_albedo.albedo.clear();
    EXPECT_THROW(shade_vertices(no_albedo, t, light, {}), Error);
    ShLight broken = light;
    broken.coeffs.resize(5);
    EXPECT_THROW(shade_vertices(sphere, t, broken, {}), Error);
    try {
        shade_vertices(sphere, t, light, bad_k);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        EXPECT_NE(std::string(e.what()).find("1.5"), std::string::npos) << e.what();
    }
}

TEST(Shade, LobeBandFactorsAreTheZonalIdentityScale) {
    // g_l = sqrt(4π/(2l+1)) z_l; g_0 = 1 for a lobe that integrates to 1.
    const std::vector<float> g = lobe_band_factors(8, 10);
    const std::vector<double> z = phong_lobe_zonal(8, 10);
    ASSERT_EQ(g.size(), 8u);
    EXPECT_NEAR(g[0], 1.0, 1e-6);
    for (int l = 0; l < 8; ++l) EXPECT_NEAR(g[l], std::sqrt(4 * kPi / (2 * l + 1)) * z[l], 1e-6);
    for (int l = 1; l < 8; ++l) EXPECT_LT(g[l], g[l - 1]);  // a smooth lobe decays with l
    EXPECT_THROW(lobe_band_factors(0, 10), Error);
    EXPECT_THROW(lobe_band_factors(4, -1), Error);
}

// ---- A sun kept out of the SH sum (shade/sun_shade.hpp) -------------------------------------

// An open floor (x, z in [-2, 2]) with a box [-0.5, 0.5] x [0, 1] x [-0.5, 0.5] standing on it, in
// 0.5 m cells: 126 vertices, coloured so that the bounces are coloured too.
Mesh floor_and_box() {
    MeshBuilder b;
    b.add_rect(Axis::y, 0, +1, Rect2{-2, 2, -2, 2}, 0.5, Vec3f{0.8f, 0.8f, 0.8f});
    b.add_box({-0.5, 0, -0.5}, {0.5, 1, 0.5}, 0.5, Vec3f{0.9f, 0.4f, 0.2f}, kBoxNoBottom);
    return b.take_mesh("floor_and_box");
}

double rms(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return std::sqrt(s / double(v.size()));
}

// The split of shade/sun_shade.hpp counts nothing twice and loses nothing: sun direct (traced) +
// sun bounced (T − T_0) + sky (T) equals the all-SH shading T·(sky + sun) as the bands grow, on a
// scene where the SH converges (a 15° sun over an open floor with a box; an interreflected bake
// with an exact product quadrature, so that T_0 under the sun's SH tends to the traced integral).
// The difference is T_0·c_sun − traced, whatever the bounces; the bounced sun itself is large
// against the tolerance, so a split that dropped it, or that lit the whole T with the sun (the
// direct light twice), would fail.
TEST(ShadeSun, SplitEqualsAllShAsTheBandsGrow) {
    const Mesh mesh = floor_and_box();
    BakeOptions bake_options;
    bake_options.transfer = TransferKind::interreflected;
    bake_options.K = 256;
    bake_options.bounces = 2;
    const DirectionSet quad = gauss_legendre_set(48, 96);
    bake_options.indirect_samples = std::uint32_t(quad.size());
    bake_options.source_spacing = std::numeric_limits<float>::infinity();
    const TransferSet T = bake(mesh, bake_options, quad);
    ASSERT_FALSE(T.direct.empty());

    const Sun sun = make_sun({1, 1.3, 0.6}, 15, sun_radiance_for_irradiance({3, 2.5, 2}, 15));
    const ShLight sky = gradient_light(GradientSky{}, 256);
    const PreparedSun prepared{sun, sun_light(sun, 256)};
    ShLight all = sky;
    add_light(all, prepared.sh);
    SunShadeOptions sun_options;
    sun_options.disc_samples = 256;

    std::vector<double> errors;
    for (const int K : {16, 64, 256}) {
        ShadeOptions options;
        options.K_used = K;
        const SunShadeResult split = shade_with_sun(mesh, T, sky, prepared, options, sun_options);
        EXPECT_TRUE(split.bounced);
        const ShadeResult reference = shade_vertices(mesh, T, all, options);
        const ShadeResult sky_only = shade_vertices(mesh, T, sky, options);
        std::vector<double> diff, direct, bounced, radiance_diff;
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
            for (int c = 0; c < 3; ++c) {
                diff.push_back(split.irradiance[v][c] - reference.irradiance[v][c]);
                direct.push_back(split.sun_direct[v][c]);
                // What is left of the split once the sky and the traced sun are taken out.
                bounced.push_back(split.irradiance[v][c] - sky_only.irradiance[v][c] -
                                  split.sun_direct[v][c]);
                radiance_diff.push_back(split.radiance[v][c] - reference.radiance[v][c] -
                                        mesh.albedo[v][c] / kPi * diff.back());
            }
        const double e = rms(diff) / rms(direct);
        std::printf("K = %3d: RMS(split - all SH) / RMS(sun direct) = %.4f, bounced sun %.4f\n", K,
                    e, rms(bounced) / rms(direct));
        errors.push_back(e);
        // The bounced sun is there and is well above the tolerance below.
        EXPECT_GT(rms(bounced) / rms(direct), 0.05) << K;
        EXPECT_LT(rms(radiance_diff), 1e-5 * rms(direct)) << "radiance is ρ/π·E";
    }
    EXPECT_LT(errors[1], errors[0]);
    EXPECT_LT(errors[2], errors[1]);
    EXPECT_LT(errors[2], kSunSplitTolerance);
}

// The point of the trace: a shadow edge is sharp. builtin:box_on_plane under a sun 45° up toward
// +X: the box's shadow on the floor is x in (−1.5, −0.5), |z| < 0.5. A floor vertex a cell inside
// gets no direct sun at all and one a cell outside the whole of it, for a point sun (one ray) and
// for a small disc (64 rays), where the all-SH shading at K = 256 smears it over the cells.
TEST(ShadeSun, TracedShadowIsSharp) {
    const Mesh mesh = make_builtin("box_on_plane");
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    const Sun sun = make_sun({1, 1, 0}, 0.25, sun_radiance_for_irradiance({3, 3, 3}, 0.25));
    const auto vertex_at = [&](float x, float z) {
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
            if (mesh.positions[v] == (Vec3f{x, 0, z}) && mesh.normals[v].y == 1) return v;
        ADD_FAILURE() << "no floor vertex at " << x << ", " << z;
        return std::size_t(0);
    };
    const std::size_t inside[] = {vertex_at(-1.375f, 0), vertex_at(-0.625f, 0.375f),
                                  vertex_at(-1.0f, -0.375f)};
    const std::size_t outside[] = {vertex_at(-1.625f, 0), vertex_at(-1.0f, 0.625f),
                                   vertex_at(-1.0f, -0.625f), vertex_at(1.0f, 0)};
    for (const int N : {1, 64}) {
        SunShadeOptions options;
        options.disc_samples = N;
        const std::vector<Vec3f> E =
            sun_direct_irradiance(*tracer, mesh.positions, mesh.normals, sun, options);
        // The whole disc above a floor normal: L·Ω/N · Σ_j n·d_j.
        double full = 0;
        for (const Vec3d& d : sun_disc_directions(sun, N, options.seed)) full += d.y;
        full *= sun.radiance.x * sun_solid_angle(sun) / N;
        EXPECT_NEAR(full, 3 * std::sqrt(0.5), 3e-3);
        for (std::size_t v : inside) EXPECT_EQ(E[v], (Vec3f{0, 0, 0})) << N << " vertex " << v;
        for (std::size_t v : outside) EXPECT_NEAR(E[v].x, full, 1e-6 * full) << N << " " << v;
    }
}

// A texel bake of `mesh` at side × side texels, K = 16, `samples` directions.
TransferSet texel_bake_K16(const Mesh& mesh, int side, int samples) {
    BakeOptions options;
    options.K = 16;
    options.samples = samples;
    return test::texel_bake(mesh, side, options);
}

TEST(ShadeSun, TexelsGetTheTracedSunAndTheSumIsTheirShading) {
    const Mesh mesh = make_builtin("quad_box");
    const TransferSet t = texel_bake_K16(mesh, 32, 64);
    const Sun sun = make_sun({1, 1, 0}, 0.5, sun_radiance_for_irradiance({3, 3, 3}, 0.5));
    const ShLight sky = gradient_light(GradientSky{}, 16);
    SunShadeOptions sun_options;
    sun_options.disc_samples = 16;
    const SunShadeResult r = shade_with_sun(mesh, t, sky, PreparedSun{sun, sun_light(sun, 16)},
                                            ShadeOptions{}, sun_options);
    EXPECT_FALSE(r.bounced);
    const ShadeResult s = shade_texels(mesh, t, sky, ShadeOptions{});
    ASSERT_EQ(r.irradiance.size(), t.texels.texel.size());
    const TexelPoints points = texel_points(mesh, t);
    int shadowed = 0, lit = 0;
    for (std::size_t i = 0; i < r.irradiance.size(); ++i) {
        const Vec3f& p = points.points.positions[i];
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(r.irradiance[i][c],
                      float(double(s.irradiance[i][c]) + double(r.sun_direct[i][c])));
        if (points.points.normals[i].y < 0.99f || std::abs(p.z) > 0.45f) continue;
        // Floor texels in the box's shadow (x in (−1.5, −0.5)) and well away from it.
        if (p.x > -1.45f && p.x < -0.55f) {
            EXPECT_EQ(r.sun_direct[i].x, 0.0f) << p.x;
            ++shadowed;
        } else if (p.x < -1.55f || p.x > 0.55f) {
            EXPECT_GT(r.sun_direct[i].x, 2.0f) << p.x;
            ++lit;
        }
    }
    EXPECT_GT(shadowed, 10);
    EXPECT_GT(lit, 10);
}

// shade_receivers takes the kind table's pass (shading_pass), as the GL renderer chooses its
// scene pass: a texel set's texels as points through their rows' vertex pass; options that do not
// fit the layout (a BRDF for vectors) are refused.
TEST(Shade, ReceiversTakeTheKindTablesPass) {
    const Mesh mesh = make_builtin("quad_box");
    const TransferSet texels = texel_bake_K16(mesh, 16, 16);
    const ShLight sky = gradient_light(GradientSky{}, 16);
    ShadeOptions shade;
    shade.k = 0.5;  // the glossy term too
    const ShadeResult all = shade_receivers(mesh, texels, sky, shade, nullptr);
    const TexelPoints points = texel_points(mesh, texels);
    ASSERT_EQ(shading_pass(points.rows.layout), ShadingPass::vertex_vectors);
    const ShadeResult rows = shade_vertices(points.points, points.rows, sky, shade);
    EXPECT_EQ(all.radiance, rows.radiance);
    EXPECT_EQ(all.irradiance, rows.irradiance);
    const GlossyShadeOptions brdf;
    EXPECT_THROW(shade_receivers(mesh, texels, sky, shade, &brdf), Error);
}

TEST(ShadeSun, SameBitsForAnyThreadCountAndDiffuseOnly) {
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions options;
    options.K = 16;
    options.samples = 64;
    const TransferSet t = bake(mesh, options);
    const Sun sun = make_sun({0.4, 1, 0.3}, 3, {100, 90, 80});
    const PreparedSun prepared{sun, sun_light(sun, 16)};
    const ShLight sky = gradient_light(GradientSky{}, 16);
    SunShadeResult by[2];
    int i = 0;
    for (const int threads : {1, 2}) {
        Arena arena(threads);
        arena.execute([&] {
            by[i++] = shade_with_sun(mesh, t, sky, prepared, ShadeOptions{}, SunShadeOptions{});
        });
    }
    EXPECT_EQ(by[0].irradiance, by[1].irradiance);
    EXPECT_EQ(by[0].radiance, by[1].radiance);
    // Each receiver's value is its own: the same bits traced alone as in any batch.
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    for (std::size_t v = 0; v < mesh.vertex_count(); v += 97)
        ASSERT_EQ(
            sun_direct_irradiance(*tracer, {mesh.positions[v]}, {mesh.normals[v]}, sun, {})[0],
            by[0].sun_direct[v])
            << v;
    const auto lit = std::count_if(by[0].sun_direct.begin(), by[0].sun_direct.end(),
                                   [](Vec3f e) { return e.x > 0; });
    EXPECT_GT(lit, 0);
    EXPECT_LT(std::size_t(lit), mesh.vertex_count());

    ShadeOptions glossy;
    glossy.k = 0.5;
    EXPECT_THROW(shade_with_sun(mesh, t, sky, prepared, glossy, {}), Error);
    SunShadeOptions bad;
    bad.disc_samples = 10;
    EXPECT_THROW(shade_with_sun(mesh, t, sky, prepared, {}, bad), Error);
}

// Glossy matrices under a sun kept out of the SH sum (shade_glossy_with_sun): the sky through M
// as shade_glossy shades it, the sun's irradiance exactly sun_direct_irradiance's, nothing from the
// sun in its shadow, and at a floor vertex that mirrors the sun to the eye a highlight of the
// exact Phong-16 lobe's height — (1 − k)·L·Ω·(E + 1)/(2π) — where the 5-band zonal fit of the
// same lobe, lit by the sun through SH, stays far below it.
TEST(ShadeSun, GlossyMatricesGetTheExactLobeOfTheTracedSun) {
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions options;
    options.transfer = TransferKind::glossy;
    options.K = 25;
    options.samples = 256;
    const TransferSet t = bake(mesh, options);
    const Sun sun = make_sun({1, 1, 0}, 1, sun_radiance_for_irradiance({3, 3, 3}, 1));
    const PreparedSun prepared{sun, sun_light(sun, 25)};
    const ShLight sky = gradient_light(GradientSky{}, 25);
    // The floor vertex at (1.5, 0, 0) and an eye on its mirror ray of the sun (45° up toward −X).
    std::size_t mirror = mesh.vertex_count();
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        if (mesh.positions[v] == (Vec3f{1.5f, 0, 0}) && mesh.normals[v].y == 1) mirror = v;
    ASSERT_LT(mirror, mesh.vertex_count());
    GlossyShadeOptions g;
    g.brdf = Brdf{BrdfModel::phong, 16};
    g.k = 0.5;
    g.eye = Vec3f{1.5f, 0, 0} + Vec3f{-1, 1, 0} * 2.0f;
    SunShadeOptions sun_options;
    sun_options.disc_samples = 256;
    const SunShadeResult r = shade_glossy_with_sun(mesh, t, sky, prepared, g, sun_options);
    const ShadeResult s = shade_glossy(mesh, t, sky, g);
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    EXPECT_EQ(r.sun_direct,
              sun_direct_irradiance(*tracer, mesh.positions, mesh.normals, sun, sun_options));
    int shadowed = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(r.irradiance[v][c], float(double(s.irradiance[v][c]) + r.sun_direct[v][c]));
        if (r.sun_direct[v].x == 0) {
            EXPECT_EQ(r.radiance[v], s.radiance[v]) << v;
            ++shadowed;
        }
    }
    EXPECT_GT(shadowed, 20);
    const double peak = 0.5 * sun.radiance.x * sun_solid_angle(sun) * 17 / (2 * kPi);
    const double diffuse = 0.5 * mesh.albedo[mirror].x / kPi * r.sun_direct[mirror].x;
    const double highlight = r.radiance[mirror].x - s.radiance[mirror].x - diffuse;
    EXPECT_NEAR(highlight, peak, 0.02 * peak);
    // The same sun through SH (K = 25) and the 5-band lobe: a blur of the highlight.
    ShLight both = sky;
    add_light(both, prepared.sh);
    const ShadeResult all_sh = shade_glossy(mesh, t, both, g);
    const double blurred = all_sh.radiance[mirror].x - s.radiance[mirror].x - diffuse;
    std::printf(
        "highlight at the mirror vertex: traced %.4f, exact lobe's peak %.4f, through SH "
        "%.4f\n",
        highlight, peak, blurred);
    EXPECT_LT(blurred, 0.5 * peak);
}

}  // namespace
}  // namespace shprt
