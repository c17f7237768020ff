// Per-fragment rendering of texel transfer (Renderer with a texel-domain set; src/render/
// texel_pass.hpp): looking straight down at the builtin quad_box's texel bake, every floor and
// box pixel equals the CPU per-texel shading (shade_texels) filtered bilinearly at the pixel's UV
// from the dilated atlas — for grey and RGB transfer, float16 and float32 planes, truncated K',
// and the three views — and the box's shadow is in the picture, where the vertex bake's render of
// the same scene shows a uniform floor. Without EGL / OpenGL 4.3 every test here SKIPs.
#include "render_test_util.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/half.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/transfer/cpca.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace shprt {
namespace {

// GL sums in float; the CPU in double. The filter's weights have a fixed-point fraction on real
// hardware (8 bits) and the fragment's UV is interpolated in float: a pixel may differ from the
// exact bilinear value by a small share of the spread of the four texels it filters.
constexpr double kRelTolerance = 1e-3, kAbsTolerance = 1e-4, kSpreadShare = 1.0 / 64;
constexpr int kAtlasSide = 64, kImageSide = 96;
constexpr float kNoHit = -1.0f;  // the clear colour: impossible for shaded values

const Mesh& quad_box() {
    static const Mesh mesh = make_builtin("quad_box");
    return mesh;
}

// The texel bake of quad_box (grey, K = 36, S = 512), float32 planes.
const TransferSet& texel_bake() {
    static const TransferSet set = [] {
        BakeOptions options;
        options.K = 36;
        options.samples = 512;
        options.threads = 2;
        return test::texel_bake(quad_box(), kAtlasSide, options);
    }();
    return set;
}

Camera top_camera() {
    Camera c;
    c.eye = {0, 7, 0};
    c.target = {0, 0, 0};
    c.up = {0, 0, -1};
    c.fov_y_deg = 40;
    c.near_plane = 0.5f;
    c.far_plane = 20;
    return c;
}

ShLight sun(int K) { return parse_light("sun:0.4,0.8,-0.3,2", K); }

Image draw(const TransferSet& transfer, const ShLight& light, const DrawSettings& settings) {
    Renderer renderer;
    renderer.set_scene(quad_box(), transfer);
    renderer.set_light(light);
    RenderTarget target(kImageSide, kImageSide, 1);  // one sample: the pixel centre
    target.bind();
    renderer.draw(settings, kImageSide, kImageSide);
    target.resolve();
    return target.read_pixels();
}

// What per-vertex `values` of quad_box interpolate to where the ray through pixel (x, y)'s
// centre first hits it; false when it hits nothing.
bool value_at_pixel(const Image& image, const Camera& camera, int x, int y,
                    const std::vector<Vec3f>& values, Vec3d& value) {
    Vec3f o, d;
    pixel_ray(camera, image.width, image.height, float(x) + 0.5f, float(y) + 0.5f, o, d);
    double t;
    return test::trace_interpolate(quad_box(), values, o, d, value, t);
}

struct Comparison {
    std::size_t compared = 0, bad = 0;
    double worst = 0;  // largest |gl − ref| / tolerance
};

// Each pixel against the bilinear filtering, at the UV where its centre's ray hits the mesh, of
// the per-texel values (atlas order) spread into the gutter as the renderer spreads them.
Comparison compare(const Image& image, const TransferSet& transfer,
                   const std::vector<Vec3f>& values, const Camera& camera) {
    const TexelAtlas& atlas = transfer.texels;
    const std::vector<std::int64_t> source = dilate_texels(atlas, kTexelGutter);
    const auto texel = [&](int x, int y) {
        x = std::clamp(x, 0, atlas.width - 1), y = std::clamp(y, 0, atlas.height - 1);
        const std::int64_t r = source[std::size_t(y) * atlas.width + x];
        return r >= 0 ? cast<double>(values[std::size_t(r)]) : Vec3d{0, 0, 0};
    };
    std::vector<Vec3f> uvs;
    for (const auto& uv : quad_box().uvs) uvs.push_back({uv[0], uv[1], 0});
    Comparison c;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            Vec3d uv;
            const float* px = image.pixel(x, y);
            if (!value_at_pixel(image, camera, x, y, uvs, uv)) {
                EXPECT_EQ(px[0], kNoHit) << "pixel " << x << "," << y;
                continue;
            }
            const double fx = uv.x * atlas.width - 0.5, fy = (1 - uv.y) * atlas.height - 0.5;
            const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
            const double ax = fx - x0, ay = fy - y0;
            const Vec3d q[4] = {texel(x0, y0), texel(x0 + 1, y0), texel(x0, y0 + 1),
                                texel(x0 + 1, y0 + 1)};
            const Vec3d ref =
                (1 - ay) * ((1 - ax) * q[0] + ax * q[1]) + ay * ((1 - ax) * q[2] + ax * q[3]);
            ++c.compared;
            double worst_here = 0;
            for (int k = 0; k < 3; ++k) {
                double lo = q[0][k], hi = q[0][k];
                for (const Vec3d& v : q) lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
                const double tolerance =
                    kRelTolerance * std::abs(ref[k]) + kAbsTolerance + kSpreadShare * (hi - lo);
                worst_here = std::max(worst_here, std::abs(px[k] - ref[k]) / tolerance);
            }
            c.worst = std::max(c.worst, worst_here);
            if (worst_here > 1) ++c.bad;
        }
    return c;
}

TEST(GlTexelRender, PixelsAreTheCpuTexelShadingFilteredAtTheirUv) {
    REQUIRE_GL(context);
    struct Case {
        int channels, K_used;
        bool f16;
        ShadeView view;
    };
    const Case cases[] = {
        {1, 0, false, ShadeView::radiance},
        {3, 0, true, ShadeView::radiance},   // RGB, float16 planes (the file's default)
        {1, 13, true, ShadeView::radiance},  // K' not a multiple of 4: the masked last group
        {3, 30, false, ShadeView::irradiance},
        {1, 0, true, ShadeView::transfer},
    };
    for (const Case& cs : cases) {
        SCOPED_TRACE(::testing::Message() << "channels=" << cs.channels << " K'=" << cs.K_used
                                          << " f16=" << cs.f16 << " view=" << int(cs.view));
        TransferSet t = texel_bake();
        if (cs.channels == 3) {  // RGB transfer: each channel the grey row scaled
            const std::size_t K = std::size_t(t.layout.K), R = t.receiver_count();
            std::vector<float> rgb(3 * K * R);
            for (std::size_t r = 0; r < R; ++r)
                for (std::size_t c = 0; c < 3; ++c)
                    for (std::size_t i = 0; i < K; ++i)
                        rgb[(3 * r + c) * K + i] = t.coeffs[r * K + i] * (0.7f + 0.3f * float(c));
            t.coeffs = std::move(rgb);
            t.layout.channels = 3;
        }
        if (cs.f16) {  // the planes then hold exactly these values
            t.layout.encoding = TransferEncoding::f16;
            for (float& v : t.coeffs) v = half_to_float(float_to_half(v));
        }
        const ShLight light = sun(36);
        ShadeOptions options;
        options.K_used = cs.K_used;
        const ShadeResult cpu = shade_texels(quad_box(), t, light, options);
        std::vector<Vec3f> values =
            cs.view == ShadeView::irradiance ? cpu.irradiance : cpu.radiance;
        if (cs.view == ShadeView::transfer)
            for (std::size_t r = 0; r < values.size(); ++r) {
                const float ao = t.receiver(r, 0)[0] * 1.12837916709551257f;
                values[r] = {ao, ao, ao};
            }
        DrawSettings settings;
        settings.camera = top_camera();
        settings.K_used = cs.K_used;
        settings.view = cs.view;
        settings.clear_color = {kNoHit, kNoHit, kNoHit};
        const Image image = draw(t, light, settings);
        const Comparison c = compare(image, t, values, settings.camera);
        EXPECT_GT(c.compared, std::size_t(kImageSide * kImageSide / 2));
        EXPECT_EQ(c.bad, 0u) << "worst error " << c.worst << " tolerances";
    }
}

// Glossy matrices per texel: the glossy passes shade each texel as a point, and every pixel is
// the bilinear filtering of those colours at its UV — the CPU's shade_texels_glossy filtered the
// same way (raw matrices with a material BRDF on the floor, and a CPCA code; radiance and
// irradiance).
TEST(GlTexelRender, GlossyTexelsAreTheCpuTexelShadingFilteredAtTheirUv) {
    REQUIRE_GL(context);
    const Mesh mesh = test::quad_box_with_glossy_floor();
    BakeOptions options;
    options.transfer = TransferKind::glossy;
    options.K = 16;
    options.samples = 128;
    options.threads = 2;
    const TransferSet raw = test::texel_bake(mesh, kAtlasSide, options);
    TransferSet coded = raw;
    CpcaOptions cpca;
    cpca.clusters = 8;
    cpca.vectors = 4;
    coded.cpca = compress_cpca(coded, cpca);
    reconstruct_cpca(coded.cpca, coded.layout.floats_per_receiver(), coded.coeffs);
    const ShLight light = sun(16);
    for (const TransferSet* t :
         {static_cast<const TransferSet*>(&raw), static_cast<const TransferSet*>(&coded)})
        for (const ShadeView view : {ShadeView::radiance, ShadeView::irradiance}) {
            SCOPED_TRACE(::testing::Message()
                         << (t == &raw ? "raw" : "cpca") << " view=" << int(view));
            GlossyShadeOptions shade;
            shade.brdf = {BrdfModel::phong, 12};
            shade.material_brdfs = true;
            shade.k = 0.3;
            shade.eye = top_camera().eye;
            const ShadeResult cpu = shade_texels_glossy(mesh, *t, light, shade);
            DrawSettings settings;
            settings.camera = top_camera();
            settings.k = shade.k;
            settings.brdf = shade.brdf;
            settings.material_brdfs = true;
            settings.view = view;
            settings.clear_color = {kNoHit, kNoHit, kNoHit};
            Renderer renderer;
            renderer.set_scene(mesh, *t);
            renderer.set_light(light);
            RenderTarget target(kImageSide, kImageSide, 1);
            target.bind();
            renderer.draw(settings, kImageSide, kImageSide);
            const Image image = target.read_pixels();
            const Comparison c =
                compare(image, *t, view == ShadeView::radiance ? cpu.radiance : cpu.irradiance,
                        settings.camera);
            EXPECT_GT(c.compared, std::size_t(kImageSide * kImageSide / 2));
            EXPECT_EQ(c.bad, 0u) << "worst error " << c.worst << " tolerances";
        }
}

// The darkest and brightest floor pixel outside the box's silhouette.
std::pair<double, double> floor_range(const Image& image, const Camera& camera) {
    std::vector<Vec3f> is_floor(quad_box().vertex_count(), Vec3f{0, 0, 0});
    for (int v = 0; v < 4; ++v) is_floor[v] = {1, 1, 1};  // the floor is quad_box's first quad
    double lo = 1e30, hi = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            Vec3d f;
            if (!value_at_pixel(image, camera, x, y, is_floor, f) || f.x < 1 - 1e-9) continue;
            const double g = image.pixel(x, y)[1];
            lo = std::min(lo, g), hi = std::max(hi, g);
        }
    return {lo, hi};
}

TEST(GlTexelRender, TheBoxShadowIsInTheTexelPictureNotInTheVertexOne) {
    REQUIRE_GL(context);
    DrawSettings settings;
    settings.camera = top_camera();
    const ShLight light = sun(36);
    const auto [texel_lo, texel_hi] =
        floor_range(draw(texel_bake(), light, settings), settings.camera);
    BakeOptions options;
    options.K = 36;
    options.samples = 512;
    options.threads = 2;
    const TransferSet vertices = bake(quad_box(), options);
    const auto [vertex_lo, vertex_hi] =
        floor_range(draw(vertices, light, settings), settings.camera);
    ASSERT_GT(texel_hi, 0.0);
    ASSERT_GT(vertex_hi, 0.0);
    EXPECT_LT(texel_lo, 0.5 * texel_hi);    // the shadow beside the box
    EXPECT_GT(vertex_lo, 0.9 * vertex_hi);  // four floor vertices, all far from the box
}

// Drawn straight into an 8-bit framebuffer, the texel pass shows what draw and present show.
TEST(GlTexelRender, DrawToDisplayShowsWhatDrawAndPresentShow) {
    REQUIRE_GL(context);
    Renderer renderer;
    renderer.set_scene(quad_box(), texel_bake());
    renderer.set_light(sun(36));
    DrawSettings settings;
    settings.camera = top_camera();
    test::expect_display_draw_matches_present(renderer, settings, kImageSide, kImageSide, 1.4f);
}

TEST(GlTexelRender, GlossyAndInPlaceUpdatesAreRefused) {
    REQUIRE_GL(context);
    Renderer renderer;
    renderer.set_scene(quad_box(), texel_bake());
    renderer.set_light(sun(36));
    EXPECT_EQ(renderer.vertex_count(), quad_box().vertex_count());
    EXPECT_EQ(renderer.scene_K(), 36);
    RenderTarget target(8, 8, 1);
    target.bind();
    DrawSettings settings;
    settings.camera = top_camera();
    settings.k = 0.5;
    EXPECT_THROW(renderer.draw(settings, 8, 8), Error);
    settings.view = ShadeView::irradiance;  // k is not used there
    EXPECT_NO_THROW(renderer.draw(settings, 8, 8));
    const std::vector<float> row(36, 0.0f);
    EXPECT_THROW(renderer.update_transfer(0, 1, row.data()), Error);
    // A mesh without UVs cannot show a texel transfer.
    Mesh no_uvs = quad_box();
    no_uvs.uvs.clear();
    EXPECT_THROW(renderer.set_scene(no_uvs, texel_bake()), Error);
}

}  // namespace
}  // namespace shprt
