// The Embree 3 tracer (I. Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray
// Tracing", SIGGRAPH 2014). Visibility goes through the ray-stream API (rtcOccluded1M, one call
// per batch of rays sharing an origin, incoherent flag): about twice the single-ray rate on the
// room on this machine, and it traces merge_coplanar's triangles (coplanar_merge.hpp), which
// cover the same points with fewer triangles; most blocked rays of a bundle are answered from the
// cones of the triangles that stopped their neighbours (tracer.hpp, "Blocker cones"). Closest
// hits use the mesh's own triangles (rtcIntersect1, rtcIntersect1M), whose indices and
// barycentrics the caller interpolates with.
#include "shprt/core/error.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/tracer.hpp"
#include "trace/blocker_cones.hpp"
#include "trace/embree_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace shprt {

namespace {

using trace_detail::EmbreeDevice;
using trace_detail::FtzDazScope;

// Rays per rtcOccluded1M call: large enough for Embree to sort a stream into packets, small
// enough to live on the stack (48 bytes each).
constexpr int kStreamChunk = 256;

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Blocker cones (tracer.hpp, blocker_cones.hpp): every kConeStride-th ray of a call is traced
// first, for calls of at least kConeMinRays rays.
using trace_detail::kConeStride;
constexpr int kConeMinRays = 2 * kConeStride;
// The cones are built and tested where at least one pair of neighbouring samples in
// kConeMinSpanShare was stopped by the same triangle (bench_blocker_cones: a cone test costs
// about a twentieth of an Embree ray here).
constexpr int kConeMinSpanShare = 8;

// An intersect context that carries where the filter records blockers: the context Embree passes
// to the filter is this struct's first member.
struct BlockerContext {
    RTCIntersectContext context;
    std::uint32_t* blockers = nullptr;  // per ray id of the stream call
};

// The context filter of a stream call that records blockers: Embree calls it for a hit it is
// about to accept (an occlusion ray ends at the first), and accepting it is left as is.
void record_blocker(const RTCFilterFunctionNArguments* args) {
    const auto* context = reinterpret_cast<const BlockerContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        context->blockers[RTCRayN_id(args->ray, args->N, i)] =
            RTCHitN_primID(args->hit, args->N, i);
    }
}

// One thread's buffers for occluded_by_cones.
struct ConeScratch {
    std::vector<std::uint32_t> index;    // rays to trace
    std::vector<std::uint32_t> blocker;  // per traced sample: its blocker, or kNoTriangle
    std::vector<TriangleCone> cone;      // per traced sample: its blocker's cone
};

// One ray of a stream call: from `origin` along `dir` over [tnear, tfar], the i-th of its chunk.
void set_ray(RTCRay& r, Vec3f origin, Vec3f dir, float tnear, float tfar, int i) {
    r.org_x = origin.x;
    r.org_y = origin.y;
    r.org_z = origin.z;
    r.tnear = tnear;
    r.dir_x = dir.x;
    r.dir_y = dir.y;
    r.dir_z = dir.z;
    r.time = 0.0f;
    r.tfar = tfar;
    r.mask = 0xFFFFFFFFu;
    r.id = static_cast<unsigned>(i);
    r.flags = 0;
}

struct GeometryRelease {
    void operator()(RTCGeometry g) const { rtcReleaseGeometry(g); }
};
struct SceneRelease {
    void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using GeometryPtr = std::unique_ptr<RTCGeometryTy, GeometryRelease>;
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneRelease>;

class EmbreeTracer final : public Tracer {
public:
    EmbreeTracer(const Mesh& mesh, const EmbreeTracerOptions& options) {
        trace_detail::validate_mesh(mesh);
        m_cones = options.blocker_cones;
        const RTCBuildQuality quality =
            options.high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
        if (options.closest_hits || !options.merge_coplanar) {
            m_scene =
                build(mesh.positions, mesh.triangles, quality, !options.merge_coplanar && m_cones);
            if (!options.merge_coplanar && m_cones) keep_blockers(mesh.positions, mesh.triangles);
        }
        if (options.merge_coplanar) {
            // MEDIUM whatever the options say: on the merged room HIGH's spatial splits of the
            // large triangles trace 13 % slower (bench_coplanar_merge), and build slower too.
            const MergedTriangles merged = merge_coplanar(mesh);
            m_occlusion_scene =
                build(merged.positions, merged.triangles, RTC_BUILD_QUALITY_MEDIUM, m_cones);
            if (m_cones) keep_blockers(merged.positions, merged.triangles);
        }
    }

    void occluded(Vec3f origin, const Vec3f* dirs, int count, float tnear, float tfar,
                  std::uint8_t* occluded) const override {
        FtzDazScope ftz;
        if (m_cones && count >= kConeMinRays && tnear == 0.0f && tfar == kInfinity)
            occluded_by_cones(origin, dirs, count, occluded);
        else
            stream_occluded(origin, dirs, nullptr, count, tnear, tfar, occluded, nullptr);
    }

    std::size_t memory_bytes() const override {
        return m_device.bytes_peak() + m_blocker_vertices.size() * sizeof(Vec3f);
    }

    void closest_hits(Vec3f origin, const Vec3f* dirs, int count, float tnear, float tfar,
                      Hit* hits) const override {
        FtzDazScope ftz;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        RTCRayHit rays[kStreamChunk];
        for (int base = 0; base < count; base += kStreamChunk) {
            const int n = std::min(kStreamChunk, count - base);
            for (int i = 0; i < n; ++i) {
                RTCRayHit& rh = rays[i];
                set_ray(rh.ray, origin, dirs[base + i], tnear, tfar, i);
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect1M(hit_scene(), &context, rays, static_cast<unsigned>(n),
                           sizeof(RTCRayHit));
            for (int i = 0; i < n; ++i) {
                const RTCRayHit& rh = rays[i];
                hits[base + i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID
                                     ? Hit{false, kNoTriangle, tfar, 0, 0}
                                     : Hit{true, rh.hit.primID, rh.ray.tfar, rh.hit.u, rh.hit.v};
            }
        }
    }

    Hit intersect(Vec3f origin, Vec3f dir, float tnear, float tfar) const override {
        FtzDazScope ftz;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh;
        set_ray(rh.ray, origin, dir, tnear, tfar, 0);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(hit_scene(), &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return Hit{false, kNoTriangle, tfar, 0, 0};
        // Embree's barycentrics use the same convention: p = (1-u-v)·v0 + u·v1 + v·v2.
        return Hit{true, rh.hit.primID, rh.ray.tfar, rh.hit.u, rh.hit.v};
    }

    const char* name() const override { return "embree"; }

private:
    // An Embree scene of one triangle geometry, copied into Embree-owned buffers (padded as its
    // SIMD loads need), so the caller's arrays can go away.
    // `visibility`: the scene occluded() traces, whose context filter records blockers.
    ScenePtr build(const std::vector<Vec3f>& positions,
                   const std::vector<std::array<std::uint32_t, 3>>& triangles,
                   RTCBuildQuality quality, bool visibility) {
        const RTCDevice device = m_device.get();
        const GeometryPtr geometry(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
        m_device.check("creating the Embree triangle geometry");
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    3 * sizeof(float), positions.size()));
        auto* indices = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(std::uint32_t), triangles.size()));
        m_device.check("allocating Embree geometry buffers");
        SHPRT_CHECK(vertices && indices, out_of_memory,
                    "allocating Embree geometry buffers failed");
        for (std::size_t i = 0; i < positions.size(); ++i) {
            vertices[3 * i + 0] = positions[i].x;
            vertices[3 * i + 1] = positions[i].y;
            vertices[3 * i + 2] = positions[i].z;
        }
        for (std::size_t t = 0; t < triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) indices[3 * t + k] = triangles[t][k];
        rtcSetGeometryBuildQuality(geometry.get(), quality);
        {
            const tsan::ForkJoinScope build(m_device.monitor());
            rtcCommitGeometry(geometry.get());
        }
        ScenePtr scene(rtcNewScene(device));
        m_device.check("creating the Embree scene");
        SHPRT_CHECK(scene != nullptr, out_of_memory, "creating the Embree scene failed");
        rtcSetSceneBuildQuality(scene.get(), quality);
        if (visibility) rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
        rtcAttachGeometryByID(scene.get(), geometry.get(), 0);
        m_device.check("attaching the mesh to the Embree scene");
        {
            FtzDazScope ftz;
            const tsan::ForkJoinScope build(m_device.monitor());
            rtcCommitScene(scene.get());
        }
        m_device.check("building the Embree scene");
        return scene;
    }

    // Rays index[0..n) of dirs (all of dirs[0..n) without an index) as streams of kStreamChunk:
    // occluded[index[i]] gets the answer. With `blockers`, the triangle that stopped each occluded
    // ray goes to blockers[i] (the context's filter records it; the others keep what they had).
    void stream_occluded(Vec3f origin, const Vec3f* dirs, const std::uint32_t* index, int n,
                         float tnear, float tfar, std::uint8_t* occluded,
                         std::uint32_t* blockers) const {
        BlockerContext context;
        rtcInitIntersectContext(&context.context);
        context.context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        if (blockers != nullptr) context.context.filter = record_blocker;
        RTCRay rays[kStreamChunk];
        for (int base = 0; base < n; base += kStreamChunk) {
            const int m = std::min(kStreamChunk, n - base);
            context.blockers = blockers ? blockers + base : nullptr;
            for (int i = 0; i < m; ++i) {
                const std::uint32_t r = index ? index[base + i] : std::uint32_t(base + i);
                set_ray(rays[i], origin, dirs[r], tnear, tfar, i);
            }
            rtcOccluded1M(occlusion_scene(), &context.context, rays, static_cast<unsigned>(m),
                          sizeof(RTCRay));
            // Embree marks an occluded ray by setting tfar to -inf.
            for (int i = 0; i < m; ++i) {
                const std::uint32_t r = index ? index[base + i] : std::uint32_t(base + i);
                occluded[r] = rays[i].tfar < 0.0f ? 1 : 0;
            }
        }
    }

    // Blocker cones (tracer.hpp): every kConeStride-th ray is traced, recording its blocker; the
    // rays between two traced ones are tested against the cones of those two rays' blockers
    // (ray.hpp, triangle_cone), and only those in neither cone are traced.
    void occluded_by_cones(Vec3f origin, const Vec3f* dirs, int count,
                           std::uint8_t* occluded) const {
        thread_local ConeScratch sc;
        const int samples = (count + kConeStride - 1) / kConeStride;
        sc.index.resize(std::size_t(count));
        sc.blocker.assign(std::size_t(samples), kNoTriangle);
        sc.cone.resize(std::size_t(samples));
        for (int j = 0; j < samples; ++j) sc.index[std::size_t(j)] = std::uint32_t(j * kConeStride);
        stream_occluded(origin, dirs, sc.index.data(), samples, 0.0f, kInfinity, occluded,
                        sc.blocker.data());
        // Whether cones will catch enough rays to pay for testing them: neighbouring samples
        // stopped by the same triangle (the rays between them mostly lie in its cone, which is
        // convex). Few on small triangles (a curved model's) or under an open sky, most where
        // large surfaces block; decided from this call's rays alone, so the answers never depend
        // on what another call saw.
        int spans = 0;
        for (std::size_t j = 0; j + 1 < std::size_t(samples); ++j)
            spans += sc.blocker[j] != kNoTriangle && sc.blocker[j] == sc.blocker[j + 1] ? 1 : 0;
        const bool test = spans * kConeMinSpanShare >= samples - 1;
        for (std::size_t j = 0; test && j < std::size_t(samples); ++j) {
            const std::uint32_t t = sc.blocker[j];
            if (j > 0 && t == sc.blocker[j - 1]) {
                sc.cone[j] = sc.cone[j - 1];
            } else if (t == kNoTriangle) {
                sc.cone[j] = triangle_cone(origin, origin, origin, origin);  // empty
            } else {
                const Vec3f* v = m_blocker_vertices.data() + 3 * std::size_t(t);
                sc.cone[j] = triangle_cone(origin, v[0], v[1], v[2]);
            }
        }
        int pending = 0;
        if (test) {
            // A ray inside either cone is occluded; the others are listed to trace, in order.
            pending = trace_detail::test_cones(sc.cone.data(), samples, dirs, count, occluded,
                                               sc.index.data());
        } else {
            for (int i = 0; i < count; ++i)
                if (i % kConeStride != 0) sc.index[std::size_t(pending++)] = std::uint32_t(i);
        }
        stream_occluded(origin, dirs, sc.index.data(), pending, 0.0f, kInfinity, occluded, nullptr);
    }

    void keep_blockers(const std::vector<Vec3f>& positions,
                       const std::vector<std::array<std::uint32_t, 3>>& triangles) {
        m_blocker_vertices.resize(3 * triangles.size());
        for (std::size_t t = 0; t < triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) m_blocker_vertices[3 * t + k] = positions[triangles[t][k]];
    }

    RTCScene occlusion_scene() const {
        return m_occlusion_scene ? m_occlusion_scene.get() : m_scene.get();
    }
    RTCScene hit_scene() const {
        SHPRT_CHECK(m_scene != nullptr, invalid_argument,
                    "this Embree tracer was built for visibility only "
                    "(EmbreeTracerOptions::closest_hits = false)");
        return m_scene.get();
    }

    EmbreeDevice m_device;  // declared first: released last
    ScenePtr m_scene;       // the mesh's own triangles: closest hits (and visibility, unmerged)
    ScenePtr m_occlusion_scene;  // merge_coplanar's triangles: visibility
    // The corners of the triangles visibility traces, three per triangle: the blocker cones'.
    std::vector<Vec3f> m_blocker_vertices;
    bool m_cones = false;
};

}  // namespace

std::unique_ptr<Tracer> make_embree_tracer(const Mesh& mesh, const EmbreeTracerOptions& options) {
    return std::make_unique<EmbreeTracer>(mesh, options);
}

std::unique_ptr<Tracer> make_embree_tracer(const Mesh& mesh) {
    return make_embree_tracer(mesh, EmbreeTracerOptions{});
}

}  // namespace shprt
