// The ray loop of the blocker cones (blocker_cones.hpp).
#include "trace/blocker_cones.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/host.hpp"

#include <algorithm>

#if defined(__x86_64__)
#include <immintrin.h>
#define SHPRT_CONE_KERNELS_X86 1
#else
#define SHPRT_CONE_KERNELS_X86 0
#endif

namespace shprt::trace_detail {

namespace {

// Ray i's answer (not a sample's: traced already): occluded, or listed to trace.
struct Keep {
    std::uint8_t* occluded;
    std::uint32_t* trace;
    int pending = 0;
    void operator()(int i, bool inside) {
        if (i % kConeStride == 0) return;
        occluded[i] = inside ? 1 : 0;
        trace[pending] = std::uint32_t(i);
        pending += inside ? 0 : 1;
    }
};

// Rays [i, count) one at a time.
void test_cones_portable(const TriangleCone* cone, int samples, const Vec3f* dirs, int i, int count,
                         Keep& keep) {
    for (; i < count; ++i) {
        const int j = i / kConeStride;
        keep(i, in_triangle_cone(cone[j], dirs[i]) ||
                    in_triangle_cone(cone[std::min(j + 1, samples - 1)], dirs[i]));
    }
}

#if SHPRT_CONE_KERNELS_X86
// Four rays at a time (a group of four lies between two samples), then the rest one at a time.
void test_cones_sse(const TriangleCone* cone, int samples, const Vec3f* dirs, int count,
                    Keep& keep) {
    static_assert(kConeStride % 4 == 0, "a group of four rays lies between two samples");
    int i = 0;
    for (; i + 4 <= count; i += 4) {
        const int j = i / kConeStride;
        const TriangleCone& b = cone[j];
        const TriangleCone& a = cone[std::min(j + 1, samples - 1)];
        // Four Vec3f (x y z x | y z x y | z x y z) to x, y and z of the four.
        const float* p = &dirs[i].x;
        const __m128 v0 = _mm_loadu_ps(p), v1 = _mm_loadu_ps(p + 4), v2 = _mm_loadu_ps(p + 8);
        const __m128 x = _mm_shuffle_ps(v0, _mm_shuffle_ps(v1, v2, _MM_SHUFFLE(1, 1, 2, 2)),
                                        _MM_SHUFFLE(2, 0, 3, 0));
        const __m128 y = _mm_shuffle_ps(_mm_shuffle_ps(v0, v1, _MM_SHUFFLE(0, 0, 1, 1)),
                                        _mm_shuffle_ps(v1, v2, _MM_SHUFFLE(2, 2, 3, 3)),
                                        _MM_SHUFFLE(2, 0, 2, 0));
        const __m128 z = _mm_shuffle_ps(_mm_shuffle_ps(v0, v1, _MM_SHUFFLE(1, 1, 2, 2)),
                                        _mm_shuffle_ps(v2, v2, _MM_SHUFFLE(3, 3, 0, 0)),
                                        _MM_SHUFFLE(2, 0, 2, 0));
        auto dot4 = [&](Vec3f n) {
            return _mm_add_ps(
                _mm_add_ps(_mm_mul_ps(x, _mm_set1_ps(n.x)), _mm_mul_ps(y, _mm_set1_ps(n.y))),
                _mm_mul_ps(z, _mm_set1_ps(n.z)));
        };
        // _mm_min_ps(a, b) is fmin2's a < b ? a : b: an empty cone's NaN stays NaN.
        auto inside = [&](const TriangleCone& k) {
            const __m128 m = _mm_min_ps(_mm_min_ps(dot4(k.n0), dot4(k.n1)), dot4(k.n2));
            return _mm_cmpge_ps(m, _mm_setzero_ps());
        };
        const int mask = _mm_movemask_ps(_mm_or_ps(inside(b), inside(a)));
        for (int l = 0; l < 4; ++l) keep(i + l, (mask >> l & 1) != 0);
    }
    test_cones_portable(cone, samples, dirs, i, count, keep);
}

#pragma GCC diagnostic push
// GCC 12's AVX-512 headers fill unused lanes from a self-initialised "undefined" vector.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// d·n of sixteen directions d (x, y, z), as dot(): (x·n.x + y·n.y) + z·n.z, no fused products.
__attribute__((target("avx512f"))) inline __m512 dot16(__m512 x, __m512 y, __m512 z, Vec3f n) {
    return _mm512_add_ps(
        _mm512_add_ps(_mm512_mul_ps(x, _mm512_set1_ps(n.x)), _mm512_mul_ps(y, _mm512_set1_ps(n.y))),
        _mm512_mul_ps(z, _mm512_set1_ps(n.z)));
}

// in_triangle_cone of sixteen directions: _mm512_min_ps(a, b) is fmin2's a < b ? a : b, and the
// compare is ordered (an empty cone's NaN is outside).
__attribute__((target("avx512f"))) inline __mmask16 inside16(const TriangleCone& k, __m512 x,
                                                             __m512 y, __m512 z) {
    const __m512 m = _mm512_min_ps(_mm512_min_ps(dot16(x, y, z, k.n0), dot16(x, y, z, k.n1)),
                                   dot16(x, y, z, k.n2));
    return _mm512_cmp_ps_mask(m, _mm512_setzero_ps(), _CMP_GE_OQ);
}

// Sixteen rays at a time (a group of sixteen lies between two samples): the answers as bytes,
// the rays to trace compressed into the list, then the rest one at a time. AVX-512F alone.
__attribute__((target("avx512f"))) void test_cones_avx512(const TriangleCone* cone, int samples,
                                                          const Vec3f* dirs, int count,
                                                          Keep& keep) {
    static_assert(kConeStride % 16 == 0, "a group of sixteen rays lies between two samples");
    // x, y and z of sixteen Vec3f (48 floats in three registers): the first eleven (ten for z)
    // from the first two registers, the others from the third.
    const __m512i x01 = _mm512_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21, 24, 27, 30, 0, 0, 0, 0, 0);
    const __m512i y01 = _mm512_setr_epi32(1, 4, 7, 10, 13, 16, 19, 22, 25, 28, 31, 0, 0, 0, 0, 0);
    const __m512i z01 = _mm512_setr_epi32(2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 0, 0, 0, 0, 0, 0);
    const __m512i x2 = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 20, 23, 26, 29);
    const __m512i y2 = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 18, 21, 24, 27, 30);
    const __m512i z2 = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 19, 22, 25, 28, 31);
    const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i one = _mm512_set1_epi32(1);
    int i = 0;
    for (; i + 16 <= count; i += 16) {
        const int j = i / kConeStride;
        const float* p = &dirs[i].x;
        const __m512 v0 = _mm512_loadu_ps(p), v1 = _mm512_loadu_ps(p + 16),
                     v2 = _mm512_loadu_ps(p + 32);
        const __m512 x = _mm512_permutex2var_ps(_mm512_permutex2var_ps(v0, x01, v1), x2, v2);
        const __m512 y = _mm512_permutex2var_ps(_mm512_permutex2var_ps(v0, y01, v1), y2, v2);
        const __m512 z = _mm512_permutex2var_ps(_mm512_permutex2var_ps(v0, z01, v1), z2, v2);
        const __mmask16 in = static_cast<__mmask16>(
            inside16(cone[j], x, y, z) | inside16(cone[std::min(j + 1, samples - 1)], x, y, z));
        // The group's first ray is a sample when the group starts a span: its answer stays.
        const bool sample = i % kConeStride == 0;
        const std::uint8_t first = keep.occluded[i];
        _mm_storeu_si128(reinterpret_cast<__m128i*>(keep.occluded + i),
                         _mm512_cvtepi32_epi8(_mm512_maskz_mov_epi32(in, one)));
        if (sample) keep.occluded[i] = first;
        const __mmask16 out = static_cast<__mmask16>(~in & (sample ? 0xFFFEu : 0xFFFFu));
        // The trace list has room for `count`: at most i entries precede this group's.
        _mm512_storeu_si512(
            keep.trace + keep.pending,
            _mm512_maskz_compress_epi32(out, _mm512_add_epi32(_mm512_set1_epi32(i), lanes)));
        keep.pending += __builtin_popcount(unsigned(out));
    }
    test_cones_portable(cone, samples, dirs, i, count, keep);
}
#pragma GCC diagnostic pop
#endif

}  // namespace

bool cone_kernel_available(ConeKernel kernel) {
    switch (kernel) {
        case ConeKernel::automatic:
        case ConeKernel::portable:
            return true;
        case ConeKernel::sse:
            return SHPRT_CONE_KERNELS_X86 != 0;
        case ConeKernel::avx512:
            return SHPRT_CONE_KERNELS_X86 != 0 && cpu_has_avx512f();
    }
    return false;
}

int test_cones(const TriangleCone* cone, int samples, const Vec3f* dirs, int count,
               std::uint8_t* occluded, std::uint32_t* trace, ConeKernel kernel) {
    SHPRT_CHECK(cone_kernel_available(kernel), unsupported,
                "this CPU has no such blocker-cone kernel");
    if (kernel == ConeKernel::automatic)
        kernel = cone_kernel_available(ConeKernel::avx512) ? ConeKernel::avx512
                 : cone_kernel_available(ConeKernel::sse)  ? ConeKernel::sse
                                                           : ConeKernel::portable;
    Keep keep{occluded, trace};
#if SHPRT_CONE_KERNELS_X86
    if (kernel == ConeKernel::avx512) {
        test_cones_avx512(cone, samples, dirs, count, keep);
        return keep.pending;
    }
    if (kernel == ConeKernel::sse) {
        test_cones_sse(cone, samples, dirs, count, keep);
        return keep.pending;
    }
#endif
    test_cones_portable(cone, samples, dirs, 0, count, keep);
    return keep.pending;
}

}  // namespace shprt::trace_detail
