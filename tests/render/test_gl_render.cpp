// The OpenGL renderer against the CPU reference: every pixel of a headless render equals the
// CPU per-vertex shading interpolated at the point the pixel's ray hits (a brute-force ray
// caster), for diffuse and glossy shading, grey and RGB transfer, truncated K'. Also: the
// background, the transfer-only view, tone-mapped presentation (what the viewer shows) against
// the PNG encoder, partial transfer updates, and a picture of the room that looks lit.
// Without EGL / OpenGL 4.3 every test here SKIPs with the reason.
#include "render_test_util.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/tonemap.hpp"
#include "shprt/transfer/cpca.hpp"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace shprt {
namespace {

// GL evaluates in float (the glossy recurrence included) and interpolates in float; the CPU in
// double. Relative agreement of a pixel with the reference, plus an absolute floor for values
// near zero.
constexpr double kGlRelTolerance = 1e-3;
constexpr double kGlAbsTolerance = 1e-4;
// Pixels whose centre the rasteriser and the ray caster see on different sides of a silhouette.
constexpr double kMaxSilhouetteMismatch = 0.01;

struct Comparison {
    std::size_t compared = 0, mismatched_hits = 0, bad = 0;
    double worst = 0;  // largest |gl − ref| / (rel·|ref| + abs)
};

// Compares each pixel of `image` with the reference: the CPU radiance interpolated where the
// pixel centre's ray hits the mesh, or `background` where it hits nothing.
Comparison compare_with_reference(const Image& image, const Mesh& mesh,
                                  const std::vector<Vec3f>& values, const Camera& camera,
                                  Vec3f background) {
    Comparison c;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            Vec3f o, d;
            pixel_ray(camera, image.width, image.height, float(x) + 0.5f, float(y) + 0.5f, o, d);
            Vec3d ref;
            double t;
            const bool hit = test::trace_interpolate(mesh, values, o, d, ref, t);
            const float* px = image.pixel(x, y);
            const bool gl_background =
                px[0] == background.x && px[1] == background.y && px[2] == background.z;
            if (hit == gl_background) {
                ++c.mismatched_hits;
                continue;
            }
            if (!hit) continue;
            ++c.compared;
            double worst_here = 0;
            for (int k = 0; k < 3; ++k) {
                const double err = std::abs(px[k] - ref[k]) /
                                   (kGlRelTolerance * std::abs(ref[k]) + kGlAbsTolerance);
                worst_here = std::max(worst_here, err);
            }
            c.worst = std::max(c.worst, worst_here);
            if (worst_here > 1) ++c.bad;
        }
    return c;
}

TEST(GlRender, PixelsMatchTheCpuReferenceDiffuseAndGlossy) {
    REQUIRE_GL(context);
    const Vec3f background{-1, -1, -1};  // impossible for the scenes below: marks "no hit"
    struct Case {
        const char* scene;
        int K, channels, K_used;
        double k, gloss;
        Camera camera;
    };
    Camera plane_cam;
    plane_cam.eye = {1.6f, 1.3f, 2.2f};
    plane_cam.target = {-0.1f, 0, 0.1f};
    plane_cam.fov_y_deg = 45;
    plane_cam.near_plane = 0.1f;
    plane_cam.far_plane = 10;
    Camera sphere_cam = plane_cam;
    sphere_cam.eye = {2.5f, 1.5f, 2.0f};
    sphere_cam.target = {0, 0, 0};
    const Case cases[] = {
        {"plane", 48, 3, 40, 1.0, 16, plane_cam},    // diffuse, RGB transfer, K' not a square
        {"plane", 64, 1, 0, 0.3, 12, plane_cam},     // glossy on a plane: view-dependent
        {"sphere", 64, 1, 0, 0.5, 8, sphere_cam},    // glossy on a curved surface
        {"sphere", 36, 3, 25, 0.0, 30, sphere_cam},  // pure glossy, RGB, truncated
        // K not a multiple of 4: the shader's one-coefficient loads, and a padded light block.
        {"sphere", 25, 1, 0, 0.7, 16, sphere_cam},
        {"plane", 30, 3, 27, 1.0, 16, plane_cam},
    };
    for (const Case& cs : cases) {
        SCOPED_TRACE(::testing::Message() << cs.scene << " K=" << cs.K << " channels="
                                          << cs.channels << " K'=" << cs.K_used << " k=" << cs.k);
        const Mesh mesh = make_builtin(cs.scene);
        const double scale[3] = {0.7, 1.0, 1.3};
        const TransferSet transfer = test::analytic_transfer(mesh, cs.K, cs.channels, scale);
        const ShLight light = test::smooth_light(cs.K, cs.K, 11);
        ShadeOptions shade;
        shade.k = cs.k;
        shade.gloss = cs.gloss;
        shade.eye = cs.camera.eye;
        shade.K_used = cs.K_used;
        const ShadeResult cpu = shade_vertices(mesh, transfer, light, shade);

        DrawSettings settings;
        settings.camera = cs.camera;
        settings.k = cs.k;
        settings.gloss = cs.gloss;
        settings.K_used = cs.K_used;
        settings.clear_color = background;
        const int w = 96, h = 72;
        Renderer renderer;
        renderer.set_scene(mesh, transfer);
        renderer.set_light(light);
        RenderTarget target(w, h, 1);  // one sample: the pixel centre, as the ray caster
        target.bind();
        renderer.draw(settings, w, h);
        target.resolve();
        const Image image = target.read_pixels();

        const Comparison c =
            compare_with_reference(image, mesh, cpu.radiance, cs.camera, background);
        EXPECT_GT(c.compared, std::size_t(w * h / 10));
        EXPECT_LE(double(c.mismatched_hits), kMaxSilhouetteMismatch * w * h);
        EXPECT_EQ(c.bad, 0u) << "worst error " << c.worst << " tolerances";
    }
}

TEST(GlRender, IrradianceAndTransferViews) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("plane");
    const TransferSet transfer = test::analytic_transfer(mesh, 16);
    const ShLight light = test::smooth_light(16, 16, 2);
    const ShadeResult cpu = shade_vertices(mesh, transfer, light, {});
    DrawSettings settings;
    settings.camera.eye = {0, 2, 1.5f};
    settings.camera.target = {0, 0, 0};
    settings.camera.near_plane = 0.1f;
    settings.camera.far_plane = 10;
    settings.clear_color = {-1, -1, -1};
    settings.view = ShadeView::irradiance;
    const Image e = render_image(mesh, transfer, light, settings, 64, 48, 1);
    const Comparison c =
        compare_with_reference(e, mesh, cpu.irradiance, settings.camera, settings.clear_color);
    EXPECT_GT(c.compared, 500u);
    EXPECT_EQ(c.bad, 0u) << c.worst;
    // Unoccluded: the AO-like value T_0·2/sqrt(π) is 1 everywhere, grey, whatever the light.
    settings.view = ShadeView::transfer;
    const Image ao = render_image(mesh, transfer, light, settings, 64, 48, 1);
    std::size_t seen = 0;
    for (std::size_t i = 0; i < ao.pixel_count(); ++i) {
        if (ao.rgb[3 * i] == -1.0f) continue;
        ++seen;
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(ao.rgb[3 * i + k], 1.0f, 1e-5f);
    }
    EXPECT_GT(seen, 500u);
}

TEST(GlRender, BackgroundIsTheLightsReconstructionAlongEachViewRay) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("plane");
    DrawSettings settings;
    settings.camera.eye = {0, 0.5f, 0};
    settings.camera.target = {0.3f, 1.5f, -1};  // looking up: the plane below is out of view
    settings.camera.fov_y_deg = 70;
    settings.camera.near_plane = 0.05f;
    settings.camera.far_plane = 10;
    settings.background = true;
    const int w = 80, h = 60;
    const Mat3d turn = matrix_from_yaw_pitch_roll_deg(70, -35, 20);
    // A full band (9) and a partial one (7: not rotation invariant), unturned and turned.
    for (int K : {9, 7}) {
        const TransferSet transfer = test::analytic_transfer(mesh, K);
        const ShLight light = test::smooth_light(K, K, 6);
        Renderer renderer;
        renderer.set_scene(mesh, transfer);
        RenderTarget target(w, h, 1);
        for (const Mat3d& R : {Mat3d::identity(), turn}) {
            SCOPED_TRACE(::testing::Message() << "K=" << K << " turned=" << (R == turn));
            renderer.set_light(light, R);
            target.bind();
            renderer.draw(settings, w, h);
            const Image image = target.read_pixels();
            ShLight want_light = light;
            rotate_light(want_light, R);
            double worst = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    Vec3f o, d;
                    pixel_ray(settings.camera, w, h, float(x) + 0.5f, float(y) + 0.5f, o, d);
                    const Vec3d want = light_radiance(want_light, cast<double>(d));
                    for (int k = 0; k < 3; ++k)
                        worst = std::max(
                            worst, std::abs(image.pixel(x, y)[k] - want[k]) / std::abs(want[k]));
                }
            // Bilinear lookup in a 256 × 128 texture of a 3-band light: well under 1 %.
            EXPECT_LT(worst, 0.01);
        }
        // Turning a full-band light turns the lookup; a partial band rebuilds the texture.
        EXPECT_EQ(renderer.background_builds(), K == 9 ? 1u : 2u);
    }
}

TEST(GlRender, ATurnedLightShadesAsItsRotatedCoefficients) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("sphere");
    const TransferSet transfer = test::analytic_transfer(mesh, 16);
    const ShLight light = make_light({"builtin"}, 16);
    const Mat3d R = matrix_from_yaw_pitch_roll_deg(-40, 25, 10);
    ShLight rotated = light;
    rotate_light(rotated, R);
    DrawSettings settings;
    settings.camera = default_camera(mesh, 1.5f);
    settings.k = 0.5;  // diffuse and glossy
    Renderer renderer;
    renderer.set_scene(mesh, transfer);
    RenderTarget target(64, 48, 1);
    auto draw = [&](const ShLight& l, const Mat3d& rotation) {
        renderer.set_light(l, rotation);
        target.bind();
        renderer.draw(settings, 64, 48);
        return target.read_pixels();
    };
    const Image turned = draw(light, R);
    const Image direct = draw(rotated, Mat3d::identity());
    EXPECT_EQ(turned.rgb, direct.rgb) << "the same coefficients reach the shader";
    const Image unturned = draw(light, Mat3d::identity());
    EXPECT_NE(unturned.rgb, direct.rgb) << "the rotation matters in this view";
}

TEST(GlRender, PresentShowsWhatThePngEncoderWrites) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("sphere");
    const TransferSet transfer = test::analytic_transfer(mesh, 16);
    const ShLight light = make_light({"builtin"}, 16);
    DrawSettings settings;
    settings.camera = default_camera(mesh, 1.5f);
    settings.k = 0.6;
    settings.background = true;
    const int w = 90, h = 60;
    Renderer renderer;
    renderer.set_scene(mesh, transfer);
    renderer.set_light(light);
    // Without MSAA present reads the texture drawn into; with it, present averages the samples
    // itself and must agree with the blit resolve that read_pixels sees.
    for (int samples : {1, 4}) {
        SCOPED_TRACE(samples);
        RenderTarget target(w, h, samples);
        target.bind();
        renderer.draw(settings, w, h);
        target.resolve();
        const Image linear = target.read_pixels();
        DisplayTarget display(w, h);  // an 8-bit window stand-in
        glBindFramebuffer(GL_FRAMEBUFFER, display.framebuffer());
        const float exposure = 1.7f;
        renderer.present(target, exposure);
        const Rgb8Image shown = read_framebuffer(display.framebuffer(), w, h);
        int worst = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int k = 0; k < 3; ++k) {
                    const int gl_code = shown.rgb[(std::size_t(y) * w + x) * 3 + k];
                    const int png_code = display_encode8(linear.pixel(x, y)[k], exposure);
                    worst = std::max(worst, std::abs(gl_code - png_code));
                }
        EXPECT_LE(worst, 1) << "codes differ by more than the 8-bit rounding";
    }
}

// The GPU's display encoding (the present pass's GLSL, which draw_to_display shares) against the
// PNG encoder's (shade/tonemap.hpp) on 196 608 radiance values from 0 to past the tone map's
// saturation: the same formulas in float, so a code may differ by one level only where the GPU's
// pow() rounds a value across a rounding boundary — rarely (llvmpipe: 1 of the 196 608 codes).
TEST(GlRender, PresentEncodesARampAsThePngEncoderDoes) {
    REQUIRE_GL(context);
    const int w = 256, h = 256;
    std::vector<float> rgba(std::size_t(w) * h * 4);
    std::vector<float> linear(std::size_t(w) * h * 3);
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
        const double t = double(i) / double(w * h - 1);
        const float x = static_cast<float>(9.0 * t * t * t);  // dense at the dark end
        const float rgb[3] = {x, 0.37f * x, 2.1f * x};
        for (int c = 0; c < 3; ++c) rgba[4 * i + c] = linear[3 * i + c] = rgb[c];
        rgba[4 * i + 3] = 1.0f;
    }
    RenderTarget target(w, h, 1);
    glBindTexture(GL_TEXTURE_2D, target.color_texture());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    Renderer renderer;
    DisplayTarget display(w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, display.framebuffer());
    const float exposure = 1.0f;
    renderer.present(target, exposure);
    const Rgb8Image shown = read_framebuffer(display.framebuffer(), w, h);
    int worst = 0;
    std::size_t differ = 0;
    std::vector<bool> seen(256, false);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                // GL texel row y is the image's row h − 1 − y.
                const std::size_t i = std::size_t(y) * w + x;
                const int want = display_encode8(linear[3 * i + c], exposure);
                const int got = shown.rgb[(std::size_t(h - 1 - y) * w + x) * 3 + c];
                worst = std::max(worst, std::abs(got - want));
                differ += got != want;
                seen[std::size_t(got)] = true;
            }
    EXPECT_LE(worst, 1);
    EXPECT_LE(differ, linear.size() / 1000) << "of " << linear.size() << " codes differ by one";
    EXPECT_EQ(std::count(seen.begin(), seen.end(), true), 256) << "every code is on the ramp";
}

// The single-sample frame drawn straight into an 8-bit framebuffer (tone mapped in the scene's
// and the background's fragment shaders) shows what the float target and the present pass show:
// the same GLSL on the same values. Each setting puts a different shader on screen: the
// per-vertex colours with the glossy term, the background, the clear colour (host-encoded) around
// a wireframe.
TEST(GlRender, DrawToDisplayShowsWhatDrawAndPresentShow) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("box_on_plane");
    const TransferSet transfer = test::analytic_transfer(mesh, 16);
    const ShLight light = make_light({"builtin"}, 16);
    const int w = 96, h = 64;
    Renderer renderer;
    renderer.set_scene(mesh, transfer);
    renderer.set_light(light);
    DrawSettings lit;
    lit.camera = default_camera(mesh, 1.3f);
    lit.k = 0.6;
    lit.background = true;
    DrawSettings wire = lit;
    wire.background = false;
    wire.wireframe = true;
    wire.clear_color = {0.3f, 0.05f, 0.6f};
    for (const auto& [settings, exposure] :
         {std::pair{lit, 1.0f}, std::pair{lit, 2.3f}, std::pair{wire, 0.7f}}) {
        SCOPED_TRACE(testing::Message()
                     << "exposure " << exposure << ", wireframe " << settings.wireframe);
        test::expect_display_draw_matches_present(renderer, settings, w, h, exposure);
    }
    RenderTarget target(w, h, 1);
    target.bind();
    EXPECT_THROW(renderer.draw_to_display(lit, w, h, 0.0f), Error);
}

TEST(GlRender, PartialTransferUpdateEqualsAFreshUpload) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("sphere");
    const TransferSet full = test::analytic_transfer(mesh, 16);
    TransferSet dark = full;
    for (float& c : dark.coeffs) c *= 0.25f;
    const ShLight light = test::smooth_light(16, 16, 8);
    DrawSettings settings;
    settings.camera = default_camera(mesh, 1.0f);
    auto frame = [&](Renderer& r) {
        RenderTarget target(48, 48, 1);
        target.bind();
        r.draw(settings, 48, 48);
        target.resolve();
        return target.read_pixels();
    };
    Renderer fresh;
    fresh.set_scene(mesh, full);
    fresh.set_light(light);
    const Image want = frame(fresh);
    Renderer updated;
    updated.set_scene(mesh, dark);
    updated.set_light(light);
    const Image before = frame(updated);
    const std::size_t half = mesh.vertex_count() / 2;
    updated.update_transfer(0, half, full.coeffs.data());
    updated.update_transfer(half, mesh.vertex_count() - half, full.receiver(half));
    const Image after = frame(updated);
    EXPECT_NE(before.rgb, want.rgb);
    EXPECT_EQ(after.rgb, want.rgb);
    EXPECT_THROW(updated.update_transfer(half, mesh.vertex_count(), full.coeffs.data()), Error);
}

// A renderer showing the sphere's analytic transfer (K = 16) under a smooth light (needs a
// current context).
struct SphereScene {
    Mesh mesh = make_builtin("sphere");
    TransferSet transfer = test::analytic_transfer(mesh, 16);
    Renderer renderer;
    SphereScene() {
        renderer.set_scene(mesh, transfer);
        renderer.set_light(test::smooth_light(16, 16, 3));
    }
};

// A refused scene leaves the last one drawn: one of another pass (texels, refused by the texel
// pass) and one of the same pass (a short transfer) both throw, and the next frame is the last
// scene's, not even shaded again.
TEST(GlRender, ARefusedSceneLeavesTheLastOneDrawn) {
    REQUIRE_GL(context);
    SphereScene scene;
    RenderTarget target(16, 16, 1);
    DrawSettings settings;
    settings.camera = default_camera(scene.mesh, 1.0f);
    const auto frame = [&] {
        target.bind();
        scene.renderer.draw(settings, 16, 16);
        target.resolve();
        return target.read_pixels().rgb;
    };
    const std::vector<float> before = frame();
    TransferSet texels = scene.transfer;
    texels.layout.domain = ReceiverDomain::texel;  // and no atlas
    EXPECT_THROW(scene.renderer.set_scene(scene.mesh, texels), Error);
    TransferSet short_rows = scene.transfer;
    short_rows.coeffs.pop_back();
    EXPECT_THROW(scene.renderer.set_scene(scene.mesh, short_rows), Error);
    EXPECT_EQ(scene.renderer.vertex_count(), scene.mesh.vertex_count());
    EXPECT_EQ(frame(), before);
    EXPECT_EQ(scene.renderer.shading_passes(), 1u);
}

TEST(GlRender, ShadingPassRunsOnlyWhenTheColoursCanChange) {
    REQUIRE_GL(context);
    SphereScene scene;
    const Mesh& mesh = scene.mesh;
    const TransferSet& transfer = scene.transfer;
    Renderer& renderer = scene.renderer;
    RenderTarget target(32, 32, 1);
    target.bind();
    DrawSettings settings;
    settings.camera = default_camera(mesh, 1.0f);
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 1u);
    // Diffuse shading does not depend on the camera.
    settings.camera.eye = settings.camera.eye * 1.3f;
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 1u);
    // Glossy shading depends on the eye; the light, K', k and updates invalidate.
    settings.k = 0.5;
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 2u);
    settings.camera.eye = settings.camera.eye * 0.9f;
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 3u);
    settings.camera.target = {0.1f, 0, 0};  // the target alone does not change the colours
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 3u);
    settings.K_used = 9;
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 4u);
    renderer.set_light(test::smooth_light(16, 16, 4));
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 5u);
    renderer.update_transfer(0, 1, transfer.coeffs.data());
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 6u);
    settings.reshade = true;
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.shading_passes(), 7u);
    // A cached frame equals a fresh renderer's frame.
    settings.reshade = false;
    settings.k = 1;
    renderer.draw(settings, 32, 32);
    settings.camera.eye = {0.5f, 3, 2};
    renderer.draw(settings, 32, 32);
    target.resolve();
    const Image cached = target.read_pixels();
    Renderer fresh;
    fresh.set_scene(mesh, transfer);
    fresh.set_light(test::smooth_light(16, 16, 4));
    target.bind();
    fresh.draw(settings, 32, 32);
    target.resolve();
    EXPECT_EQ(cached.rgb, target.read_pixels().rgb);
}

// A glossy bake of builtin:box_on_plane (K, S samples), with a CPCA code of `clusters` × `vectors`
// and the rows rebuilt from it when clusters > 0.
TransferSet glossy_box_on_plane(const Mesh& mesh, int K, std::uint32_t samples, int clusters = 0,
                                int vectors = 0) {
    BakeOptions options;
    options.transfer = TransferKind::glossy;
    options.K = K;
    options.samples = samples;
    TransferSet transfer = bake(mesh, options);
    if (clusters > 0) {
        CpcaOptions cpca;
        cpca.clusters = clusters;
        cpca.vectors = vectors;
        transfer.cpca = compress_cpca(transfer, cpca);
        reconstruct_cpca(transfer.cpca, transfer.layout.floats_per_receiver(), transfer.coeffs);
    }
    return transfer;
}

// The glossy tests' view of box_on_plane: the box and its shadow from above one corner.
Camera box_view() {
    Camera camera;
    camera.eye = {1.8f, 1.6f, 2.3f};
    camera.target = {0, 0.1f, 0};
    camera.near_plane = 0.1f;
    camera.far_plane = 20;
    return camera;
}

// Glossy transfer matrices (a real bake of a box on a plane, so shadows are in the matrices) and
// their CPCA code, shaded on the GPU, against shade_glossy on the CPU (shade/glossy.hpp): every
// pixel equals the CPU radiance interpolated where its ray hits, for the three BRDF models, the
// colour override, truncated K', and the irradiance and transfer views.
TEST(GlRender, GlossyMatricesAndTheirCpcaCodeMatchShadeGlossy) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("box_on_plane");
    const TransferSet raw = glossy_box_on_plane(mesh, 25, 256);
    const TransferSet coded = glossy_box_on_plane(mesh, 25, 256, 6, 5);
    const ShLight light = test::smooth_light(25, 25, 5);
    const Camera camera = box_view();
    const Vec3f background{-1, -1, -1};
    struct Case {
        const char* brdf;
        double k;
        int K_used;
        std::optional<Vec3f> albedo;
        ShadeView view;
    };
    const Case cases[] = {
        {"phong:16", 0.4, 0, std::nullopt, ShadeView::radiance},
        {"blinn:40", 0.0, 0, Vec3f{0.9f, 0.5f, 0.2f}, ShadeView::radiance},
        {"ggx:0.3", 0.7, 16, std::nullopt, ShadeView::radiance},  // K' a full band below K
        {"phong:8", 0.5, 0, std::nullopt, ShadeView::irradiance},
        {"phong:8", 0.5, 20, std::nullopt, ShadeView::transfer},  // K' not a full band
    };
    for (const TransferSet* transfer : {&raw, static_cast<const TransferSet*>(&coded)}) {
        for (const Case& cs : cases) {
            SCOPED_TRACE(::testing::Message()
                         << (transfer == &raw ? "raw" : "cpca") << " " << cs.brdf << " k=" << cs.k
                         << " K'=" << cs.K_used << " view=" << int(cs.view));
            GlossyShadeOptions shade;
            shade.brdf = parse_brdf(cs.brdf);
            shade.k = cs.k;
            shade.albedo = cs.albedo;
            shade.eye = camera.eye;
            shade.K_used = cs.K_used;
            std::vector<Vec3f> reference;
            if (cs.view == ShadeView::transfer) {
                // E under a white sky of radiance 1, over π: the diffuse transfer's T_0·2/√π.
                const TransferSet diffuse = glossy_to_diffuse(mesh, *transfer);
                for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
                    const float ao = float(diffuse.receiver(v)[0] * 2 / std::sqrt(kPi));
                    reference.push_back({ao, ao, ao});
                }
            } else {
                const ShadeResult cpu = shade_glossy(mesh, *transfer, light, shade);
                reference = cs.view == ShadeView::irradiance ? cpu.irradiance : cpu.radiance;
            }
            DrawSettings settings;
            settings.camera = camera;
            settings.k = cs.k;
            settings.brdf = shade.brdf;
            settings.albedo = cs.albedo;
            settings.K_used = cs.K_used;
            settings.view = cs.view;
            settings.clear_color = background;
            const int w = 96, h = 72;
            const Image image = render_image(mesh, *transfer, light, settings, w, h, 1);
            const Comparison c = compare_with_reference(image, mesh, reference, camera, background);
            EXPECT_GT(c.compared, std::size_t(w * h / 4));
            EXPECT_LE(double(c.mismatched_hits), kMaxSilhouetteMismatch * w * h);
            EXPECT_EQ(c.bad, 0u) << "worst error " << c.worst << " tolerances";
        }
    }
}

// The two other ways a CPCA code's products reach the vertex pass, against shade_glossy: many
// clusters, several dispatches each binding its own uniform block (64 clusters of 9 × 25 vec4s:
// 18 a block at 64 KiB); and a code whose cluster products do not fit a block at all (171 × 25
// vec4s), read from the storage buffer.
TEST(GlRender, CpcaCodesOverSeveralBlocksAndTooWideForOne) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("box_on_plane");
    const int K = 25;
    GLint max_block = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    struct Case {
        int clusters, vectors;
    };
    for (const Case& cs : {Case{64, 8}, Case{2, 170}}) {
        SCOPED_TRACE(::testing::Message() << cs.clusters << " x " << cs.vectors);
        const int block_bytes = (1 + cs.vectors) * K * 16;
        if (cs.vectors == 170) {
            ASSERT_GT(block_bytes, max_block) << "the code fits a block: no storage buffer path";
        } else {
            ASSERT_GT(cs.clusters * block_bytes, max_block) << "not several dispatches";
        }
        const TransferSet transfer = glossy_box_on_plane(mesh, K, 128, cs.clusters, cs.vectors);
        const ShLight light = test::smooth_light(25, 25, 8);
        const Camera camera = box_view();
        GlossyShadeOptions shade;
        shade.brdf = parse_brdf("phong:20");
        shade.k = 0.3;
        shade.eye = camera.eye;
        const ShadeResult cpu = shade_glossy(mesh, transfer, light, shade);
        DrawSettings settings;
        settings.camera = camera;
        settings.k = shade.k;
        settings.brdf = shade.brdf;
        settings.clear_color = {-1, -1, -1};
        const Image image = render_image(mesh, transfer, light, settings, 80, 60, 1);
        const Comparison c =
            compare_with_reference(image, mesh, cpu.radiance, camera, settings.clear_color);
        EXPECT_GT(c.compared, std::size_t(80 * 60 / 4));
        EXPECT_EQ(c.bad, 0u) << "worst error " << c.worst << " tolerances";
    }
}

// Per-material BRDFs (Mesh::brdfs) on the GPU against shade_glossy, raw matrices and a CPCA code:
// each vertex's lobe and specular colour come from the lobe block; switching material_brdfs off
// gives the one BRDF (with its own specular colour).
TEST(GlRender, MaterialBrdfsMatchShadeGlossy) {
    REQUIRE_GL(context);
    Mesh mesh = make_builtin("box_on_plane");
    mesh.brdfs = {Brdf{BrdfModel::ggx, 0.2, Vec3f{1, 0.71f, 0.29f}}, Brdf{BrdfModel::phong, 3}};
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        mesh.brdf_index.push_back(v % 3 == 2 ? Mesh::kNoBrdf : std::uint32_t(v % 3));
    const TransferSet raw = glossy_box_on_plane(mesh, 25, 64);
    const TransferSet coded = glossy_box_on_plane(mesh, 25, 64, 6, 5);
    const ShLight light = test::smooth_light(25, 25, 6);
    const Camera camera = box_view();
    for (const TransferSet* transfer : {&raw, static_cast<const TransferSet*>(&coded)})
        for (const bool materials : {true, false}) {
            SCOPED_TRACE(::testing::Message() << (transfer == &raw ? "raw" : "cpca")
                                              << (materials ? " materials" : " one BRDF"));
            GlossyShadeOptions shade;
            shade.brdf = parse_brdf("blinn:30:0.3,0.6,0.9");
            shade.material_brdfs = materials;
            shade.k = 0.2;
            shade.eye = camera.eye;
            const ShadeResult cpu = shade_glossy(mesh, *transfer, light, shade);
            DrawSettings settings;
            settings.camera = camera;
            settings.k = shade.k;
            settings.brdf = shade.brdf;
            settings.material_brdfs = materials;
            settings.clear_color = {-1, -1, -1};
            Renderer renderer;
            renderer.set_scene(mesh, *transfer);
            EXPECT_TRUE(renderer.scene_has_material_brdfs());
            renderer.set_light(light);
            RenderTarget target(96, 72, 1);
            target.bind();
            renderer.draw(settings, 96, 72);
            const Image image = target.read_pixels();
            const Comparison c =
                compare_with_reference(image, mesh, cpu.radiance, camera, settings.clear_color);
            EXPECT_GT(c.compared, std::size_t(96 * 72 / 4));
            EXPECT_EQ(c.bad, 0u) << "worst error " << c.worst << " tolerances";
            // The other setting's picture differs: the lobes reach the pixels.
            shade.material_brdfs = !materials;
            const Comparison other = compare_with_reference(
                image, mesh, shade_glossy(mesh, *transfer, light, shade).radiance, camera,
                settings.clear_color);
            EXPECT_GT(other.bad, other.compared / 4);
        }
}

// A CPCA code on the GPU: the light is multiplied by the cluster matrices once per light and K',
// not per frame, and only the code is uploaded.
TEST(GlRender, CpcaClusterPassRunsWhenTheLightChangesOnly) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("box_on_plane");
    const TransferSet transfer = glossy_box_on_plane(mesh, 16, 64, 4, 3);
    Renderer renderer;
    renderer.set_scene(mesh, transfer);
    EXPECT_TRUE(renderer.scene_has_matrices());
    const std::size_t D = transfer.layout.floats_per_receiver();
    EXPECT_DOUBLE_EQ(renderer.transfer_bytes_per_vertex(),
                     cpca_bytes_per_receiver(transfer.cpca, D, mesh.vertex_count(), 4));
    EXPECT_LT(renderer.transfer_bytes_per_vertex(), double(D) * 4);
    renderer.set_light(test::smooth_light(16, 16, 3));
    RenderTarget target(32, 32, 1);
    target.bind();
    DrawSettings settings;
    settings.camera = default_camera(mesh, 1.0f);
    settings.k = 0.5;
    settings.brdf = parse_brdf("phong:12");
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.cluster_passes(), 1u);
    EXPECT_EQ(renderer.shading_passes(), 1u);
    settings.camera.eye = settings.camera.eye * 1.2f;  // the eye: the vertex pass only
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.cluster_passes(), 1u);
    EXPECT_EQ(renderer.shading_passes(), 2u);
    settings.brdf = parse_brdf("ggx:0.4");  // the BRDF: the vertex pass only
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.cluster_passes(), 1u);
    EXPECT_EQ(renderer.shading_passes(), 3u);
    renderer.set_light(test::smooth_light(16, 16, 4));  // the light: both
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.cluster_passes(), 2u);
    settings.K_used = 9;  // K': both
    renderer.draw(settings, 32, 32);
    EXPECT_EQ(renderer.cluster_passes(), 3u);
    EXPECT_EQ(renderer.shading_passes(), 5u);
    EXPECT_THROW(renderer.update_transfer(0, 1, transfer.coeffs.data()), Error);
}

TEST(GlRender, BadUseThrows) {
    REQUIRE_GL(context);
    Renderer renderer;
    DrawSettings settings;
    EXPECT_THROW(renderer.draw(settings, 16, 16), Error);  // no scene, no light
    const Mesh mesh = make_builtin("plane");
    TransferSet transfer = test::analytic_transfer(mesh, 9);
    renderer.set_scene(mesh, transfer);
    renderer.set_light(make_light({"constant"}, 9));
    settings.k = 2;
    EXPECT_THROW(renderer.draw(settings, 16, 16), Error);
    transfer.coeffs.pop_back();
    EXPECT_THROW(renderer.set_scene(mesh, transfer), Error);
    EXPECT_THROW(RenderTarget(0, 10), Error);
    // A light larger than the uniform block, or with the wrong number of coefficients.
    ShLight huge;
    huge.K = kMaxLightK + 1;
    huge.coeffs.assign(3 * std::size_t(huge.K), 0.0f);
    EXPECT_THROW(renderer.set_light(huge), Error);
    ShLight short_light = make_light({"constant"}, 9);
    short_light.coeffs.pop_back();
    EXPECT_THROW(renderer.set_light(short_light), Error);
    EXPECT_FALSE(context->description().empty());
    EXPECT_NE(context->description().find("OpenGL"), std::string::npos);
}

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

TEST(GlRender, TheRoomLooksLit) {
    REQUIRE_GL(context);
    const Mesh room = generate_room({});
    BakeOptions options;
    options.K = 16;
    options.samples = 128;
    const TransferSet transfer = bake(room, options);
    const ShLight light = make_light({"builtin"}, 16);
    DrawSettings settings;
    const int w = 320, h = 180;
    settings.camera = default_camera(room, float(w) / float(h));
    const Image image = render_image(room, transfer, light, settings, w, h);
    std::vector<double> lum;
    std::size_t background = 0;
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        const float* p = image.rgb.data() + 3 * i;
        if (p[0] == 0 && p[1] == 0 && p[2] == 0) {
            ++background;
            continue;
        }
        lum.push_back(luminance(p));
        ASSERT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
    }
    // Mostly room (the open top shows some sky-less black at the top of the frame).
    EXPECT_LT(double(background) / double(image.pixel_count()), 0.3);
    std::sort(lum.begin(), lum.end());
    double mean = 0;
    for (double l : lum) mean += l;
    mean /= double(lum.size());
    // Albedo ≤ 1 under a sky of irradiance ~3 to 6: radiance of order 0.1 to 2.
    EXPECT_GT(mean, 0.05);
    EXPECT_LT(mean, 3.0);
    // Shadows and lit areas: the darker pixels of the room are much darker than the bright ones.
    const double p20 = lum[lum.size() / 5];
    const double p90 = lum[lum.size() * 9 / 10];
    EXPECT_LT(p20, 0.5 * p90) << "p20 " << p20 << " p90 " << p90;
    EXPECT_GT(p90, 0.2);
}

}  // namespace
}  // namespace shprt
