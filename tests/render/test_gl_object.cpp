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

}  // namespace
}  // namespace shprt
