// The renderer's sun kept out of the SH sum (Renderer::set_sun, render/sun_pass.hpp) against its
// CPU twin (shade/sun_shade.hpp) at the pixels' surface points: the direct sun traced with Embree
// over the disc, and the sky and the bounced sun interpolated from shade_with_sun's vertices.
#include "render_test_util.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/sun_shade.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace shprt {
namespace {

// Agreement away from shadow edges: float shading and interpolation against double.
constexpr double kRelTolerance = 1e-3, kAbsTolerance = 1e-4;
// The penumbra the map draws against the traced one, as the mean over floor pixels of
// |V_gl − V_traced| in pixels' worth per pixel of traced penumbra (see the test).
constexpr double kMaxEdgeError = 0.35;

enum class Class { lit, umbra, penumbra, other };

// What the camera sees at each pixel centre (row 0 at the top): the hit point, the interpolated
// normal (normalised) and albedo, the triangle's face normal's class, or no hit.
struct PixelSurface {
    bool hit = false;
    std::uint32_t plane = 0;  // equal for pixels on one flat face of the scene (by face normal)
    Vec3f position, normal, albedo;
    float u = 0, v = 0;
    std::uint32_t triangle = 0;
};

std::vector<PixelSurface> surfaces(const Mesh& mesh, const Tracer& tracer, const Camera& camera,
                                   int w, int h) {
    std::vector<PixelSurface> out(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Vec3f o, d;
            pixel_ray(camera, w, h, float(x) + 0.5f, float(y) + 0.5f, o, d);
            const Hit hit = tracer.intersect(o, d, 0.0f, 1e30f);
            PixelSurface& s = out[std::size_t(y) * w + x];
            if (!hit.hit) continue;
            const auto& t = mesh.triangles[hit.triangle];
            const float a = 1 - hit.u - hit.v;
            auto lerp = [&](const std::vector<Vec3f>& v) {
                return v[t[0]] * a + v[t[1]] * hit.u + v[t[2]] * hit.v;
            };
            s.hit = true;
            s.triangle = hit.triangle;
            s.u = hit.u;
            s.v = hit.v;
            s.position = o + d * hit.t;
            s.normal = normalize(lerp(mesh.normals));
            s.albedo = lerp(mesh.albedo);
            const Vec3f face = normalize(cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                                               mesh.positions[t[2]] - mesh.positions[t[0]]));
            // Faces of box_on_plane are axis-aligned: the axis and sign, and the offset.
            const int axis = std::abs(face.x) > 0.9f ? 0 : std::abs(face.y) > 0.9f ? 1 : 2;
            const float offset = s.position[axis];
            s.plane = std::uint32_t(axis * 2 + (face[axis] > 0)) * 1000u +
                      std::uint32_t(std::lround((offset + 10.0f) * 16.0f));
        }
    return out;
}

// The traced sun's fraction of the unoccluded disc at each surface, and the unoccluded E.
struct TracedSun {
    std::vector<Vec3f> E;
    std::vector<double> full, fraction;
};

TracedSun traced_sun(const Tracer& tracer, const std::vector<PixelSurface>& px, const Sun& sun,
                     int disc_samples) {
    std::vector<Vec3f> positions, normals;
    for (const PixelSurface& s : px) {
        positions.push_back(s.position);
        normals.push_back(s.normal);
    }
    SunShadeOptions options;
    options.disc_samples = disc_samples;
    TracedSun t;
    t.E = sun_direct_irradiance(tracer, positions, normals, sun, options);
    const std::vector<Vec3d> dirs = sun_disc_directions(sun, disc_samples, options.seed);
    for (std::size_t i = 0; i < px.size(); ++i) {
        double full = 0;
        for (const Vec3d& d : dirs) full += std::max(0.0, dot(cast<double>(normals[i]), d));
        full *= sun.radiance.x * sun_solid_angle(sun) / double(dirs.size());
        t.full.push_back(full);
        t.fraction.push_back(full > 0 ? double(t.E[i].x) / full : 0.0);
    }
    return t;
}

// Pixels whose whole (2r+1)² neighbourhood is on the same face and fully lit or fully in the
// umbra of the traced sun: there the shadow map must agree exactly (its edges stay away).
std::vector<Class> classify(const std::vector<PixelSurface>& px, const TracedSun& sun, int w, int h,
                            int r) {
    auto pixel_class = [&](std::size_t i) {
        if (!px[i].hit || sun.full[i] <= 0) return Class::other;
        // Every disc direction unoccluded (the sum in float against the same sum in double).
        if (sun.fraction[i] > 1 - 1e-6) return Class::lit;
        if (sun.E[i].x == 0) return Class::umbra;
        return Class::penumbra;
    };
    std::vector<Class> out(px.size(), Class::other);
    for (int y = r; y < h - r; ++y)
        for (int x = r; x < w - r; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const Class c = pixel_class(i);
            bool same = c == Class::lit || c == Class::umbra;
            for (int dy = -r; dy <= r && same; ++dy)
                for (int dx = -r; dx <= r && same; ++dx) {
                    const std::size_t j = std::size_t(y + dy) * w + (x + dx);
                    same = pixel_class(j) == c && px[j].plane == px[i].plane;
                }
            out[i] = same ? c : c == Class::penumbra ? Class::penumbra : Class::other;
        }
    return out;
}

Camera shadow_camera(const Mesh& mesh) {
    // From above the box's shadow (the sun is toward +X, so the shadow falls toward −X).
    return look_at_camera({-0.4f, 2.6f, 1.7f}, {-1.0f, 0.0f, 0.0f}, 50.0f, mesh_bounds(mesh));
}

// A sun toward +X, 50° up and a little toward +Z, of radius 2° (a box 1 m high: a penumbra of
// up to 2 · 1.4 m · tan 2° ≈ 10 cm, several pixels), E = (3, 2.5, 2) at normal incidence.
Sun test_sun() { return make_sun({1, 1.2, 0.3}, 2, sun_radiance_for_irradiance({3, 2.5, 2}, 2)); }

// builtin:box_on_plane with analytic (unshadowed) transfer of 4 coefficients, under test_sun().
struct DirectScene {
    Mesh mesh = make_builtin("box_on_plane");
    TransferSet transfer = test::analytic_transfer(mesh, 4);
    Sun sun = test_sun();
    PreparedSun prepared{sun, sun_light(sun, 4)};
};

// With no sky, each pixel is ρ/π · E_sun. Away from shadow edges it is the traced value to
// float precision; across the penumbra, the map's visibility V_gl = pixel / (ρ/π · E_full)
// follows the traced fraction of the disc: the mean |V_gl − V_traced| over the floor, times
// the floor's pixel count, is the error in "pixels' worth" — at most kMaxEdgeError of the traced
// penumbra's pixel count (an edge a pixel off all along would be 1).
// One frame with the sun's filter `filter` in the current context.
Image draw_with_filter(const Mesh& mesh, const TransferSet& transfer, const DrawSettings& settings,
                       int w, int h, const PreparedSun& sun, SunFilter filter) {
    Renderer renderer;
    renderer.set_sun_filter(filter);
    renderer.set_sun(&sun);
    renderer.set_scene(mesh, transfer);
    renderer.set_light(ShLight::zero(transfer.layout.K));
    RenderTarget target(w, h, 1);
    target.bind();
    renderer.draw(settings, w, h);
    return target.read_pixels();
}

// Both filters: the full one (`render`, --screenshot) and the interactive one (the viewer's
// continuous frames on a software rasteriser), each with the same bounds.
class GlSunFilter : public ::testing::TestWithParam<SunFilter> {};

TEST_P(GlSunFilter, DirectSunMatchesTheTracedSunAtEveryPixel) {
    REQUIRE_GL(context);
    const DirectScene scene;
    const Mesh& mesh = scene.mesh;
    const TransferSet& transfer = scene.transfer;
    const Sun& sun = scene.sun;
    const PreparedSun& prepared = scene.prepared;
    DrawSettings settings;
    settings.camera = shadow_camera(mesh);
    const int w = 192, h = 144;
    const Image image = draw_with_filter(mesh, transfer, settings, w, h, prepared, GetParam());

    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    const std::vector<PixelSurface> px = surfaces(mesh, *tracer, settings.camera, w, h);
    const TracedSun traced = traced_sun(*tracer, px, sun, 256);
    const std::vector<Class> cls = classify(px, traced, w, h, 2);

    std::size_t lit = 0, umbra = 0, bad = 0, floor_pixels = 0, penumbra_pixels = 0;
    double worst = 0, edge_error = 0;
    for (std::size_t i = 0; i < px.size(); ++i) {
        if (!px[i].hit) continue;
        const float* p = image.pixel(int(i % w), int(i / w));
        const Vec3f rho = px[i].albedo;
        if (cls[i] == Class::lit || cls[i] == Class::umbra) {
            (cls[i] == Class::lit ? lit : umbra) += 1;
            for (int c = 0; c < 3; ++c) {
                const double want = double(rho[c]) / kPi * double(traced.E[i][c]);
                const double err =
                    std::abs(p[c] - want) / (kRelTolerance * std::abs(want) + kAbsTolerance);
                worst = std::max(worst, err);
                if (err > 1 && bad++ < 5)
                    ADD_FAILURE() << "pixel " << i % w << "," << i / w << " channel " << c << ": "
                                  << p[c] << " vs traced " << want;
            }
        }
        // The floor (y = 0, facing up), for the edge.
        if (px[i].normal.y > 0.999f && std::abs(px[i].position.y) < 1e-4f) {
            ++floor_pixels;
            const double v_gl = p[0] / (double(rho.x) / kPi * traced.full[i]);
            edge_error += std::abs(v_gl - traced.fraction[i]);
            penumbra_pixels += traced.E[i].x > 0 && traced.fraction[i] < 1 - 1e-6;
        }
    }
    std::printf(
        "%s filter: lit %zu, umbra %zu pixels away from edges (worst %.3f of the tolerance); "
        "floor %zu pixels, traced penumbra %zu, |V_gl - V_traced| summed %.1f pixels\n",
        GetParam() == SunFilter::full ? "full" : "interactive", lit, umbra, worst, floor_pixels,
        penumbra_pixels, edge_error);
    EXPECT_EQ(bad, 0u);
    EXPECT_GT(lit, 2000u);
    EXPECT_GT(umbra, 300u);
    ASSERT_GT(penumbra_pixels, 100u);
    EXPECT_LT(edge_error, kMaxEdgeError * double(penumbra_pixels));
}

INSTANTIATE_TEST_SUITE_P(Filters, GlSunFilter,
                         ::testing::Values(SunFilter::full, SunFilter::interactive),
                         [](const auto& info) {
                             return info.param == SunFilter::full ? "Full" : "Interactive";
                         });

// An interreflected file under a sky and the sun: every pixel away from the sun's shadow edges
// is shade_with_sun's sky and bounced sun interpolated from the vertices (the draw's colours)
// plus the traced direct sun at the pixel — so the draw counts the sun's SH part through T_0
// once, subtracted, and the bounces once. Irradiance view (E) and radiance view (ρ/π · E).
// Interreflected transfer of K = 16 (one bounce, `samples` directions), with its direct part.
TransferSet bounced_transfer(const Mesh& mesh, int samples) {
    BakeOptions options;
    options.transfer = TransferKind::interreflected;
    options.K = 16;
    options.samples = samples;
    options.bounces = 1;
    return bake(mesh, options);
}

TEST(GlSun, SkyAndBouncedSunAreShadeWithSunsVertices) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("box_on_plane");
    const TransferSet T = bounced_transfer(mesh, 64);
    ASSERT_FALSE(T.direct.empty());
    const Sun sun = test_sun();
    const PreparedSun prepared{sun, sun_light(sun, 16)};
    const ShLight sky = gradient_light(GradientSky{}, 16);
    SunShadeOptions sun_options;
    sun_options.disc_samples = 1;  // only the vertex part is used below
    const SunShadeResult split =
        shade_with_sun(mesh, T, sky, prepared, ShadeOptions{}, sun_options);
    ASSERT_TRUE(split.bounced);

    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    DrawSettings settings;
    settings.camera = shadow_camera(mesh);
    const int w = 128, h = 96;
    const std::vector<PixelSurface> px = surfaces(mesh, *tracer, settings.camera, w, h);
    const TracedSun traced = traced_sun(*tracer, px, sun, 256);
    const std::vector<Class> cls = classify(px, traced, w, h, 2);
    // The bounced sun is a visible part of the picture, or the test would not see it.
    double bounced_share = 0;
    {
        const ShadeResult sky_only = shade_vertices(mesh, T, sky, ShadeOptions{});
        double b = 0, all = 0;
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
            b += split.irradiance[v].x - sky_only.irradiance[v].x - split.sun_direct[v].x;
            all += split.irradiance[v].x;
        }
        bounced_share = b / all;
    }
    EXPECT_GT(bounced_share, 0.02);

    for (const ShadeView view : {ShadeView::irradiance, ShadeView::radiance}) {
        settings.view = view;
        const Image image = render_image(mesh, T, sky, settings, w, h, 1, &prepared);
        // The vertices' colours without their direct sun (the draw's per-vertex part).
        std::vector<Vec3f> vertex(mesh.vertex_count());
        for (std::size_t v = 0; v < vertex.size(); ++v) {
            const Vec3f d = split.sun_direct[v];
            const Vec3f rho = mesh.albedo[v];
            vertex[v] =
                view == ShadeView::irradiance
                    ? split.irradiance[v] - d
                    : split.radiance[v] - Vec3f{rho.x * d.x, rho.y * d.y, rho.z * d.z} / float(kPi);
        }
        std::size_t compared = 0, bad = 0;
        for (std::size_t i = 0; i < px.size(); ++i) {
            if (cls[i] != Class::lit && cls[i] != Class::umbra) continue;
            const auto& t = mesh.triangles[px[i].triangle];
            const float a = 1 - px[i].u - px[i].v;
            const Vec3f base = vertex[t[0]] * a + vertex[t[1]] * px[i].u + vertex[t[2]] * px[i].v;
            const Vec3f rho = px[i].albedo;
            const float* p = image.pixel(int(i % w), int(i / w));
            ++compared;
            for (int c = 0; c < 3; ++c) {
                const double direct = view == ShadeView::irradiance
                                          ? double(traced.E[i][c])
                                          : double(rho[c]) / kPi * double(traced.E[i][c]);
                const double want = double(base[c]) + direct;
                if (std::abs(p[c] - want) > kRelTolerance * std::abs(want) + kAbsTolerance &&
                    bad++ < 5)
                    ADD_FAILURE() << int(view) << " pixel " << i % w << "," << i / w << " channel "
                                  << c << ": " << p[c] << " vs " << want;
            }
        }
        EXPECT_EQ(bad, 0u);
        EXPECT_GT(compared, 3000u);
    }
}

// Glossy matrices (k = 0.5, Phong 16) under the sun and no sky: away from shadow edges each pixel
// is shade_glossy_with_sun's sum at the pixel's surface point — k·ρ/π·E + (1 − k)·L·Ω·mean f(r·d_j)
// over the disc's traced directions, r the eye's reflection there — lit, and 0 in the umbra.
TEST(GlSun, GlossyMatricesGetTheSunThroughTheirLobe) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("box_on_plane");
    BakeOptions options;
    options.transfer = TransferKind::glossy;
    options.K = 9;
    options.samples = 64;
    const TransferSet T = bake(mesh, options);
    const Sun sun = test_sun();
    const PreparedSun prepared{sun, sun_light(sun, 9)};
    DrawSettings settings;
    settings.camera = shadow_camera(mesh);
    settings.k = 0.5;
    settings.brdf = Brdf{BrdfModel::phong, 16};
    const int w = 160, h = 120;
    const Image image = render_image(mesh, T, ShLight::zero(9), settings, w, h, 1, &prepared);

    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    const std::vector<PixelSurface> px = surfaces(mesh, *tracer, settings.camera, w, h);
    const TracedSun traced = traced_sun(*tracer, px, sun, 256);
    const std::vector<Class> cls = classify(px, traced, w, h, 2);
    const BrdfProfile f = brdf_profile(settings.brdf);
    const std::vector<Vec3d> dirs = sun_disc_directions(sun, 256, SunShadeOptions{}.seed);
    const Vec3d eye = cast<double>(settings.camera.eye);
    std::size_t lit = 0, umbra = 0, bad = 0;
    double worst = 0;
    for (std::size_t i = 0; i < px.size(); ++i) {
        if (cls[i] != Class::lit && cls[i] != Class::umbra) continue;
        const Vec3d n = cast<double>(px[i].normal), p = cast<double>(px[i].position);
        const Vec3d r = reflect_view(n, p, eye);
        double lobe = 0;
        for (const Vec3d& d : dirs)
            if (dot(n, d) > 0) lobe += f(dot(r, d));
        lobe *= sun_solid_angle(sun) / double(dirs.size());
        const bool in_sun = cls[i] == Class::lit;
        (in_sun ? lit : umbra) += 1;
        const float* q = image.pixel(int(i % w), int(i / w));
        for (int c = 0; c < 3; ++c) {
            const double want = in_sun ? 0.5 * double(px[i].albedo[c]) / kPi * traced.E[i][c] +
                                             0.5 * sun.radiance[c] * lobe
                                       : 0.0;
            const double err = std::abs(q[c] - want) / (kRelTolerance * want + kAbsTolerance);
            worst = std::max(worst, err);
            if (err > 1 && bad++ < 5)
                ADD_FAILURE() << "pixel " << i % w << "," << i / w << " channel " << c << ": "
                              << q[c] << " vs " << want;
        }
    }
    std::printf("glossy: lit %zu, umbra %zu pixels away from edges (worst %.3f of the tolerance)\n",
                lit, umbra, worst);
    EXPECT_EQ(bad, 0u);
    EXPECT_GT(lit, 2000u);
    EXPECT_GT(umbra, 200u);
}

// The sun turns with the light: set_light's rotation moves the shadow, and the map is drawn
// again only when the sun's direction changes.
TEST(GlSun, TheSunTurnsWithTheLightAndTheMapFollows) {
    REQUIRE_GL(context);
    const DirectScene scene;
    const Mesh& mesh = scene.mesh;
    const TransferSet& transfer = scene.transfer;
    const PreparedSun& prepared = scene.prepared;
    Renderer renderer;
    renderer.set_sun(&prepared);
    renderer.set_scene(mesh, transfer);
    renderer.set_light(ShLight::zero(4));
    EXPECT_FALSE(renderer.sun_bounced());
    DrawSettings settings;
    settings.camera = shadow_camera(mesh);
    const int w = 96, h = 72;
    RenderTarget target(w, h, 1);
    auto frame = [&] {
        target.bind();
        renderer.draw(settings, w, h);
        target.resolve();
        return target.read_pixels();
    };
    const Image a = frame();
    (void)frame();
    EXPECT_EQ(renderer.sun_map_builds(), 1u);
    // Half a turn about +Y: the sun is now toward −X and the shadow falls toward +X, out of the
    // picture; the pixels that were in the umbra are lit.
    renderer.set_light(ShLight::zero(4), rotation_y(kPi));
    const Image b = frame();
    EXPECT_EQ(renderer.sun_map_builds(), 2u);
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    const std::vector<PixelSurface> px = surfaces(mesh, *tracer, settings.camera, w, h);
    std::size_t darker = 0, floor = 0;
    for (std::size_t i = 0; i < px.size(); ++i)
        // The shadow of the box's top (y = 1) is offset by (−1/1.2, −0.3/1.2) in x and z.
        if (px[i].hit && px[i].normal.y > 0.999f && px[i].position.x < -0.6f &&
            px[i].position.x > -1.2f && std::abs(px[i].position.z + 0.25f) < 0.4f) {
            ++floor;
            darker +=
                a.pixel(int(i % w), int(i / w))[0] < 0.1f * b.pixel(int(i % w), int(i / w))[0];
        }
    EXPECT_GT(floor, 50u);
    EXPECT_EQ(darker, floor) << "floor pixels in the shadow before the turn and lit after it";
    // The paper's glossy term of vector transfer is refused with the sun (not linear in the light).
    settings.k = 0.5;
    EXPECT_THROW(renderer.draw(settings, w, h), Error);
}

// While the sun moves the frame draws the coarser map (set_moving_shadow_map_size); the first
// frame at rest redraws the full one and is the picture a renderer without a moving map draws.
TEST(GlSun, AMovingSunDrawsTheCoarseMapAndTheFirstFrameAtRestTheFullOne) {
    REQUIRE_GL(context);
    const DirectScene scene;
    DrawSettings settings;
    settings.camera = shadow_camera(scene.mesh);
    const int w = 96, h = 72;
    const Mat3d turned = rotation_y(0.3);
    auto make = [&](int moving) {
        auto r = std::make_unique<Renderer>();
        r->set_shadow_map_size(1024);
        r->set_moving_shadow_map_size(moving);
        r->set_sun(&scene.prepared);
        r->set_scene(scene.mesh, scene.transfer);
        r->set_light(ShLight::zero(4));
        return r;
    };
    RenderTarget target(w, h, 1);
    auto frame = [&](Renderer& r) {
        target.bind();
        r.draw(settings, w, h);
        target.resolve();
        return target.read_pixels();
    };
    const auto same = [&](const Image& a, const Image& b) {
        std::size_t differ = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                differ += std::memcmp(a.pixel(x, y), b.pixel(x, y), 3 * sizeof(float)) != 0;
        return differ;
    };
    const std::unique_ptr<Renderer> full = make(0);
    full->set_light(ShLight::zero(4), turned);
    const Image want = frame(*full);

    const std::unique_ptr<Renderer> r = make(128);
    const Image first = frame(*r);  // at rest: the full map
    EXPECT_EQ(r->sun_map_builds(), 1u);
    r->set_light(ShLight::zero(4), turned);  // the sun moves
    const Image moving = frame(*r);
    EXPECT_EQ(r->sun_map_builds(), 2u);
    const Image rest = frame(*r);  // the same sun: at rest again, the full map redrawn
    EXPECT_EQ(r->sun_map_builds(), 3u);
    (void)frame(*r);
    EXPECT_EQ(r->sun_map_builds(), 3u) << "nothing moves: no map is redrawn";
    EXPECT_EQ(same(rest, want), 0u) << "the first frame at rest is the full map's picture";
    EXPECT_GT(same(moving, want), std::size_t(w * h / 200))
        << "a 128² map's shadow edges differ from the 1024² map's";
    EXPECT_GT(same(first, want), 0u);
    EXPECT_THROW(r->set_moving_shadow_map_size(32), Error);
}

// The diffuse sum on the host (Renderer::set_vertex_shading, with the sun's bounce folded in)
// against the compute pass: the same picture to float rounding, in both views, before and after
// the light (and the sun with it) turns (float sums in another order, and T·(c_sky + c_sun) −
// T_0·c_sun cancels: 5e-5 relative).
TEST(GlSun, HostAndDeviceShadingAgree) {
    REQUIRE_GL(context);
    const Mesh mesh = make_builtin("box_on_plane");
    const TransferSet T = bounced_transfer(mesh, 16);
    const Sun sun = test_sun();
    const PreparedSun prepared{sun, sun_light(sun, 16)};
    const ShLight sky = gradient_light(GradientSky{}, 16);
    DrawSettings settings;
    settings.camera = shadow_camera(mesh);
    const int w = 64, h = 48;
    RenderTarget target(w, h, 1);
    auto frame = [&](Renderer& renderer, bool host) {
        renderer.set_vertex_shading(host ? Renderer::VertexShading::host
                                         : Renderer::VertexShading::device);
        target.bind();
        renderer.draw(settings, w, h);
        EXPECT_EQ(renderer.last_shading_on_host(), host);
        target.resolve();
        return target.read_pixels();
    };
    for (const bool with_sun : {false, true}) {
        Renderer renderer;
        renderer.set_sun(with_sun ? &prepared : nullptr);
        renderer.set_scene(mesh, T);
        renderer.set_light(sky);
        ASSERT_EQ(renderer.sun_bounced(), with_sun);
        for (const Mat3d& turn : {Mat3d::identity(), rotation_y(0.7)}) {
            renderer.set_light(sky, turn);
            for (const ShadeView view : {ShadeView::irradiance, ShadeView::radiance}) {
                settings.view = view;
                const Image device = frame(renderer, false), host = frame(renderer, true);
                std::size_t bad = 0, lit = 0;
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x)
                        for (int c = 0; c < 3; ++c) {
                            const float a = device.pixel(x, y)[c], b = host.pixel(x, y)[c];
                            lit += a > 0.01f;
                            if (std::abs(a - b) > 5e-5f * std::abs(a) + 1e-6f && bad++ < 5)
                                ADD_FAILURE()
                                    << with_sun << " view " << int(view) << " pixel " << x << ","
                                    << y << " channel " << c << ": device " << a << ", host " << b;
                        }
                EXPECT_EQ(bad, 0u);
                EXPECT_GT(lit, std::size_t(w * h));
            }
        }
    }
}

}  // namespace
}  // namespace shprt
