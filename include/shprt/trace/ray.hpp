// Rays, ray-origin offsetting and the ray/triangle and ray/box tests shared by every tracer that
// is ours (the flat BVH on the CPU and in CUDA kernels). Header-only, SHPRT_HD, no std::vector,
// no exceptions.
//
// Implements:
//  * C. Wächter, N. Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
//    Tracing Gems (2019), ch. 6 — offset_ray_origin.
//  * S. Woop, C. Benthin, I. Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013 —
//    intersect_triangle: its edge tests (two-sided, with the double-precision fallback on zero
//    edge functions); t comes from the plane equation instead (see intersect_triangle_watertight).
//  * T. Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013 — the conservative slab test.
//
// Conventions: a ray is origin o + t·d, d non-zero and finite (it need not be unit length; t is
// measured in units of |d|). Intervals are open: a hit counts when tmin < t < tmax.
#pragma once

#include "shprt/core/bits.hpp"
#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"

#include <cmath>
#include <cstdint>

namespace shprt {

// Closest-hit result. Barycentrics: p = (1-u-v)·a + u·b + v·c for the triangle (a, b, c) =
// mesh.triangles[triangle]; t is the ray parameter (p = o + t·d). To continue a path from the
// hit, take p from the barycentrics (it lies on the surface; o + t·d drifts along the ray for
// grazing hits) and offset it with offset_ray_origin. When hit is false, triangle is
// kNoTriangle and t, u, v are unspecified.
struct Hit {
    bool hit;
    std::uint32_t triangle;
    float t, u, v;
};

inline constexpr std::uint32_t kNoTriangle = 0xFFFFFFFFu;

// Axis-aligned box; empty boxes have lo > hi on some axis.
struct Aabb {
    Vec3f lo, hi;
};

namespace detail {

// min/max that compile to one instruction on both sides (NaN-free inputs assumed).
SHPRT_HD_INLINE float fmin2(float a, float b) {
#if defined(__CUDA_ARCH__)
    return fminf(a, b);
#else
    return a < b ? a : b;
#endif
}
SHPRT_HD_INLINE float fmax2(float a, float b) {
#if defined(__CUDA_ARCH__)
    return fmaxf(a, b);
#else
    return a > b ? a : b;
#endif
}

}  // namespace detail

// Moves a surface point p off its surface along the geometric normal n (unit length, pointing to
// the side the rays leave from), by an amount that scales with p's floating-point magnitude:
// each coordinate is moved by 256·n_i units in the last place (as an integer step on the float's
// bits, in the direction of n_i), or, for coordinates within 1/32 of zero where ulps are tiny, by
// the absolute amount n_i/65536. Wächter & Binder's constants: the offset stays above the
// rounding error of the intersection point and of triangle vertices of the same magnitude, so a
// ray leaving into n's half-space cannot re-hit the surface it starts on.
// Convention for every tracer: origin = offset_ray_origin(position, normal), tnear = 0.
SHPRT_HD_INLINE Vec3f offset_ray_origin(Vec3f p, Vec3f n) {
    constexpr float kOrigin = 1.0f / 32.0f;
    constexpr float kFloatScale = 1.0f / 65536.0f;
    constexpr float kIntScale = 256.0f;
    Vec3f out;
    for (int i = 0; i < 3; ++i) {
        const float pi = p[i], ni = n[i];
        if (std::fabs(pi) < kOrigin) {
            out[i] = pi + kFloatScale * ni;
            continue;
        }
        // Only here: near zero the bits of −0.0 (INT32_MIN) plus a negative step would overflow.
        const std::int32_t step = static_cast<std::int32_t>(kIntScale * ni);
        // Adding to the bit pattern of a negative float moves it away from zero, hence the sign.
        out[i] = i32_as_float(float_as_i32(pi) + (pi < 0 ? -step : step));
    }
    return out;
}

// Per-ray constants of the watertight test (Woop et al. 2013, section 3): the axis kz along which
// |d| is largest, the two others (kx, ky; swapped when d[kz] < 0 to keep the winding), and the
// shear (sx, sy) that maps d onto the kz axis.
struct WatertightRay {
    Vec3f o, d;
    int kx, ky, kz;
    float sx, sy;
};

SHPRT_HD_INLINE WatertightRay make_watertight_ray(Vec3f o, Vec3f d) {
    const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    WatertightRay r;
    r.o = o;
    r.d = d;
    r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    r.kx = r.kz == 2 ? 0 : r.kz + 1;
    r.ky = r.kx == 2 ? 0 : r.kx + 1;
    if (d[r.kz] < 0.0f) {
        const int k = r.kx;
        r.kx = r.ky;
        r.ky = k;
    }
    r.sx = d[r.kx] / d[r.kz];
    r.sy = d[r.ky] / d[r.kz];
    return r;
}

// The (unnormalised) geometric normal of triangle (a, b, c): (b − a) × (c − a). The flat BVH
// stores it beside the vertices; it must be computed by this function so that stored and
// recomputed normals are the same bits.
SHPRT_HD_INLINE Vec3f triangle_normal(Vec3f a, Vec3f b, Vec3f c) { return cross(b - a, c - a); }

// Watertight, two-sided ray/triangle test (Woop, Benthin & Wald 2013). A ray through a shared edge
// or vertex of a closed mesh hits at least one of the triangles that share it; edge functions that
// come out exactly zero in float are recomputed in double, as the paper prescribes. Degenerate
// (zero-area) triangles never report a hit. On a hit with tmin < t < tmax, returns true and sets
// t, and the barycentrics u, v with p = (1-u-v)·a + u·b + v·c; otherwise leaves them untouched.
//
// t is the plane distance t = n·(a − o) / n·d with n = triangle_normal(a, b, c), not the paper's
// sheared T/det (same value up to rounding). Why: a ray that starts exactly in the plane of an
// axis-aligned triangle — a floor vertex at the foot of a wall, a box corner vertex lying in the
// planes of its neighbouring faces — has n·(a − o) = 0 exactly here, so t = 0 and the hit is
// rejected (t > tmin = 0) whatever the direction, as Embree does; the sheared form mixes axes and
// returns rounding noise of either sign (t ≈ ±1e-12), i.e. spurious occlusion at such creases.
// `n` must be triangle_normal(a, b, c) (the flat BVH passes its stored copy).
SHPRT_HD_INLINE bool intersect_triangle_watertight(const WatertightRay& r, Vec3f a, Vec3f b,
                                                   Vec3f c, Vec3f n, float tmin, float tmax,
                                                   float& t, float& u, float& v) {
    const Vec3f A = a - r.o, B = b - r.o, C = c - r.o;
    const float Akz = A[r.kz], Bkz = B[r.kz], Ckz = C[r.kz];
    const float Ax = A[r.kx] - r.sx * Akz, Ay = A[r.ky] - r.sy * Akz;
    const float Bx = B[r.kx] - r.sx * Bkz, By = B[r.ky] - r.sy * Bkz;
    const float Cx = C[r.kx] - r.sx * Ckz, Cy = C[r.ky] - r.sy * Ckz;
    // Scaled barycentrics: edge functions of the edges opposite a, b and c.
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        // Products of floats are exact in double, so the sign of each difference is exact.
        U = static_cast<float>(static_cast<double>(Cx) * By - static_cast<double>(Cy) * Bx);
        V = static_cast<float>(static_cast<double>(Ax) * Cy - static_cast<double>(Ay) * Cx);
        W = static_cast<float>(static_cast<double>(Bx) * Ay - static_cast<double>(By) * Ax);
    }
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
    const float det = U + V + W;
    const float den = dot(n, r.d);
    if (det == 0.0f || den == 0.0f) return false;
    // The interval test is on the rounded t itself (not on a scaled numerator against tmax·den),
    // so the closest hit of a set of triangles does not depend on the order they are tested in.
    const float t_hit = dot(n, A) / den;
    if (!(t_hit > tmin) || !(t_hit < tmax)) return false;
    const float inv_det = 1.0f / det;
    t = t_hit;
    u = V * inv_det;
    v = W * inv_det;
    return true;
}

// The same without a precomputed normal.
SHPRT_HD_INLINE bool intersect_triangle_watertight(const WatertightRay& r, Vec3f a, Vec3f b,
                                                   Vec3f c, float tmin, float tmax, float& t,
                                                   float& u, float& v) {
    return intersect_triangle_watertight(r, a, b, c, triangle_normal(a, b, c), tmin, tmax, t, u, v);
}

// Convenience form that sets up the per-ray constants for one test.
SHPRT_HD_INLINE bool intersect_triangle(Vec3f o, Vec3f d, Vec3f a, Vec3f b, Vec3f c, float tmin,
                                        float tmax, float& t, float& u, float& v) {
    return intersect_triangle_watertight(make_watertight_ray(o, d), a, b, c, tmin, tmax, t, u, v);
}

// The directions in which rays from a point o hit a triangle (a, b, c) at t > 0: the cone
// {α·A + β·B + γ·C : α, β, γ ≥ 0, not all 0} with A = a − o, B = b − o, C = c − o. Writing
// d = α·A + β·B + γ·C gives d·(B×C) = α·det, d·(C×A) = β·det, d·(A×B) = γ·det with
// det = A·(B×C), so d is in the cone exactly when those three have det's sign: the cone's three
// plane normals, oriented inwards, and a test of three dot products with no division. The Embree
// tracer tests the rays of one origin against the cones of triangles that blocked nearby rays
// (tracer.hpp, "Blocker cones").
// The normals are computed in double (A − o exactly, then the products) and stored as unit
// vectors in float, so that each is right to float rounding whatever the triangle's shape seen
// from o (a sliver's float cross products are not) and however far o is from the origin. A cone
// whose o lies in the triangle's plane to float precision — within 2^-20 of the largest
// coordinate of o, a, b and c, eight units in the last place — is empty: nothing is inside. That
// is the tracers' crease rule (tracer.hpp): a ray starting on another surface does not hit it
// (float tests see t = 0 there, or rounding noise), so neither may a cone. So is a cone thinner
// than 2^-10 (|det| against |A|·|B|·|C|, the sine of the corners' solid angle): a sliver, or a
// triangle seen edge-on, whose three planes are nearly one, so that float rounding of the
// normals could put directions pointing away from it on their inner sides. Such a cone holds
// few rays anyway; an empty cone only sends its rays to the tracer.
struct TriangleCone {
    Vec3f n0, n1, n2;
};

namespace detail {
SHPRT_HD_INLINE float largest_abs(Vec3f p) {
    return std::fmax(std::fabs(p.x), std::fmax(std::fabs(p.y), std::fabs(p.z)));
}
}  // namespace detail

SHPRT_HD_INLINE TriangleCone triangle_cone(Vec3f o, Vec3f a, Vec3f b, Vec3f c) {
    using V = Vec3<double>;
    const V O{o.x, o.y, o.z};
    const V A = V{a.x, a.y, a.z} - O, B = V{b.x, b.y, b.z} - O, C = V{c.x, c.y, c.z} - O;
    V n[3] = {cross(B, C), cross(C, A), cross(A, B)};
    // det = A·(B×C) = A·N with N = (B − A)×(C − A): |det|/|N| is o's distance from the plane.
    const double det = dot(A, n[0]);
    const V N = cross(B - A, C - A);
    const double magnitude =
        double(std::fmax(std::fmax(detail::largest_abs(o), detail::largest_abs(a)),
                         std::fmax(detail::largest_abs(b), detail::largest_abs(c))));
    const double corners = std::sqrt(dot(A, A) * dot(B, B) * dot(C, C));
    TriangleCone k;
    if (!(std::fabs(det) > 9.5367431640625e-07 * magnitude * std::sqrt(dot(N, N))) ||  // 2^-20
        !(std::fabs(det) > 9.765625e-04 * corners)) {                                  // 2^-10
        const float nan = i32_as_float(0x7FC00000);  // a quiet NaN
        k.n0 = k.n1 = k.n2 = Vec3f{nan, nan, nan};   // every comparison with NaN is false
        return k;
    }
    Vec3f* out[3] = {&k.n0, &k.n1, &k.n2};
    for (int i = 0; i < 3; ++i) {
        const double s = (det < 0.0 ? -1.0 : 1.0) / std::sqrt(dot(n[i], n[i]));
        *out[i] = Vec3f{float(n[i].x * s), float(n[i].y * s), float(n[i].z * s)};
    }
    return k;
}

// Whether the ray o + t·d, t > 0, hits the cone's triangle (directions on its boundary count, as
// rays through a closed triangle's edges do).
// Branch-free (the smallest of the three against 0), so that loops over rays vectorise. An empty
// cone's three NaN products give NaN on either side of fmin2, and NaN >= 0 is false.
SHPRT_HD_INLINE bool in_triangle_cone(const TriangleCone& k, Vec3f d) {
    using detail::fmin2;
    return fmin2(fmin2(dot(d, k.n0), dot(d, k.n1)), dot(d, k.n2)) >= 0.0f;
}

// Per-ray constants of the slab test. Direction components of magnitude below 2^-80 are replaced
// by ±2^-80 so the reciprocal stays finite and no 0·∞ arises (Aila & Laine's trick).
struct SlabRay {
    Vec3f o, inv_d;
};

SHPRT_HD_INLINE SlabRay make_slab_ray(Vec3f o, Vec3f d) {
    constexpr float kEps = 8.27180612553027674871e-25f;  // 2^-80
    SlabRay r;
    r.o = o;
    for (int i = 0; i < 3; ++i) {
        const float di = d[i];
        r.inv_d[i] = 1.0f / (std::fabs(di) > kEps ? di : (di < 0.0f ? -kEps : kEps));
    }
    return r;
}

// Conservative slab test (Ize 2013): true when the ray's parameter interval [tmin, tmax] overlaps
// the box; tnear receives the entry parameter (clamped to tmin). The exit parameter is enlarged by
// 1 + 2·γ(3) so that float rounding never culls a box the exact ray touches.
SHPRT_HD_INLINE bool intersect_box(const SlabRay& r, const Aabb& b, float tmin, float tmax,
                                   float& tnear) {
    using detail::fmax2;
    using detail::fmin2;
    constexpr float kRobust = 1.0f + 2.0f * 3.0f * 5.9604645e-8f / (1.0f - 3.0f * 5.9604645e-8f);
    const float x0 = (b.lo.x - r.o.x) * r.inv_d.x, x1 = (b.hi.x - r.o.x) * r.inv_d.x;
    const float y0 = (b.lo.y - r.o.y) * r.inv_d.y, y1 = (b.hi.y - r.o.y) * r.inv_d.y;
    const float z0 = (b.lo.z - r.o.z) * r.inv_d.z, z1 = (b.hi.z - r.o.z) * r.inv_d.z;
    const float t0 = fmax2(fmax2(fmin2(x0, x1), fmin2(y0, y1)), fmax2(fmin2(z0, z1), tmin));
    const float t1 = fmin2(fmin2(fmax2(x0, x1), fmax2(y0, y1)), fmin2(fmax2(z0, z1), tmax));
    tnear = t0;
    return t0 <= t1 * kRobust;
}

}  // namespace shprt
