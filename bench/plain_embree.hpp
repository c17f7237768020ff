// The plain Embree program of bench_bake: a bake's occlusion rays (per vertex, the shared
// directions above its horizon, from offset_ray_origin, one stream call per vertex) cast and
// nothing else, the limit the bake's tracing is measured against. The same rays cost Embree up
// to a third more in an incoherent order than in a coherent one (issue 39), so the limit is the
// fastest order: run() casts them in the set's order or in a given one (coherent_order, sorted
// along a space-filling curve), and bench_bake times both. Like the bake, it casts the rays of one
// of each set of twins (receivers with the same position and normal; bake/stages.hpp). A local
// set (DirectionSet::frame) is turned into each vertex's tangent frame first (sh/local_frame.hpp),
// as the bake turns it; every one of its directions is above the horizon and its weights hold the
// cosine. It traces the triangles the bake's tracer traces for visibility, merge_coplanar's.
// (bench_interreflect measured its closest hits against it too, until the interreflected
// bake's T_0 became the direct bake itself.)
#pragma once

#include "bake/stages.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/ray.hpp"
#include "trace/embree_common.hpp"

#include <embree3/rtcore.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace shprt::bench {

class PlainEmbree {
public:
    explicit PlainEmbree(const Mesh& mesh) {
        // The tracer's device configuration, triangles (its visibility traces merge_coplanar's:
        // the same points as the mesh's, fewer triangles) and their build quality (MEDIUM, which
        // traces them faster than HIGH), for a like-for-like BVH.
        const MergedTriangles merged = merge_coplanar(mesh);
        m_device = rtcNewDevice(trace_detail::embree_device_config());
        RTCGeometry g = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, merged.positions.size()));
        auto* i = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, merged.triangles.size()));
        std::memcpy(v, merged.positions.data(), merged.positions.size() * 12);
        std::memcpy(i, merged.triangles.data(), merged.triangles.size() * 12);
        rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_MEDIUM);
        rtcCommitGeometry(g);
        m_scene = rtcNewScene(m_device);
        rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_MEDIUM);
        rtcAttachGeometry(m_scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(m_scene);
    }
    ~PlainEmbree() {
        rtcReleaseScene(m_scene);
        rtcReleaseDevice(m_device);
    }
    PlainEmbree(const PlainEmbree&) = delete;
    PlainEmbree& operator=(const PlainEmbree&) = delete;

    // Casts every vertex's above-horizon rays, one stream call per vertex, in the bake's chunks
    // on `threads` threads. Two ways to pick the above-horizon rays: a branch per direction, or
    // branch-free (always write the ray, advance only when above); the benchmark times both and
    // takes the faster as the reference. `order` (S indices, or nullptr for the set's own order)
    // is the order the directions are cast in. `rays` gets the ray count and c0[v] the visible
    // Σ cos·weight·y_0 (the bake's c_0, for validation; summed in the cast order).
    template <bool kBranchFree>
    void run(const Mesh& mesh, const DirectionSet& set, std::size_t chunk, int threads,
             std::uint64_t& rays, std::vector<float>& c0,
             const std::uint32_t* order = nullptr) const {
        const std::size_t V = mesh.vertex_count(), S = set.size();
        const bool local = set.frame == DirectionFrame::local;
        c0.assign(V, 0.0f);
        // As the bake: a receiver casts its rays only if it is the first of its chunk's twins
        // and not a twin of another chunk's (bake/stages.hpp); every twin has its first's rays.
        const std::vector<std::uint8_t> traced =
            detail::traced_receivers(mesh.positions.data(), mesh.normals.data(), V, chunk, S);
        std::vector<std::uint32_t> first;
        detail::find_twins(mesh.positions.data(), mesh.normals.data(), V, first);
        struct Local {
            std::vector<RTCRay> rays;
            std::vector<float> cos_weight;
            std::uint64_t count = 0;
        };
        tbb::enumerable_thread_specific<Local> locals;
        const float y0 = 0.28209479177387814f;  // 1/√(4π)
        tbb::task_arena(threads).execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, (V + chunk - 1) / chunk, 1),
                [&](const tbb::blocked_range<std::size_t>& r) {
                    Local& l = locals.local();
                    if (l.cos_weight.empty()) {
                        l.rays.resize(S);
                        l.cos_weight.resize(S);
                    }
                    const unsigned saved = _mm_getcsr();
                    _mm_setcsr(saved | 0x8040u);  // FTZ | DAZ, as Embree wants
                    RTCIntersectContext context;
                    rtcInitIntersectContext(&context);
                    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
                    for (std::size_t c = r.begin(); c != r.end(); ++c) {
                        const std::size_t end = std::min(V, (c + 1) * chunk);
                        for (std::size_t v = c * chunk; v < end; ++v) {
                            if (!traced[v]) continue;  // the bake takes a twin's row: below
                            const Vec3f n = mesh.normals[v];
                            const Vec3f o = offset_ray_origin(mesh.positions[v], n);
                            const LocalAxes frame = local_axes(n);
                            unsigned m = 0;
                            for (std::size_t i = 0; i < S; ++i) {
                                const std::size_t s = order ? order[i] : i;
                                Vec3f d{set.dirs[3 * s], set.dirs[3 * s + 1], set.dirs[3 * s + 2]};
                                if (local) d = to_world(frame, d);
                                const float dx = d.x, dy = d.y, dz = d.z;
                                const float cosine = local ? 1.0f : n.x * dx + n.y * dy + n.z * dz;
                                if (!kBranchFree && !(cosine > 0.0f)) continue;
                                RTCRay& ray = l.rays[m];
                                ray.org_x = o.x;
                                ray.org_y = o.y;
                                ray.org_z = o.z;
                                ray.tnear = 0.0f;
                                ray.dir_x = dx;
                                ray.dir_y = dy;
                                ray.dir_z = dz;
                                ray.time = 0.0f;
                                ray.tfar = std::numeric_limits<float>::infinity();
                                ray.mask = 0xFFFFFFFFu;
                                ray.id = m;
                                ray.flags = 0;
                                l.cos_weight[m] = cosine * set.weights[s];
                                m += kBranchFree ? (cosine > 0.0f ? 1u : 0u) : 1u;
                            }
                            float sum = 0;
                            rtcOccluded1M(m_scene, &context, l.rays.data(), m, sizeof(RTCRay));
                            for (unsigned j = 0; j < m; ++j)
                                if (l.rays[j].tfar >= 0.0f) sum += l.cos_weight[j];
                            c0[v] = sum * y0;
                            l.count += m;
                        }
                    }
                    _mm_setcsr(saved);
                },
                tbb::simple_partitioner());
        });
        for (std::size_t v = 0; v < V; ++v) c0[v] = c0[first[v]];  // twins: their first's sum
        rays = 0;
        for (const Local& l : locals) rays += l.count;
    }

private:
    RTCDevice m_device;
    RTCScene m_scene;
};

}  // namespace shprt::bench
