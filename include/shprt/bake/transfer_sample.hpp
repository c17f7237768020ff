// One entry of the bake's transfer matrix, W[v][s] = V(p, w_s)·max(0, n·w_s)·weight_s, as SHPRT_HD
// code: the body of the GPU bake's kernel (src/bake/cuda/transfer_kernels.cu), and what the CPU
// tests run on the host to check that kernel's math without a GPU. Header-only; no std::vector,
// exceptions or virtual calls.
//
// It reproduces the CPU bake (bake_cpu.cpp) operation for operation: the cosine is
// ((n.x·w.x + n.y·w.y) + n.z·w.z) in float with no fused multiply-add, the product with the weight
// is one float multiply, and a ray is cast only when that product is non-zero, from
// offset_ray_origin(p, n) with tnear = 0 and tfar = ∞. So where the flat BVH and Embree agree on
// visibility, the GPU's W equals the CPU's W bit for bit. (Device code is compiled with
// --fmad=false, see cmake/Cuda.cmake, and uses the round-to-nearest intrinsics here as well.)
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/sh/local_frame.hpp"
#include "shprt/trace/flat_bvh.hpp"
#include "shprt/trace/ray.hpp"

#include <cstdint>

namespace shprt {

// max(0, n·w) as the CPU bake computes it: no FMA contraction, left-to-right sum.
SHPRT_HD_INLINE float transfer_cosine(Vec3f n, Vec3f w) {
#if defined(__CUDA_ARCH__)
    return __fadd_rn(__fadd_rn(__fmul_rn(n.x, w.x), __fmul_rn(n.y, w.y)), __fmul_rn(n.z, w.z));
#else
    const float xy = n.x * w.x + n.y * w.y;
    return xy + n.z * w.z;
#endif
}

// max(0, n·w)·weight: the unoccluded value of a sample, as the CPU bake's weight_row computes it.
SHPRT_HD_INLINE float transfer_unoccluded(Vec3f n, Vec3f w, float weight) {
    const float cosine = transfer_cosine(n, w);
#if defined(__CUDA_ARCH__)
    return cosine > 0.0f ? __fmul_rn(cosine, weight) : 0.0f;
#else
    return cosine > 0.0f ? cosine * weight : 0.0f;
#endif
}

// The unoccluded value of a glossy (matrix) sample: `weight` above the horizon (n·w > 0, the same
// test as transfer_unoccluded), else 0 — the hemisphere without the cosine, as the CPU bake's
// weight_row with `hemisphere`.
SHPRT_HD_INLINE float transfer_hemisphere(Vec3f n, Vec3f w, float weight) {
    return transfer_cosine(n, w) > 0.0f ? weight : 0.0f;
}

// W = V·max(0, n·w)·weight for the vertex at `p` with unit normal `n` and the unit direction `w`
// of integration weight `weight`. V (visibility: 1 when the ray from offset_ray_origin(p, n) along
// w hits nothing in (0, ∞) of `bvh`) is evaluated only when `shadowed` and the unoccluded value is
// non-zero; `ray_cast` tells whether a ray was traced (the bake's ray count). Below the horizon
// (n·w ≤ 0) the result is 0 and no ray is cast. `bvh` may be empty when !shadowed. With
// `hemisphere` (glossy transfer matrices) the cosine is left out: W = V·weight above the horizon.
SHPRT_HD_INLINE float transfer_sample(const FlatBvhView& bvh, Vec3f p, Vec3f n, Vec3f w,
                                      float weight, bool shadowed, bool& ray_cast,
                                      bool hemisphere = false) {
    const float unoccluded =
        hemisphere ? transfer_hemisphere(n, w, weight) : transfer_unoccluded(n, w, weight);
    ray_cast = false;
    if (!shadowed || unoccluded == 0.0f) return unoccluded;
    ray_cast = true;
    constexpr float kInf = __builtin_huge_valf();
    return bvh_occluded(bvh, offset_ray_origin(p, n), w, 0.0f, kInf) ? 0.0f : unoccluded;
}

// A sample of a local set (DirectionFrame::local, docs/sampling.md): `l` lies in the receiver's
// tangent frame, whose axes are local_axes(n), and the ray goes along to_world(axes, l) from
// offset_ray_origin(p, n), as the CPU bake's trace_row casts it. The set's density already holds
// the cosine (or the hemisphere, for glossy matrices), so the unoccluded value is the weight and
// every sample is above the horizon: with `shadowed` a ray is always cast. The GPU kernel computes
// `axes` per sample from the normal; the host emulation per receiver (the same bits).
SHPRT_HD_INLINE float local_transfer_sample(const FlatBvhView& bvh, Vec3f p, Vec3f n,
                                            const LocalAxes& axes, Vec3f l, float weight,
                                            bool shadowed, bool& ray_cast) {
    ray_cast = shadowed;
    if (!shadowed) return weight;
    constexpr float kInf = __builtin_huge_valf();
    return bvh_occluded(bvh, offset_ray_origin(p, n), to_world(axes, l), 0.0f, kInf) ? 0.0f
                                                                                     : weight;
}

// What interreflected transfer keeps of a sample's ray: the closest hit's triangle (kNoTriangle
// when no ray was cast or it escaped) and barycentrics (u, v) (ray.hpp's Hit, without t).
struct SampleHit {
    std::uint32_t triangle;
    float u, v;
};

// The interreflected bake's sample (docs/interreflection.md): the same W as transfer_sample with
// `shadowed` (a ray that hits anything is occluded), from the closest hit, which it also returns.
// The same ray (origin, direction, interval) as transfer_sample.
SHPRT_HD_INLINE float closest_hit_sample(const FlatBvhView& bvh, Vec3f p, Vec3f n, Vec3f w,
                                         float weight, bool& ray_cast, SampleHit& hit) {
    const float unoccluded = transfer_unoccluded(n, w, weight);
    ray_cast = false;
    hit = SampleHit{kNoTriangle, 0.0f, 0.0f};
    if (unoccluded == 0.0f) return unoccluded;
    ray_cast = true;
    constexpr float kInf = __builtin_huge_valf();
    const Hit h = bvh_intersect(bvh, offset_ray_origin(p, n), w, 0.0f, kInf);
    if (!h.hit) return unoccluded;
    hit = SampleHit{h.triangle, h.u, h.v};
    return 0.0f;
}

}  // namespace shprt
