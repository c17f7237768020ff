// The flat BVH: a compact binary BVH layout that lives in one array (host or GPU memory), and its
// traversal, written once as SHPRT_HD code: the CUDA kernels call bvh_occluded / bvh_intersect,
// and the CPU runs the very same functions in tests against Embree. Header-only; no std::vector,
// exceptions or virtual calls. Building it is bvh_build.hpp's job (host only).
//
// Traversal: one ray at a time, a fixed stack of child references, the "while-while" loop of
// T. Aila, S. Laine, "Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009 (an inner
// loop descends interior nodes, nearer child first, until it reaches a leaf; the outer loop
// intersects the leaf and pops). Ray/box: Ize's conservative slab test; ray/triangle: the
// watertight test of Woop et al. (see ray.hpp).
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/trace/ray.hpp"

#include <cstdint>

namespace shprt {

// A child reference is one 32-bit word:
//  * bit 31 clear: an interior node, the value is its index in `nodes`;
//  * bit 31 set: a leaf; bits 0..26 hold the first primitive reference (an index into tri_verts /
//    tri_ids) and bits 27..30 hold count − 1: the leaf is primitive references
//    [first, first + count), 1 ≤ count ≤ kFlatBvhMaxLeafSize.
inline constexpr std::uint32_t kFlatBvhLeafBit = 0x80000000u;
inline constexpr std::uint32_t kFlatBvhFirstMask = (1u << 27) - 1u;
inline constexpr int kFlatBvhCountShift = 27;
inline constexpr int kFlatBvhMaxLeafSize = 16;
inline constexpr std::uint32_t kFlatBvhMaxPrimRefs = 1u << 27;  // 134 217 728
// Traversal stack entries: at most one per tree level, so trees are built no deeper than this.
inline constexpr int kFlatBvhStackSize = 64;
// Floats per primitive reference in tri_verts: a.xyz, n.x, b.xyz, n.y, c.xyz, n.z with
// n = triangle_normal(a, b, c) (ray.hpp) — three 16-byte aligned float4s, so a GPU fetches a
// triangle and its normal with three vector loads.
inline constexpr int kFlatBvhTriStride = 12;

// One interior node of a BVH2, 64 bytes, 16-byte aligned (four float4/uint4 loads on a GPU): the
// boxes of both children, so one fetch decides which children the ray enters and in which order
// (Aila & Laine's layout). The root is node 0 and is always interior (a one-leaf tree gets a root
// whose two children are that same leaf). Nodes are stored depth first: child[0] of node i, when
// interior, is node i + 1.
struct alignas(16) FlatBvhNode {
    Aabb box[2];                // bytes 0..47: child bounds (lo.xyz, hi.xyz) each
    std::uint32_t child[2];     // bytes 48..55: child references (see kFlatBvhLeafBit)
    std::uint32_t reserved[2];  // bytes 56..63: zero
};
static_assert(sizeof(FlatBvhNode) == 64, "FlatBvhNode is four 16-byte words");

// A non-owning view of a flat BVH in one address space (host or device):
//  nodes[node_count]                       interior nodes, root = nodes[0];
//  tri_verts[kFlatBvhTriStride · tri_count] triangle vertices per primitive reference, in leaf
//                                          order (a reference may repeat a triangle when the
//                                          builder split it spatially);
//  tri_ids[tri_count]                      the mesh triangle index of each reference.
// node_count == 0 means an empty BVH: nothing is ever hit. For a GPU, copy the three arrays of a
// FlatBvh (bvh_build.hpp) byte for byte to device memory (cudaMalloc: 256-byte aligned) and pass a
// view of the device pointers by value to the kernel; nodes and tri_verts must be 16-byte aligned.
// Traversal state per thread: the kFlatBvhStackSize-entry stack (256 bytes of local memory).
struct FlatBvhView {
    const FlatBvhNode* nodes;
    const float* tri_verts;
    const std::uint32_t* tri_ids;
    std::uint32_t node_count, tri_count;
};

SHPRT_HD_INLINE bool flat_bvh_is_leaf(std::uint32_t ref) { return (ref & kFlatBvhLeafBit) != 0; }
SHPRT_HD_INLINE std::uint32_t flat_bvh_leaf_first(std::uint32_t ref) {
    return ref & kFlatBvhFirstMask;
}
SHPRT_HD_INLINE std::uint32_t flat_bvh_leaf_count(std::uint32_t ref) {
    return ((ref >> kFlatBvhCountShift) & 15u) + 1u;
}
// Precondition: first < kFlatBvhMaxPrimRefs, 1 ≤ count ≤ kFlatBvhMaxLeafSize.
SHPRT_HD_INLINE std::uint32_t flat_bvh_make_leaf(std::uint32_t first, std::uint32_t count) {
    return kFlatBvhLeafBit | ((count - 1u) << kFlatBvhCountShift) | first;
}

// Reads primitive reference `ref`: vertices a, b, c (mesh order) and n = triangle_normal(a, b, c).
// In device code: three read-only 128-bit loads (tri_verts must be 16-byte aligned, as
// cudaMalloc'd memory is).
SHPRT_HD_INLINE void flat_bvh_load_triangle(const FlatBvhView& bvh, std::uint32_t ref, Vec3f& a,
                                            Vec3f& b, Vec3f& c, Vec3f& n) {
#if defined(__CUDA_ARCH__)
    const float4* p = reinterpret_cast<const float4*>(bvh.tri_verts) + 3u * ref;
    const float4 q0 = __ldg(p), q1 = __ldg(p + 1), q2 = __ldg(p + 2);
    a = {q0.x, q0.y, q0.z};
    b = {q1.x, q1.y, q1.z};
    c = {q2.x, q2.y, q2.z};
    n = {q0.w, q1.w, q2.w};
#else
    const float* p = bvh.tri_verts + static_cast<std::size_t>(ref) * kFlatBvhTriStride;
    a = {p[0], p[1], p[2]};
    b = {p[4], p[5], p[6]};
    c = {p[8], p[9], p[10]};
    n = {p[3], p[7], p[11]};
#endif
}

// Reads interior node `index`: both child boxes and child references. In device code: four
// read-only 128-bit loads (nodes must be 16-byte aligned).
SHPRT_HD_INLINE void flat_bvh_load_node(const FlatBvhView& bvh, std::uint32_t index, Aabb& box0,
                                        Aabb& box1, std::uint32_t& child0, std::uint32_t& child1) {
#if defined(__CUDA_ARCH__)
    const float4* p = reinterpret_cast<const float4*>(bvh.nodes + index);
    const float4 q0 = __ldg(p), q1 = __ldg(p + 1), q2 = __ldg(p + 2);
    const uint4 q3 = __ldg(reinterpret_cast<const uint4*>(p + 3));
    // Floats 0..5: box0 lo.xyz, hi.xyz; floats 6..11: box1 lo.xyz, hi.xyz.
    box0 = Aabb{{q0.x, q0.y, q0.z}, {q0.w, q1.x, q1.y}};
    box1 = Aabb{{q1.z, q1.w, q2.x}, {q2.y, q2.z, q2.w}};
    child0 = q3.x;
    child1 = q3.y;
#else
    const FlatBvhNode& node = bvh.nodes[index];
    box0 = node.box[0];
    box1 = node.box[1];
    child0 = node.child[0];
    child1 = node.child[1];
#endif
}

namespace detail {

// The shared traversal. kAnyHit: stop at the first hit (visibility); otherwise find the closest.
// Returns whether something was hit; for closest hit, `ref_out`, t, u, v describe it (ref_out is
// a primitive reference, not yet mapped through tri_ids).
template <bool kAnyHit>
SHPRT_HD_INLINE bool flat_bvh_traverse(const FlatBvhView& bvh, Vec3f o, Vec3f d, float tmin,
                                       float tmax, std::uint32_t& ref_out, float& t_out,
                                       float& u_out, float& v_out) {
    if (bvh.node_count == 0) return false;
    const SlabRay slab = make_slab_ray(o, d);
    const WatertightRay tri_ray = make_watertight_ray(o, d);
    std::uint32_t stack[kFlatBvhStackSize];
    int sp = 0;
    std::uint32_t ref = 0;  // the root, always interior
    bool found = false;
    for (;;) {
        // Inner loop: descend interior nodes until the ray reaches a leaf or runs out of nodes.
        while (!flat_bvh_is_leaf(ref)) {
            Aabb box0, box1;
            std::uint32_t child0, child1;
            flat_bvh_load_node(bvh, ref, box0, box1, child0, child1);
            float t0, t1;
            const bool hit0 = intersect_box(slab, box0, tmin, tmax, t0);
            const bool hit1 = intersect_box(slab, box1, tmin, tmax, t1);
            if (hit0 && hit1) {
                const bool swap = t1 < t0;
                stack[sp++] = swap ? child0 : child1;
                ref = swap ? child1 : child0;
            } else if (hit0) {
                ref = child0;
            } else if (hit1) {
                ref = child1;
            } else {
                if (sp == 0) return found;
                ref = stack[--sp];
            }
        }
        // Leaf: intersect its triangles.
        const std::uint32_t first = flat_bvh_leaf_first(ref);
        const std::uint32_t end = first + flat_bvh_leaf_count(ref);
        for (std::uint32_t i = first; i < end; ++i) {
            Vec3f a, b, c, n;
            flat_bvh_load_triangle(bvh, i, a, b, c, n);
            float t, u, v;
            if (intersect_triangle_watertight(tri_ray, a, b, c, n, tmin, tmax, t, u, v)) {
                found = true;
                if constexpr (kAnyHit) return true;
                tmax = t;
                ref_out = i;
                t_out = t;
                u_out = u;
                v_out = v;
            }
        }
        if (sp == 0) return found;
        ref = stack[--sp];
    }
}

}  // namespace detail

// True when the ray o + t·d hits any triangle with tmin < t < tmax (any-hit traversal).
// Preconditions: d non-zero and finite, 0 ≤ tmin; the tree's depth ≤ kFlatBvhStackSize (the
// builder guarantees it).
SHPRT_HD_INLINE bool bvh_occluded(const FlatBvhView& bvh, Vec3f o, Vec3f d, float tmin,
                                  float tmax) {
    std::uint32_t ref;
    float t, u, v;
    return detail::flat_bvh_traverse<true>(bvh, o, d, tmin, tmax, ref, t, u, v);
}

// The closest hit of o + t·d with tmin < t < tmax: Hit.triangle is the mesh's triangle index,
// (u, v) its barycentrics (p = (1-u-v)·a + u·b + v·c in the mesh's vertex order). On a miss,
// hit = false, triangle = kNoTriangle, t = tmax. Same preconditions as bvh_occluded.
SHPRT_HD_INLINE Hit bvh_intersect(const FlatBvhView& bvh, Vec3f o, Vec3f d, float tmin,
                                  float tmax) {
    std::uint32_t ref = 0;
    float t = tmax, u = 0.0f, v = 0.0f;
    if (!detail::flat_bvh_traverse<false>(bvh, o, d, tmin, tmax, ref, t, u, v))
        return Hit{false, kNoTriangle, tmax, 0.0f, 0.0f};
    return Hit{true, bvh.tri_ids[ref], t, u, v};
}

}  // namespace shprt
