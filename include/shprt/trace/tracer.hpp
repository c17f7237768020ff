// The tracing interface the bake uses: visibility for batches of rays that share an origin, and
// closest hit with triangle id and barycentrics. Two CPU implementations:
//  * make_embree_tracer — Intel Embree 3 (the production CPU path);
//  * make_flat_bvh_tracer — our flat BVH (flat_bvh.hpp) traversed on the CPU: the same SHPRT_HD
//    code the CUDA kernels run, so it is the reference that ties the GPU to Embree.
//
// Self-intersection. Rays start on the surface they leave, so a naive origin re-hits its own
// triangle (or a neighbour) at t ≈ 0 because of rounding. The convention, for every tracer and
// every caller: pass origin = offset_ray_origin(position, normal) (ray.hpp; Wächter & Binder
// 2019) and tnear = 0, with `normal` the unit normal on the side the rays leave into. The offset
// scales with the float magnitude of the position, so it holds at any scene scale without an
// epsilon to tune. Guarantee (tested for both tracers, every vertex of tessellated planes, axis
// aligned and tilted, thousands of upper-hemisphere directions down to grazing angles): a flat
// plane under an open sky is unoccluded at every vertex, with no exception.
//
// Creases. A vertex that lies on another surface as well (a floor vertex at the foot of a wall, a
// hard-edged box's corner vertex in the planes of its neighbouring faces, a box standing on a
// floor) starts its rays exactly on that other surface: their hit with it is at t = 0, outside
// the interval. Rays leaving away from that surface are therefore never stopped by it (tested),
// and rays into it pass it — into the solid behind a closed surface, which stops them, or behind
// a one-sided one. The plane-distance t of intersect_triangle makes that t exactly 0 for
// axis-aligned surfaces, so both tracers agree on these rays; for tilted ones it is rounding.
//
// Intervals: a ray hits when tnear < t < tfar. (Embree's own test is closed at both ends; the two
// can differ only for a hit exactly at an endpoint.) Directions need not be unit length; t is in
// units of |dir|. Directions must be non-zero and finite.
//
// Blocker cones. A bake's rays leave one origin in a coherent order (neighbours in the stream are
// neighbours on the sphere), and most of its blocked rays are stopped by the same large triangle
// as their neighbours — the room's walls, floor and slabs, merged (coplanar_merge.hpp). So the
// Embree tracer, for a call of at least 32 rays with tnear = 0 and tfar = ∞, traces every 16th
// ray first, recording the triangle that stopped it (a context filter); where neighbouring
// samples were stopped by the same triangle often enough (1 pair in 8) to pay for the tests, each
// ray between two samples is tested against the cones of their blockers (ray.hpp,
// triangle_cone: three dot products; sixteen rays at a time with AVX-512, src/trace/
// blocker_cones.hpp), and only the rays in neither cone go to Embree. A ray in a
// blocker's cone hits that triangle at t > 0, so it is occluded: the answers are the tracer's,
// except for rays that graze an edge, where Embree's own test and the watertight one disagree
// too (on Assimp's IFC house, 1 ray in 5.8 M differs from Embree, and there the watertight flat
// BVH answers as the cones: test_blocker_cones). Each call decides from its own rays, so the
// answers never depend on threads or on other calls. On the merged room the rays are 1.75×
// faster; where blockers are small (a curved model) or few (an open sky) the cones are not tested
// and the samples' separate stream costs 1–4 % (bench_blocker_cones; bench/RESULTS.md, "Blocker
// cones and projection by sums" and "AVX-512 cones, the rotation in lanes, a cheaper set-up").
//
// Embree threading. Debian's Embree uses TBB as its tasking system, and its device option
// "threads=N" installs a process-wide tbb::global_control(max_allowed_parallelism, N): it would
// throttle (or oversubscribe) the caller's own TBB loops. Tracing itself (rtcOccluded1M,
// rtcIntersect1) uses no Embree threads at all; only scene builds do. So the device is created
// with no thread count ("threads" left at its default, affinity off, no pre-started threads):
// builds run as TBB tasks in the caller's pool, and tracing runs exactly on the caller's threads.
// Each tracing call sets FTZ/DAZ on the calling thread (and restores the caller's MXCSR after),
// as Embree requires for full speed.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/trace/ray.hpp"

#include <cstdint>
#include <memory>

namespace shprt {

class Tracer {
public:
    virtual ~Tracer() = default;

    // occluded[i] = 1 if the ray origin + t·dirs[i], tnear < t < tfar, hits any triangle, else 0,
    // for i in [0, count). Rays that share an origin (one vertex's directions) go in one call.
    // Thread-safe: called concurrently from many threads on one Tracer.
    virtual void occluded(Vec3f origin, const Vec3f* dirs, int count, float tnear, float tfar,
                          std::uint8_t* occluded) const = 0;

    // The closest hit of origin + t·dir with tnear < t < tfar (see Hit in ray.hpp: mesh triangle
    // index and barycentrics in the mesh's vertex order). Thread-safe.
    virtual Hit intersect(Vec3f origin, Vec3f dir, float tnear, float tfar) const = 0;

    // hits[i] = intersect(origin, dirs[i], tnear, tfar) for i in [0, count): the closest hits of
    // rays that share an origin (one vertex's directions), for interreflected transfer. Embree
    // casts them as one stream (rtcIntersect1M); the default loops over intersect(). Thread-safe.
    virtual void closest_hits(Vec3f origin, const Vec3f* dirs, int count, float tnear, float tfar,
                              Hit* hits) const {
        for (int i = 0; i < count; ++i) hits[i] = intersect(origin, dirs[i], tnear, tfar);
    }

    // "embree" or "flat-bvh".
    virtual const char* name() const = 0;

    // Host memory of the acceleration structure, bytes: the peak its library allocated while
    // building and holding it (Embree: what the device's memory monitor reported, geometry
    // buffers and build scratch included; the flat BVH: its arrays). For BakeStats'
    // peak_bytes_host.
    virtual std::size_t memory_bytes() const = 0;
};

struct EmbreeTracerOptions {
    // Scene build quality: true = RTC_BUILD_QUALITY_HIGH, false = MEDIUM. Measured on the 20k-
    // triangle room: in a random ray order the same tracing rate (within 1 %), in the bake's
    // coherent order 1-3 % faster; HIGH builds 3-7× slower (12 against 3.5 ms). So MEDIUM is the
    // default, and a bake asks for HIGH when it casts enough rays to pay for it
    // (for_rays); see bench/RESULTS.md ("Tracing", "Coherent ray order"). It applies to the
    // mesh's own triangles: merged ones (below) always build MEDIUM, measured faster on them.
    bool high_quality = false;
    // HIGH where `rays` ≥ kHighQualityRaysPerTriangle × `triangles`: the build's extra cost (about
    // 0.45 µs a triangle) against 2 % of the rays' (about 0.47 ns a ray), both measured on the
    // room.
    static constexpr double kHighQualityRaysPerTriangle = 1000.0;
    // Merged triangles where `rays` ≥ kMergeRaysPerTriangle × `triangles`: the merge's cost (0.3
    // to 0.9 µs a triangle on one thread, whether or not anything merges) against what it saves
    // on the room (7.5 ns of wall time a ray on two threads), both measured with
    // bench_coplanar_merge; with more threads a ray saves less wall time, hence the margin.
    static constexpr double kMergeRaysPerTriangle = 200.0;
    static EmbreeTracerOptions for_rays(double rays, std::size_t triangles) {
        EmbreeTracerOptions o;
        o.high_quality = rays >= kHighQualityRaysPerTriangle * double(triangles);
        o.merge_coplanar = rays >= kMergeRaysPerTriangle * double(triangles);
        // Cones pay on large blockers, which a tessellated mesh has only once merged
        // (bench_blocker_cones: 1.75x on the merged room, 0.97-0.99x on its own triangles).
        o.blocker_cones = o.merge_coplanar;
        return o;
    }
    // Visibility (occluded) traces merge_coplanar's triangles (coplanar_merge.hpp): the same
    // points, with coplanar neighbours merged; 1.7x the rays per second on the room, the same
    // rows to the bit (bench/RESULTS.md, "Tracing merged coplanar triangles"). false: the mesh's
    // own.
    bool merge_coplanar = true;
    // Blocker cones for calls of occluded() with tnear = 0 and tfar = ∞ (see "Blocker cones"
    // above): every 16th ray is traced first, and the rays between are tested against the cones
    // of the triangles that blocked their two neighbours before any is traced. false: every ray
    // goes to Embree.
    bool blocker_cones = true;
    // Build the mesh's own triangles for intersect and closest_hits. A tracer for visibility only
    // (a direct bake) sets false and saves that build; intersect then throws.
    bool closest_hits = true;
};

// Builds an Embree scene over mesh.triangles (copied; the mesh may be freed afterwards), and one
// over their coplanar merge for visibility (see EmbreeTracerOptions).
// Throws shprt::Error(invalid_argument) naming mesh.source for a mesh with no triangles, an
// index out of range, a non-finite position, or only zero-area triangles; Embree's own errors
// come back as shprt::Error with Embree's message.
std::unique_ptr<Tracer> make_embree_tracer(const Mesh& mesh, const EmbreeTracerOptions& options);
std::unique_ptr<Tracer> make_embree_tracer(const Mesh& mesh);

// Builds the flat BVH (build_flat_bvh, default options) and traverses it on the CPU with
// bvh_occluded / bvh_intersect. Same errors as build_flat_bvh.
std::unique_ptr<Tracer> make_flat_bvh_tracer(const Mesh& mesh);

}  // namespace shprt
