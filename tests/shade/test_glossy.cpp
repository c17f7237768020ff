// Glossy shading with transfer matrices (shade/glossy.hpp): lobe normalisation and fits, the
// white furnace, the analytic zonal convolution at an unoccluded receiver, and a brute-force
// integral of lobe × visibility × light at room vertices within the stated truncation bound.
#include "shprt/shade/glossy.hpp"

#include "shade_test_util.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/cpca.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace shprt {
namespace {

const Brdf kBrdfs[] = {{BrdfModel::phong, 16}, {BrdfModel::blinn_phong, 40}, {BrdfModel::ggx, 0.4}};

// A one-vertex "mesh" whose transfer matrix is the identity: a receiver that sees the whole
// sphere (M = Σ_s w_s y yᵀ = I exactly for an exact rule).
struct IdentityReceiver {
    Mesh mesh;
    TransferSet transfer;
    explicit IdentityReceiver(int K) {
        mesh.positions = {{0, 0, 0}};
        mesh.normals = {normalize(Vec3f{0.2f, 1.0f, 0.1f})};
        mesh.albedo = {{0.5f, 0.5f, 0.5f}};
        TransferInfo info;
        info.kind = TransferKind::glossy;
        info.layout.K = K;
        info.layout.shape = TransferShape::symmetric_matrix;
        transfer = TransferSet::zeros(info, 1);
        float* p = transfer.receiver(0);
        for (int i = 0; i < K; ++i)
            for (int j = i; j < K; ++j) *p++ = i == j ? 1.0f : 0.0f;
    }
};

ShLight constant_light(int K, double radiance) {
    ShLight l = ShLight::zero(K);
    for (int c = 0; c < 3; ++c) l.channel(c)[0] = float(radiance * std::sqrt(4 * kPi));
    return l;
}

ShLight random_light(int K, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    ShLight l = ShLight::zero(K);
    for (int c = 0; c < 3; ++c) {
        l.channel(c)[0] = 3.0f;
        for (int i = 1; i < K; ++i) l.channel(c)[i] = float(u(rng));
    }
    return l;
}

TEST(GlossyLobe, EveryLobeIntegratesToOneAndItsFitErrorFallsWithBands) {
    for (const Brdf& b : kBrdfs) {
        SCOPED_TRACE(to_string(b));
        const BrdfLobe lobe = brdf_lobe(b, 8);
        EXPECT_NEAR(lobe.zonal[0] * std::sqrt(4 * kPi), 1.0, 1e-9);
        EXPECT_GT(lobe.fit_error, 0.0);
        EXPECT_LT(lobe.fit_error, 1.0);
        EXPECT_LT(brdf_lobe(b, 12).fit_error, lobe.fit_error);
        // The profile is the same lobe: its projection's z_0 equals ∫ f dω / √(4π).
        const std::vector<double> z = project_zonal(brdf_profile(b), 3, 512);
        for (int l = 0; l < 3; ++l) EXPECT_NEAR(z[l], lobe.zonal[l], 1e-6);
    }
    // A normalised Phong lobe of exponent 1 is the clamped cosine over π.
    const std::vector<double> cosine = clamped_cosine_zonal(6);
    const BrdfLobe phong1 = brdf_lobe({BrdfModel::phong, 1}, 6);
    for (int l = 0; l < 6; ++l) EXPECT_NEAR(phong1.zonal[l], cosine[l] / kPi, 1e-12);
}

TEST(GlossyLobe, ParsesSpecsAndRefusesBadOnes) {
    EXPECT_EQ(parse_brdf("ggx:0.3").model, BrdfModel::ggx);
    EXPECT_EQ(parse_brdf("blinn:20").parameter, 20.0);
    EXPECT_EQ(parse_brdf("blinn:20").specular, (Vec3f{1, 1, 1}));
    // An optional specular colour; to_string writes it where it is not white, and reads back.
    const Brdf gold = parse_brdf("ggx:0.4:1,0.71,0.29");
    EXPECT_EQ(gold, (Brdf{BrdfModel::ggx, 0.4, Vec3f{1, 0.71f, 0.29f}}));
    EXPECT_EQ(to_string(gold), "ggx:0.4:1,0.71,0.29");
    EXPECT_EQ(to_string(parse_brdf("phong:16:1,1,1")), "phong:16");
    for (const Brdf& b : kBrdfs) EXPECT_EQ(parse_brdf(to_string(b)), b);
    for (const char* bad : {"phong", "phong:-1", "ggx:0", "ggx:2", "lambert:1", "phong:x",
                            "phong:16:", "phong:16:1,1", "phong:16:1,1,1,1", "phong:16:0.5,1.5,0",
                            "phong:16:0,-0.1,0", "ggx:0.3:a,b,c", "phong:16:nan,0,0"})
        EXPECT_THROW(parse_brdf(bad), Error) << bad;
}

TEST(GlossyShade, WhiteFurnaceReturnsTheSpecularAlbedoForEveryLobeAndView) {
    // Constant light 1 seen through the whole sphere (M = I): a normalised lobe reflects ρ_s.
    const IdentityReceiver r(25);
    for (const Brdf& b : kBrdfs) {
        for (Vec3f eye : {Vec3f{0, 5, 0}, Vec3f{3, 1, -2}, Vec3f{-1, 0.2f, 4}}) {
            GlossyShadeOptions o;
            o.brdf = b;
            o.k = 0;
            o.albedo = Vec3f{1, 1, 1};
            o.eye = eye;
            const ShadeResult s = shade_glossy(r.mesh, r.transfer, constant_light(25, 1.0), o);
            EXPECT_NEAR(s.radiance[0].x, 1.0, 1e-6) << to_string(b);
            o.albedo = Vec3f{0.25f, 0.5f, 0.75f};
            const ShadeResult c = shade_glossy(r.mesh, r.transfer, constant_light(25, 1.0), o);
            EXPECT_NEAR(c.radiance[0].z, 0.75, 1e-6);
            // Without the override, the BRDF's own specular colour is ρ_s.
            o.albedo.reset();
            o.brdf.specular = Vec3f{0.9f, 0.6f, 0.2f};
            const ShadeResult own = shade_glossy(r.mesh, r.transfer, constant_light(25, 1.0), o);
            EXPECT_NEAR(own.radiance[0].x, 0.9, 1e-6) << to_string(o.brdf);
            EXPECT_NEAR(own.radiance[0].y, 0.6, 1e-6) << to_string(o.brdf);
            EXPECT_NEAR(own.radiance[0].z, 0.2, 1e-6) << to_string(o.brdf);
        }
    }
}

TEST(GlossyShade, UnoccludedReceiverGivesTheAnalyticZonalConvolution) {
    // M = I: the glossy term is the light convolved with the lobe (Funk–Hecke), evaluated at the
    // reflection direction: Σ_lm sqrt(4π/(2l+1)) z_l L_lm y_lm(r).
    const int K = 25;
    const IdentityReceiver r(K);
    const ShLight light = random_light(K, 11);
    const Vec3f eye{1.5f, 2.0f, -0.5f};
    for (const Brdf& b : kBrdfs) {
        GlossyShadeOptions o;
        o.brdf = b;
        o.k = 0;
        o.albedo = Vec3f{1, 1, 1};
        o.eye = eye;
        const ShadeResult s = shade_glossy(r.mesh, r.transfer, light, o);
        const Vec3d n = normalize(cast<double>(r.mesh.normals[0]));
        const Vec3d w = normalize(cast<double>(eye));
        const Vec3d refl = n * (2 * dot(n, w)) - w;
        std::vector<double> y(K), coeffs(K);
        for (int i = 0; i < K; ++i) coeffs[i] = light.channel(1)[i];
        const std::vector<double> z = brdf_lobe(b, 5).zonal;
        convolve_zonal(z.data(), 5, coeffs.data(), K);
        sh_eval_k<double>(K, refl.x, refl.y, refl.z, y.data());
        double expected = 0;
        for (int i = 0; i < K; ++i) expected += coeffs[i] * y[i];
        EXPECT_NEAR(s.radiance[0].y, expected, 1e-5 * std::fabs(expected)) << to_string(b);
    }
}

TEST(GlossyShade, BakedPlaneFurnaceAtNormalViewIsOneWithinTheTruncationBound) {
    // An unoccluded plane seen along its normal under constant light 1: the lobe lies inside the
    // hemisphere, so the exact glossy radiance is 1. In SH both the lobe g and the visibility V
    // (the hemisphere's indicator) are zonal about n, and the answer is Σ_{l<n} g_l h_l, whose
    // error against Σ_l g_l h_l = 1 is at most ‖g − g_n‖·‖V − V_n‖ (Cauchy–Schwarz on the tails,
    // docs/glossy.md). The baked plane must give Σ_{l<n} g_l h_l to Monte Carlo precision.
    const Mesh plane = make_builtin("plane");
    BakeOptions bo;
    bo.transfer = TransferKind::glossy;
    bo.K = 25;
    bo.samples = 4096;
    const TransferSet t = bake(plane, bo);
    const Brdf b{BrdfModel::phong, 8};
    double g2 = 0, h2 = 0;
    const std::vector<double> g = project_zonal(brdf_profile(b), 5, 1024, &g2);
    const std::vector<double> h =
        project_zonal([](double x) { return x > 0 ? 1.0 : 0.0; }, 5, 1024, &h2);
    double predicted = 0, g_kept = 0, h_kept = 0;
    for (int l = 0; l < 5; ++l) {
        predicted += g[l] * h[l];
        g_kept += g[l] * g[l];
        h_kept += h[l] * h[l];
    }
    const double bound = std::sqrt((g2 - g_kept) * (h2 - h_kept));
    EXPECT_LE(std::fabs(predicted - 1.0), bound);
    EXPECT_LT(bound, 0.2);  // the stated bound is informative for phong:8 at 5 bands

    GlossyShadeOptions o;
    o.brdf = b;
    o.k = 0;
    o.albedo = Vec3f{1, 1, 1};
    o.eye = Vec3f{0, 10, 0};
    const ShadeResult s = shade_glossy(plane, t, constant_light(25, 1.0), o);
    std::size_t centre = 0;  // the eye is straight above the centre vertex
    for (std::size_t v = 0; v < plane.vertex_count(); ++v)
        if (length(plane.positions[v]) < length(plane.positions[centre])) centre = v;
    EXPECT_NEAR(s.radiance[centre].x, predicted, 0.01);
    EXPECT_NEAR(s.radiance[centre].x, 1.0, bound + 0.01);
}

TEST(GlossyShade, RoomVerticesAgreeWithABruteForceIntegralWithinTheTruncationBound) {
    // L_o = ∫ g(r·ω) V(ω) L(ω) dω over the hemisphere, summed over the bake's own directions with
    // the lobe's true profile and a ray per direction. The SH answer is the same sum with g
    // replaced by its K-coefficient zonal fit g_K (M·L projects V·L), so by Cauchy–Schwarz on the
    // discrete inner product |SH − brute| ≤ sqrt(Σ w (g − g_K)²) · sqrt(Σ w (V·L)²).
    const Mesh room = make_builtin("room");
    const int K = 25;
    BakeOptions bo;
    bo.transfer = TransferKind::glossy;
    bo.K = K;
    bo.samples = 2048;
    bo.direction_frame = DirectionFrame::sphere;  // the brute force sums over the same world set
    const DirectionSet set = make_direction_set(bo.sampler, bo.seed, bo.samples);
    const auto tracer = make_embree_tracer(room);
    const Receivers all = vertex_receivers(room);
    const ShLight light = random_light(K, 5);
    const Vec3f eye = default_camera(room, 16.0f / 9.0f).eye;
    const Brdf brdf{BrdfModel::phong, 8};
    const std::vector<double> lobe = brdf_lobe(brdf, 5).zonal;
    const BrdfProfile profile = brdf_profile(brdf);

    TransferInfo info = bake_description(bo);
    TransferSet t = TransferSet::zeros(info, room.vertex_count());
    const std::size_t V = room.vertex_count();
    const std::size_t picks[] = {V / 7, V / 3, V / 2, (2 * V) / 3, V - 5};
    double least_visible = 1;
    for (std::size_t v : picks) {
        const TransferSet one = bake(room, all.range(v, 1), bo);
        std::copy(one.coeffs.begin(), one.coeffs.end(), t.receiver(v));
        least_visible = std::min(least_visible, double(one.coeffs[0]) / 0.5);
    }
    EXPECT_LT(least_visible, 0.95) << "some picked vertex is partly occluded";
    GlossyShadeOptions o;
    o.brdf = brdf;
    o.k = 0;
    o.albedo = Vec3f{1, 1, 1};
    o.eye = eye;
    const ShadeResult s = shade_glossy(room, t, light, o);

    std::vector<double> y(K), gk(K);
    for (std::size_t v : picks) {
        const Vec3f nf = room.normals[v];
        const Vec3d n = normalize(cast<double>(nf));
        const Vec3d p = cast<double>(room.positions[v]);
        const Vec3d w = normalize(cast<double>(eye) - p);
        const Vec3d r = n * (2 * dot(n, w)) - w;
        rotate_zonal(lobe.data(), K, r, gk.data());
        double brute = 0, residual2 = 0, light2 = 0;
        for (std::size_t q = 0; q < set.size(); ++q) {
            const Vec3f dir{set.dirs[3 * q], set.dirs[3 * q + 1], set.dirs[3 * q + 2]};
            if (dot(nf, dir) <= 0) continue;
            std::uint8_t occluded = 0;
            tracer->occluded(offset_ray_origin(room.positions[v], nf), &dir, 1, 0.0f,
                             std::numeric_limits<float>::infinity(), &occluded);
            if (occluded) continue;
            const Vec3d d = cast<double>(dir);
            sh_eval_k<double>(K, d.x, d.y, d.z, y.data());
            double L = 0, g_fit = 0;
            for (int i = 0; i < K; ++i) {
                L += double(light.channel(0)[i]) * y[i];
                g_fit += gk[i] * y[i];
            }
            const double g = profile(dot(r, d));
            const double wq = set.weights[q];
            brute += wq * g * L;
            residual2 += wq * (g - g_fit) * (g - g_fit);
            light2 += wq * L * L;
        }
        const double bound = std::sqrt(residual2 * light2);
        SCOPED_TRACE(v);
        // The bound is exact (Cauchy–Schwarz); the shading is float: a relative 1e-6 of slack
        // (a fully occluded vertex has brute = 0 and a result at the bound itself).
        EXPECT_NEAR(s.radiance[v].x, brute, bound * (1 + 1e-6) + 1e-4 * std::fabs(brute));
    }
}

TEST(GlossyShade, ACpcaCodeIsShadedPerClusterLikeItsRebuiltRows) {
    const Mesh scene = make_builtin("box_on_plane");
    BakeOptions bo;
    bo.transfer = TransferKind::glossy;
    bo.K = 16;
    bo.samples = 128;
    CpcaOptions co;
    co.clusters = 12;
    co.vectors = 5;
    const CpcaResult r = compress_transfer(bake(scene, bo), scene.normals, co, false);
    TransferSet rows = r.compressed;
    rows.cpca = CpcaCode{};  // the same rows without the code: shaded row by row
    GlossyShadeOptions o;
    o.brdf = {BrdfModel::ggx, 0.3};
    o.eye = Vec3f{2, 3, 4};
    const ShLight light = random_light(16, 3);
    const ShadeResult by_cluster = shade_glossy(scene, r.compressed, light, o);
    const ShadeResult by_row = shade_glossy(scene, rows, light, o);
    for (std::size_t v = 0; v < scene.vertex_count(); ++v) {
        EXPECT_NEAR(by_cluster.radiance[v].y, by_row.radiance[v].y, 1e-4) << v;
        EXPECT_NEAR(by_cluster.irradiance[v].z, by_row.irradiance[v].z, 1e-3) << v;
    }
}

TEST(GlossyShade, MaterialBrdfsShadeEachVertexWithItsOwnLobe) {
    // Three material groups (two BRDFs and "none") over a baked scene: each vertex must get what
    // shading the whole scene with its group's one BRDF gives, bit for bit.
    Mesh scene = make_builtin("box_on_plane");
    BakeOptions bo;
    bo.transfer = TransferKind::glossy;
    bo.K = 16;
    bo.samples = 64;
    const TransferSet transfer = bake(scene, bo);
    scene.brdfs = {Brdf{BrdfModel::ggx, 0.3, Vec3f{0.95f, 0.64f, 0.54f}},
                   Brdf{BrdfModel::phong, 80}};
    for (std::size_t v = 0; v < scene.vertex_count(); ++v)
        scene.brdf_index.push_back(v % 3 == 2 ? Mesh::kNoBrdf : std::uint32_t(v % 3));
    GlossyShadeOptions o;
    o.brdf = {BrdfModel::blinn_phong, 40};
    o.k = 0.25;
    o.eye = Vec3f{2, 3, 4};
    o.material_brdfs = true;
    const ShLight light = random_light(16, 5);
    const ShadeResult mixed = shade_glossy(scene, transfer, light, o);
    std::vector<ShadeResult> single;
    for (const Brdf& b : {scene.brdfs[0], scene.brdfs[1], o.brdf}) {
        GlossyShadeOptions one = o;
        one.material_brdfs = false;
        one.brdf = b;
        single.push_back(shade_glossy(scene, transfer, light, one));
    }
    std::size_t differing = 0;  // vertices whose groups' pictures differ (the test has teeth)
    for (std::size_t v = 0; v < scene.vertex_count(); ++v) {
        const ShadeResult& expected = single[v % 3];
        EXPECT_EQ(mixed.radiance[v], expected.radiance[v]) << "vertex " << v;
        differing += single[0].radiance[v] != single[1].radiance[v] ? 1 : 0;
    }
    EXPECT_GT(differing, scene.vertex_count() / 2);
    // Without material_brdfs, o.brdf everywhere.
    o.material_brdfs = false;
    const ShadeResult plain = shade_glossy(scene, transfer, light, o);
    for (std::size_t v = 0; v < scene.vertex_count(); ++v)
        EXPECT_EQ(plain.radiance[v], single[2].radiance[v]) << "vertex " << v;
    // Indices that do not fit the mesh are refused.
    o.material_brdfs = true;
    scene.brdf_index[4] = 2;
    EXPECT_THROW(shade_glossy(scene, transfer, light, o), Error);
    scene.brdf_index.pop_back();
    EXPECT_THROW(shade_glossy(scene, transfer, light, o), Error);
}

// Glossy matrices per texel (a texel-domain glossy bake of quad_box): each texel is shaded as a
// point with its raster position, normal and albedo, and its triangle's material BRDF; floor
// texels far from the box reflect a white furnace as 1.
TEST(GlossyShade, TexelMatricesAreShadedAtEachTexelsPoint) {
    const Mesh mesh = test::quad_box_with_glossy_floor();
    BakeOptions bo;
    bo.transfer = TransferKind::glossy;
    bo.K = 16;
    bo.samples = 256;
    const TransferSet t = test::texel_bake(mesh, 32, bo);
    const TexelSamples texels = rasterize_texels(mesh, 32, 32);
    GlossyShadeOptions o;
    o.brdf = {BrdfModel::phong, 8};
    o.material_brdfs = true;
    o.k = 0.3;
    o.eye = Vec3f{0.5f, 3, 1};
    const ShLight light = random_light(16, 9);
    const ShadeResult all = shade_texels_glossy(mesh, t, light, o);
    ASSERT_EQ(all.radiance.size(), texels.count());
    std::size_t floor = 0;
    for (std::size_t r = 0; r < texels.count(); r += 13) {
        Mesh point;
        point.positions = {texels.positions[r]};
        point.normals = {texels.normals[r]};
        point.albedo = {texels.albedo[r]};
        TransferSet row = t;
        row.layout.domain = ReceiverDomain::vertex;
        row.texels = {};
        row.coeffs.assign(t.receiver(r), t.receiver(r) + t.layout.floats_per_receiver());
        GlossyShadeOptions one = o;
        one.material_brdfs = false;
        const bool on_floor = texels.triangle[r] < 2;
        floor += on_floor ? 1 : 0;
        if (on_floor) one.brdf = mesh.brdfs[0];
        EXPECT_EQ(shade_glossy(point, row, light, one).radiance[0], all.radiance[r]) << r;
    }
    EXPECT_GT(floor, 10u);
    // White furnace: a floor texel at the atlas's far corner, seen along its normal.
    o.k = 0;
    o.albedo = Vec3f{1, 1, 1};
    o.material_brdfs = false;
    std::size_t far = 0;  // the floor texel farthest from the box
    float far_distance = -1;
    for (std::size_t r = 0; r < texels.count(); ++r)
        if (texels.triangle[r] < 2 && length(texels.positions[r]) > far_distance)
            far = r, far_distance = length(texels.positions[r]);
    o.eye = texels.positions[far] + Vec3f{0, 5, 0};
    const ShadeResult furnace = shade_texels_glossy(mesh, t, constant_light(16, 1), o);
    EXPECT_NEAR(furnace.radiance[far].y, 1.0, 0.12);  // phong:8 at 4 bands: ~0.10 truncation
}

// The diffuse transfer of texel matrices (`--glossy paper`, `export`): per texel, with the texel's
// own normal, as the texels converted as points; the atlas is kept.
TEST(GlossyShade, TexelMatricesTurnIntoTexelDiffuseTransfer) {
    const Mesh mesh = test::quad_box_with_glossy_floor();
    BakeOptions bo;
    bo.transfer = TransferKind::glossy;
    bo.K = 9;
    bo.samples = 64;
    const TransferSet t = test::texel_bake(mesh, 16, bo);
    const TransferSet d = glossy_to_diffuse(mesh, t);
    EXPECT_EQ(d.layout.domain, ReceiverDomain::texel);
    EXPECT_EQ(d.layout.shape, TransferShape::vector);
    EXPECT_EQ(d.texels, t.texels);
    const TexelPoints points = texel_points(mesh, t);
    ASSERT_GT(points.points.vertex_count(), mesh.vertex_count());  // more texels than vertices
    EXPECT_EQ(d.coeffs, glossy_to_diffuse(points.points, points.rows).coeffs);
    d.check(mesh);
}

TEST(GlossyShade, RefusesDiffuseTransfer) {
    const Mesh plane = make_builtin("plane");
    BakeOptions bo;
    bo.K = 9;
    bo.samples = 16;
    const TransferSet diffuse = bake(plane, bo);
    GlossyShadeOptions o;
    EXPECT_THROW(shade_glossy(plane, diffuse, constant_light(9, 1), o), Error);
    EXPECT_THROW(check_shadable(plane, bake(plane,
                                            [] {
                                                BakeOptions g;
                                                g.transfer = TransferKind::glossy;
                                                g.K = 4;
                                                g.samples = 16;
                                                return g;
                                            }())),
                 Error);
}

TEST(GlossyShade, GlossyToDiffuseIsTheShadowedTransferToTruncation) {
    // t = M·a(n) is the projection of V·(the K-truncated clamped cosine): on the unoccluded
    // plane it is close to the diffuse bake of the same directions (the truncated cosine differs
    // from the cosine by its l ≥ 3 bands, small).
    const Mesh plane = make_builtin("plane");
    BakeOptions bo;
    bo.K = 9;
    bo.samples = 4096;
    const TransferSet diffuse = bake(plane, bo);
    bo.transfer = TransferKind::glossy;
    const TransferSet glossy = glossy_to_diffuse(plane, bake(plane, bo));
    ASSERT_EQ(glossy.layout.shape, TransferShape::vector);
    for (int i = 0; i < 9; ++i)
        EXPECT_NEAR(glossy.receiver(100)[i], diffuse.receiver(100)[i], 0.05);
}

}  // namespace
}  // namespace shprt
