// The Tracer interface, for both implementations (Embree and the flat BVH on the CPU):
// self-intersection on flat planes, a box on a plane against brute force, barycentrics, bad
// input, and thread safety.
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/trace/tracer.hpp"

#include "trace/trace_test_util.hpp"

// White-box: the private Embree device wrapper of src/trace.
#include "../src/trace/embree_common.hpp"

#include <gtest/gtest.h>

#if defined(__x86_64__) || defined(__SSE__)
#include <xmmintrin.h>
#define SHPRT_TEST_HAS_MXCSR 1
#else
#define SHPRT_TEST_HAS_MXCSR 0
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>

namespace shprt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

using Factory = std::function<std::unique_ptr<Tracer>(const Mesh&)>;

struct Backend {
    const char* name;
    Factory make;
};

std::vector<Backend> backends() {
    return {{"embree", [](const Mesh& m) { return make_embree_tracer(m); }},
            {"flat-bvh", [](const Mesh& m) { return make_flat_bvh_tracer(m); }}};
}

// Every vertex of a flat plane, under an open sky, sees nothing in its upper hemisphere: counts
// occluded rays (must be zero) over `dirs` per vertex, with the documented ray convention.
long count_self_shadowed(const Tracer& tracer, const Mesh& m, Vec3f normal,
                         const std::vector<Vec3f>& dirs) {
    long occluded = 0;
    std::vector<std::uint8_t> occ(dirs.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const Vec3f origin = offset_ray_origin(m.positions[v], normal);
        tracer.occluded(origin, dirs.data(), static_cast<int>(dirs.size()), 0.0f, kInf, occ.data());
        for (std::uint8_t o : occ) occluded += o;
        // Closest hit on a sample of the same rays.
        for (std::size_t i = v % 16; i < dirs.size(); i += 16)
            if (tracer.intersect(origin, dirs[i], 0.0f, kInf).hit) ++occluded;
    }
    return occluded;
}

TEST(Tracer, FlatPlaneIsNeverSelfShadowed) {
    constexpr int kDirections = 3000;  // a quarter of them grazing, n·d down to 1e-7
    struct Case {
        std::string name;
        Mesh mesh;
        Vec3f normal;
    };
    std::vector<Case> cases;
    cases.push_back({"y = 0 plane", test::make_plane(32, 2.0f, 0.0f, -1.0f, -1.0f), {0, 1, 0}});
    cases.push_back({"y = 3.7 plane", test::make_plane(32, 2.0f, 3.7f, -1.0f, -1.0f), {0, 1, 0}});
    cases.push_back(
        {"far plane", test::make_plane(24, 64.0f, -250.0f, 1000.0f, -3000.0f), {0, 1, 0}});
    Vec3f tilted_normal;
    Mesh tilted = test::make_tilted_plane(24, tilted_normal);
    cases.push_back({"tilted plane", std::move(tilted), tilted_normal});
    for (const Backend& backend : backends())
        for (const Case& c : cases) {
            const auto tracer = backend.make(c.mesh);
            const auto dirs = test::hemisphere_directions(c.normal, kDirections, 31);
            const long shadowed = count_self_shadowed(*tracer, c.mesh, c.normal, dirs);
            std::printf("%s, %s: %zu vertices x %d directions, %ld occluded\n", backend.name,
                        c.name.c_str(), c.mesh.positions.size(), kDirections, shadowed);
            EXPECT_EQ(shadowed, 0) << backend.name << ", " << c.name;
        }
}

// The plane seen from below is fully occluded: the offset is not hiding real hits.
TEST(Tracer, PlaneOccludesTheOtherSide) {
    const Mesh plane = test::make_plane(8, 2.0f, 0.0f, -1.0f, -1.0f);
    for (const Backend& backend : backends()) {
        const auto tracer = backend.make(plane);
        std::mt19937 rng(1);
        std::uniform_real_distribution<float> u(-0.9f, 0.9f);
        int missed = 0;
        for (int i = 0; i < 2000; ++i) {
            const Vec3f origin{u(rng), 0.5f, u(rng)};
            const Vec3f target{u(rng), 0.0f, u(rng)};
            const Vec3f d = target - origin;
            std::uint8_t occ = 0;
            tracer->occluded(origin, &d, 1, 0.0f, kInf, &occ);
            if (!occ) ++missed;
        }
        EXPECT_EQ(missed, 0) << backend.name;
    }
}

// Box on a plane: the visibility of every vertex (upper hemisphere of its normal) and the closest
// hits equal a brute-force loop over all triangles, on every ray. Counted apart: "crease" rays,
// whose origin lies on another surface (the box's bottom vertices sit on the floor; a hard-edged
// corner vertex lies in the planes of the neighbouring faces, which an offset along its own normal
// does not leave) — their first hit is at t = 0 exactly, which the plane-distance t of ray.hpp
// computes exactly for axis-aligned faces, so they must match too.
TEST(Tracer, BoxOnPlaneEqualsBruteForce) {
    const Mesh scene = test::make_box_on_plane();
    constexpr int kDirections = 96;
    constexpr float kAmbiguousT = 1e-6f;  // the origin offsets here are ≥ 1.5e-5
    struct Ray {
        Vec3f origin;
        std::vector<Vec3f> dirs;
        std::vector<Hit> ref;         // brute force
        std::vector<char> ambiguous;  // crease ray: a surface within kAmbiguousT of the origin
    };
    std::vector<Ray> rays(scene.positions.size());
    long total = 0, ambiguous = 0, occluded = 0;
    parallel_each(0, rays.size(), [&](std::size_t v) {
        Ray& r = rays[v];
        const Vec3f n = scene.normals[v];
        r.origin = offset_ray_origin(scene.positions[v], n);
        r.dirs = test::hemisphere_directions(n, kDirections, static_cast<std::uint32_t>(v));
        for (const Vec3f& d : r.dirs) {
            r.ambiguous.push_back(
                test::brute_force_intersect(scene, r.origin, d, -kAmbiguousT, kAmbiguousT).hit);
            r.ref.push_back(test::brute_force_intersect(scene, r.origin, d, 0.0f, kInf));
        }
    });
    for (const Ray& r : rays)
        for (int i = 0; i < kDirections; ++i) {
            ++total;
            ambiguous += r.ambiguous[i];
            occluded += r.ref[i].hit;
        }
    std::printf("box on plane: %ld rays, %ld of them crease rays, %ld occluded\n", total, ambiguous,
                occluded);
    EXPECT_GT(ambiguous, 0);
    EXPECT_GT(occluded, total / 50);
    for (const Backend& backend : backends()) {
        const auto tracer = backend.make(scene);
        long occlusion_diff = 0, hit_diff = 0;
        std::vector<std::uint8_t> occ(kDirections);
        for (const Ray& r : rays) {
            tracer->occluded(r.origin, r.dirs.data(), kDirections, 0.0f, kInf, occ.data());
            for (int i = 0; i < kDirections; ++i) {
                const Hit& ref = r.ref[i];
                if ((occ[i] != 0) != ref.hit) ++occlusion_diff;
                const Hit got = tracer->intersect(r.origin, r.dirs[i], 0.0f, kInf);
                if (got.hit != ref.hit ||
                    (ref.hit && (got.triangle != ref.triangle ||
                                 std::fabs(got.t - ref.t) > 1e-5f * std::max(1.0f, ref.t))))
                    ++hit_diff;
            }
        }
        std::printf(
            "%s, box on plane: %ld occlusion and %ld closest-hit differences from brute "
            "force\n",
            backend.name, occlusion_diff, hit_diff);
        EXPECT_EQ(occlusion_diff, 0) << backend.name;
        EXPECT_EQ(hit_diff, 0) << backend.name;
    }
}

// An inner corner: floor (y = 0, x in [0, 2]) meeting a wall (x = 0, y in [0, 2]). Vertices on
// the crease line lie on both surfaces; a ray leaving into the room (away from the other surface)
// must not be stopped by it. Rays into the other surface are not asserted (t = 0 there).
TEST(Tracer, CreaseVerticesHaveNoSpuriousHits) {
    Mesh corner;
    corner.source = "test:corner";
    test::add_grid(corner, {0, 0, 1}, {2, 0, 0}, {0, 0, -2}, {0, 1, 0}, 10);  // floor
    test::add_grid(corner, {0, 0, -1}, {0, 2, 0}, {0, 0, 2}, {1, 0, 0}, 10);  // wall
    constexpr int kDirections = 2000;
    for (const Backend& backend : backends()) {
        const auto tracer = backend.make(corner);
        long rays = 0, occluded = 0;
        std::vector<std::uint8_t> occ(kDirections);
        for (std::size_t v = 0; v < corner.positions.size(); ++v) {
            const Vec3f p = corner.positions[v], n = corner.normals[v];
            const bool on_crease = p.x == 0.0f && p.y == 0.0f;
            if (!on_crease) continue;
            const Vec3f other = n.y == 1.0f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
            std::vector<Vec3f> dirs;
            for (const Vec3f& d : test::hemisphere_directions(n, 2 * kDirections, 77))
                if (dot(d, other) > 0.0f && static_cast<int>(dirs.size()) < kDirections)
                    dirs.push_back(d);
            const Vec3f origin = offset_ray_origin(p, n);
            tracer->occluded(origin, dirs.data(), static_cast<int>(dirs.size()), 0.0f, kInf,
                             occ.data());
            for (std::size_t i = 0; i < dirs.size(); ++i) {
                ++rays;
                occluded += occ[i];
                occluded += tracer->intersect(origin, dirs[i], 0.0f, kInf).hit ? 1 : 0;
            }
        }
        std::printf("%s, crease vertices: %ld rays leaving into the room, %ld stopped\n",
                    backend.name, rays, occluded);
        EXPECT_GT(rays, 20000);
        EXPECT_EQ(occluded, 0) << backend.name;
    }
}

#if SHPRT_TEST_HAS_MXCSR
// Tracing sets FTZ/DAZ for itself and leaves the caller's floating-point mode as it was.
TEST(Tracer, RestoresCallerFloatMode) {
    const Mesh plane = test::make_plane(4, 1.0f, 0.0f);
    const unsigned before = _mm_getcsr();
    for (const Backend& backend : backends()) {
        const auto tracer = backend.make(plane);
        const Vec3f d{0, -1, 0};
        std::uint8_t occ = 0;
        tracer->occluded({0.5f, 1, 0.5f}, &d, 1, 0.0f, kInf, &occ);
        tracer->intersect({0.5f, 1, 0.5f}, d, 0.0f, kInf);
        EXPECT_EQ(occ, 1);
        EXPECT_EQ(_mm_getcsr(), before) << backend.name;
    }
}
#endif

// The barycentric point q = (1-u-v)·a + u·b + v·c lies on the ray (distance across the ray) at
// the parameter t (distance along it). Along the ray the error grows like 1/|cos| for grazing
// hits (t is the ill-conditioned quantity there), so its tolerance is wider; Embree computes with
// fast reciprocals and gets the wider tolerances. The soup spans [0, 1]³.
TEST(Tracer, IntersectBarycentricsReproduceHitPoint) {
    const Mesh soup = test::make_triangle_soup(5000, 0.1f, 8);
    for (const Backend& backend : backends()) {
        const bool embree = std::string(backend.name) == "embree";
        const float tol_across = embree ? 5e-5f : 5e-6f;
        const float tol_along = 5e-5f;
        const auto tracer = backend.make(soup);
        std::mt19937 rng(2);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        int hits = 0;
        double max_across = 0.0, max_along = 0.0, max_bary = 0.0;
        for (int i = 0; i < 20000; ++i) {
            const Vec3f o{u(rng), u(rng), u(rng)};
            // Not unit length. Two statements: the operands of `*` may be evaluated in either
            // order, and gcc and clang drew the two numbers in opposite orders (other rays).
            const float scale = 0.5f + u(rng);
            const Vec3f d = test::random_direction(rng) * scale;
            const Hit h = tracer->intersect(o, d, 0.0f, kInf);
            if (!h.hit) continue;
            ++hits;
            ASSERT_LT(h.triangle, soup.triangles.size());
            const auto& tri = soup.triangles[h.triangle];
            const Vec3d q = cast<double>(soup.positions[tri[0]]) * (1.0 - h.u - h.v) +
                            cast<double>(soup.positions[tri[1]]) * double(h.u) +
                            cast<double>(soup.positions[tri[2]]) * double(h.v);
            const Vec3d dd = cast<double>(d), rel = q - cast<double>(o);
            const Vec3d dn = normalize(dd);
            const double along = dot(rel, dn);
            const double across = length(rel - dn * along);
            const double along_err = std::fabs(along - double(h.t) * length(dd));
            max_across = std::max(max_across, across);
            max_along = std::max(max_along, along_err);
            max_bary = std::max({max_bary, double(-h.u), double(-h.v), double(h.u + h.v) - 1.0});
            EXPECT_LT(across, tol_across) << backend.name << " ray " << i;
            EXPECT_LT(along_err, tol_along) << backend.name << " ray " << i;
            EXPECT_GT(h.t, 0.0f);
            std::uint8_t occ = 0;
            tracer->occluded(o, &d, 1, 0.0f, kInf, &occ);
            EXPECT_EQ(occ, 1);
        }
        std::printf(
            "%s: %d hits; barycentric point off the ray by at most %.3g, off t·|d| along "
            "it by at most %.3g; barycentrics outside the triangle by at most %.3g\n",
            backend.name, hits, max_across, max_along, max_bary);
        EXPECT_LE(max_bary, 1e-5) << backend.name;
        EXPECT_GT(hits, 5000) << backend.name;
    }
}

TEST(Tracer, MissReportsNoTriangle) {
    const Mesh plane = test::make_plane(2, 1.0f, 0.0f);
    for (const Backend& backend : backends()) {
        const auto tracer = backend.make(plane);
        const Hit h = tracer->intersect({0.5f, 1.0f, 0.5f}, {0, 1, 0}, 0.0f, kInf);
        EXPECT_FALSE(h.hit);
        EXPECT_EQ(h.triangle, kNoTriangle);
        // tfar shorter than the distance to the plane.
        std::uint8_t occ = 1;
        const Vec3f down{0, -1, 0};
        tracer->occluded({0.5f, 1.0f, 0.5f}, &down, 1, 0.0f, 0.5f, &occ);
        EXPECT_EQ(occ, 0);
        tracer->occluded({0.5f, 1.0f, 0.5f}, &down, 1, 0.0f, 1.5f, &occ);
        EXPECT_EQ(occ, 1);
        tracer->occluded({0.5f, 1.0f, 0.5f}, &down, 0, 0.0f, 1.5f, nullptr);  // count 0: no-op
        EXPECT_STREQ(tracer->name(), backend.name);
    }
}

TEST(Tracer, ReportsTheMemoryOfItsAccelerationStructure) {
    const Mesh soup = test::make_triangle_soup(20000, 0.05f, 7);
    const std::size_t T = soup.triangle_count(), V = soup.vertex_count();
    // Embree: its own copy of the vertex and index buffers at least (12 bytes each per vertex and
    // triangle, plus padding), and a BVH well under 1 KB per triangle.
    const auto embree = make_embree_tracer(soup);
    EXPECT_GE(embree->memory_bytes(), 12 * V + 12 * T);
    EXPECT_LT(embree->memory_bytes(), 1024 * T);
    // The flat BVH: its nodes (64 bytes per interior node, T − 1 for a binary tree over one
    // triangle per leaf at most) and its triangle arrays.
    const auto flat = make_flat_bvh_tracer(soup);
    EXPECT_GE(flat->memory_bytes(), 36 * T);
    EXPECT_LT(flat->memory_bytes(), 1024 * T);
    // A larger scene takes more.
    const auto small = make_embree_tracer(test::make_triangle_soup(2000, 0.05f, 7));
    EXPECT_LT(small->memory_bytes(), embree->memory_bytes());
}

TEST(Tracer, BadMeshesThrow) {
    Mesh empty;
    empty.source = "test:empty";
    Mesh no_triangles = test::make_plane(2, 1.0f, 0.0f);
    no_triangles.triangles.clear();
    Mesh nan = test::make_plane(2, 1.0f, 0.0f);
    nan.positions[3].y = std::numeric_limits<float>::quiet_NaN();
    Mesh inf = test::make_plane(2, 1.0f, 0.0f);
    inf.positions[0].x = kInf;
    Mesh bad_index = test::make_plane(2, 1.0f, 0.0f);
    bad_index.triangles[1][2] = static_cast<std::uint32_t>(bad_index.positions.size());
    Mesh degenerate = test::make_plane(2, 1.0f, 0.0f);
    for (auto& t : degenerate.triangles) t = {0, 1, 2};  // collinear row
    Mesh repeated = test::make_plane(2, 1.0f, 0.0f);
    for (auto& t : repeated.triangles) t = {4, 4, 5};
    const std::vector<std::pair<const char*, const Mesh*>> bad = {
        {"empty", &empty},      {"no triangles", &no_triangles}, {"NaN", &nan},
        {"Inf", &inf},          {"index", &bad_index},           {"degenerate", &degenerate},
        {"repeated", &repeated}};
    for (const Backend& backend : backends())
        for (const auto& [what, mesh] : bad) {
            try {
                backend.make(*mesh);
                ADD_FAILURE() << backend.name << " accepted a bad mesh: " << what;
            } catch (const Error& e) {
                EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << what;
                const std::string message = e.what();
                if (!mesh->source.empty()) {
                    EXPECT_NE(message.find(mesh->source), std::string::npos) << message;
                }
            }
        }
}

// An error Embree reports through its callback comes back as shprt::Error at the next check,
// with Embree's message, and is cleared.
TEST(Tracer, EmbreeErrorsBecomeShprtErrors) {
    trace_detail::EmbreeDevice device;
    RTCScene scene = rtcNewScene(device.get());
    ASSERT_NE(scene, nullptr);
    EXPECT_NO_THROW(device.check("creating a scene"));
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_REFIT);  // not valid for a scene
    try {
        device.check("setting the build quality");
        ADD_FAILURE() << "no error reported";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("setting the build quality: Embree error"), std::string::npos)
            << message;
        EXPECT_NE(message.find("build quality"), std::string::npos) << message;
    }
    EXPECT_NO_THROW(device.check("after"));
    rtcReleaseScene(scene);
}

// Many threads on one tracer give exactly the serial answers.
TEST(Tracer, ParallelCallsMatchSerial) {
    const Mesh scene = test::make_box_on_plane();
    constexpr int kDirections = 256;
    const auto dirs = test::hemisphere_directions({0, 1, 0}, kDirections, 5);
    const std::size_t vertices = scene.positions.size();
    for (const Backend& backend : backends()) {
        const auto tracer = backend.make(scene);
        auto run = [&](std::size_t v, std::uint8_t* occ, Hit* hit) {
            const Vec3f origin = offset_ray_origin(scene.positions[v], scene.normals[v]);
            tracer->occluded(origin, dirs.data(), kDirections, 0.0f, kInf, occ);
            *hit = tracer->intersect(origin, dirs[v % kDirections], 0.0f, kInf);
        };
        std::vector<std::uint8_t> serial(vertices * kDirections), parallel(serial.size());
        std::vector<Hit> serial_hits(vertices), parallel_hits(vertices);
        for (std::size_t v = 0; v < vertices; ++v)
            run(v, &serial[v * kDirections], &serial_hits[v]);
        parallel_each(0, vertices, [&](std::size_t v) {
            run(v, &parallel[v * kDirections], &parallel_hits[v]);
        });
        long occluded = 0;
        for (std::uint8_t o : serial) occluded += o;
        EXPECT_GT(occluded, 0);
        EXPECT_EQ(serial, parallel) << backend.name;
        for (std::size_t v = 0; v < vertices; ++v) {
            EXPECT_EQ(serial_hits[v].hit, parallel_hits[v].hit);
            EXPECT_EQ(serial_hits[v].triangle, parallel_hits[v].triangle);
            EXPECT_EQ(serial_hits[v].t, parallel_hits[v].t);
        }
    }
}

}  // namespace
}  // namespace shprt
