// The Embree 3 tracer (I. Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray
// Tracing", SIGGRAPH 2014). Visibility goes through the ray-stream API (rtcOccluded1M, one call
// per batch of rays sharing an origin, incoherent flag): about twice the single-ray rate on the
// room on this machine, and it traces merge_coplanar's triangles (coplanar_merge.hpp), which
// cover the same points with fewer triangles. Closest hits use the mesh's own triangles
// (rtcIntersect1, rtcIntersect1M), whose indices and barycentrics the caller interpolates with.
#include "shprt/core/error.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/tracer.hpp"
#include "trace/embree_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

namespace shprt {

namespace {

using trace_detail::EmbreeDevice;
using trace_detail::FtzDazScope;

// Rays per rtcOccluded1M call: large enough for Embree to sort a stream into packets, small
// enough to live on the stack (48 bytes each).
constexpr int kStreamChunk = 256;

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
        const RTCBuildQuality quality =
            options.high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
        if (options.closest_hits || !options.merge_coplanar)
            m_scene = build(mesh.positions, mesh.triangles, quality);
        if (options.merge_coplanar) {
            // MEDIUM whatever the options say: on the merged room HIGH's spatial splits of the
            // large triangles trace 13 % slower (bench_coplanar_merge), and build slower too.
            const MergedTriangles merged = merge_coplanar(mesh);
            m_occlusion_scene = build(merged.positions, merged.triangles, RTC_BUILD_QUALITY_MEDIUM);
        }
    }

    void occluded(Vec3f origin, const Vec3f* dirs, int count, float tnear, float tfar,
                  std::uint8_t* occluded) const override {
        FtzDazScope ftz;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        RTCRay rays[kStreamChunk];
        for (int base = 0; base < count; base += kStreamChunk) {
            const int n = std::min(kStreamChunk, count - base);
            for (int i = 0; i < n; ++i) {
                set_ray(rays[i], origin, dirs[base + i], tnear, tfar, i);
            }
            rtcOccluded1M(occlusion_scene(), &context, rays, static_cast<unsigned>(n),
                          sizeof(RTCRay));
            // Embree marks an occluded ray by setting tfar to -inf.
            for (int i = 0; i < n; ++i) occluded[base + i] = rays[i].tfar < 0.0f ? 1 : 0;
        }
    }

    std::size_t memory_bytes() const override { return m_device.bytes_peak(); }

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
    ScenePtr build(const std::vector<Vec3f>& positions,
                   const std::vector<std::array<std::uint32_t, 3>>& triangles,
                   RTCBuildQuality quality) {
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
};

}  // namespace

std::unique_ptr<Tracer> make_embree_tracer(const Mesh& mesh, const EmbreeTracerOptions& options) {
    return std::make_unique<EmbreeTracer>(mesh, options);
}

std::unique_ptr<Tracer> make_embree_tracer(const Mesh& mesh) {
    return make_embree_tracer(mesh, EmbreeTracerOptions{});
}

}  // namespace shprt
