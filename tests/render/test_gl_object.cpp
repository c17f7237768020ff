// A probe-lit dynamic object drawn by the renderer (Renderer::set_object): every pixel of the
// object is shade_object's CPU colours interpolated where the pixel's ray hits it, beside the
// scene's own pixels.
#include "common/probe_grids.hpp"
#include "render/render_test_util.hpp"
#include "shprt/bake/object_bake.hpp"
#include "shprt/shade/object_shade.hpp"

namespace shprt {
namespace {

constexpr double kRelTolerance = 2e-3, kAbsTolerance = 1e-4;

TEST(GlObject, ObjectPixelsAreTheCpuShadingInterpolated) {
    REQUIRE_GL(context);
    constexpr int K = 9;
    const Mesh scene = make_builtin("plane");
    const TransferSet transfer = test::analytic_transfer(scene, K);
    const ShLight light = test::smooth_light(K, K);
    ObjectBakeOptions o;
    o.K = K;
    o.samples = 32;
    const DynamicObject object = make_dynamic_object(make_builtin("sphere"), o);
    // Brighter toward +x, so the object's colours vary across it.
    const ProbeGrid grid = test::identity_probe_grid({-1, 0, -1}, {1, 1, 1}, {3, 2, 3}, K,
                                                     [](Vec3f p) { return 0.6f + 0.3f * p.x; });
    ObjectPose pose;
    pose.position = {0.2f, 0.5f, 0.1f};
    pose.scale = 0.4f;
    pose.yaw_pitch_roll_deg = {20, 10, 0};
    DrawSettings settings;
    settings.camera = look_at_camera({0, 2.2f, 2.4f}, {0, 0.2f, 0}, 40, mesh_bounds(scene));
    ObjectShadeOptions options;
    options.eye = settings.camera.eye;
    const ObjectShading lit = shade_object(object, pose, grid, light, options);
    const DrawnObject drawn{&object.mesh, &lit};
    const int w = 80, h = 60;
    const Image image = render_image(scene, transfer, light, settings, w, h, 1, nullptr, &drawn);

    // The reference: the object placed (its world positions) with its CPU colours, and the
    // scene's CPU shading; a pixel is the object's where its ray hits the object first.
    Mesh placed = object.mesh;
    placed.positions = lit.positions;
    const std::vector<Vec3f> scene_values = shade_vertices(scene, transfer, light, {}).radiance;
    std::size_t object_pixels = 0, scene_pixels = 0, bad = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Vec3f origin, dir;
            pixel_ray(settings.camera, w, h, float(x) + 0.5f, float(y) + 0.5f, origin, dir);
            Vec3d ref, on_scene;
            double t_object, t_scene;
            const bool object_hit =
                test::trace_interpolate(placed, lit.radiance, origin, dir, ref, t_object);
            const bool scene_hit =
                test::trace_interpolate(scene, scene_values, origin, dir, on_scene, t_scene);
            if (!object_hit || (scene_hit && t_scene < t_object)) {
                if (!scene_hit) continue;
                ref = on_scene;
                ++scene_pixels;
            } else {
                ++object_pixels;
            }
            const float* p = image.pixel(x, y);
            double worst = 0;
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(p[c] - ref[c]) /
                                            (kRelTolerance * std::abs(ref[c]) + kAbsTolerance));
            if (worst > 1 && bad++ < 5) std::printf("pixel %d,%d: %g vs %g\n", x, y, p[0], ref.x);
        }
    std::printf("%zu object pixels, %zu scene pixels, %zu off\n", object_pixels, scene_pixels, bad);
    EXPECT_GT(object_pixels, 300u);
    EXPECT_GT(scene_pixels, 1000u);
    // Pixels whose centre the rasteriser and the ray caster see on other sides of a silhouette.
    EXPECT_LE(bad, (object_pixels + scene_pixels) / 100);
}

// Under a sun kept out of the SH sum (and a black sky) the object is lit by the sun's direct term
// alone, and it casts into the sun's shadow map: the plane under it darkens.
TEST(GlObject, TheSunLightsTheObjectAndTheObjectCastsIntoItsShadowMap) {
    REQUIRE_GL(context);
    constexpr int K = 9;
    const Mesh scene = make_builtin("plane");
    const TransferSet transfer = test::analytic_transfer(scene, K);
    const ShLight black = ShLight::zero(K);
    const Sun sun = make_sun({0, 1, 0}, 1, {3, 3, 3});
    const PreparedSun prepared{sun, sun_light(sun, K)};
    ObjectBakeOptions o;
    o.K = K;
    o.self_shadow = false;
    const DynamicObject object = make_dynamic_object(make_builtin("sphere"), o);
    const ProbeGrid grid = test::identity_probe_grid({-1, 0, -1}, {1, 1, 1}, {3, 2, 3}, K);
    ObjectPose pose;
    pose.position = {0, 0.6f, 0};
    pose.scale = 0.3f;
    DrawSettings settings;
    settings.camera = look_at_camera({0, 1.2f, 2.5f}, {0, 0.2f, 0}, 45, mesh_bounds(scene));
    const ObjectShading lit = shade_object(object, pose, grid, black, {});
    const DrawnObject drawn{&object.mesh, &lit};
    const int w = 64, h = 48;
    const Image bare = render_image(scene, transfer, black, settings, w, h, 1, &prepared);
    const Image with = render_image(scene, transfer, black, settings, w, h, 1, &prepared, &drawn);
    // The sun's direct radiance on the plane: ρ/π · E_n, E_n ≈ radiance · disc solid angle.
    double lit_plane = 0;
    for (int i = 0; i < w * h; ++i) lit_plane = std::max(lit_plane, double(bare.rgb[3 * i]));
    ASSERT_GT(lit_plane, 0);
    std::size_t shadowed = 0, sunlit_object = 0;
    for (int i = 0; i < w * h; ++i) {
        const double a = bare.rgb[3 * i], b = with.rgb[3 * i];
        if (a > 0.9 * lit_plane && b < 0.1 * lit_plane) ++shadowed;  // plane, now in shadow
        if (a != b && b > 0.5 * lit_plane) ++sunlit_object;          // the object's sunlit top
    }
    std::printf("%zu plane pixels in the object's shadow, %zu sunlit object pixels\n", shadowed,
                sunlit_object);
    for (const Vec3f& c : lit.radiance) ASSERT_EQ(c.x, 0.0f);  // no sky: the CPU colours are 0
    EXPECT_GT(shadowed, 30u) << "the object's shadow on the plane";
    EXPECT_GT(sunlit_object, 20u) << "the sun on the object";
}

}  // namespace
}  // namespace shprt
