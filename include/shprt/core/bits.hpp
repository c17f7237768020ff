// Reinterpreting a float's bits as an integer and back, for host and device code: CUDA's
// intrinsics on the device, memcpy (the defined way in C++) on the host.
#pragma once

#include "shprt/core/hd.hpp"

#include <cstdint>
#if !defined(__CUDA_ARCH__)
#include <cstring>
#endif

namespace shprt {

SHPRT_HD_INLINE std::uint32_t float_as_u32(float f) {
#if defined(__CUDA_ARCH__)
    return __float_as_uint(f);
#else
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
#endif
}

SHPRT_HD_INLINE float u32_as_float(std::uint32_t u) {
#if defined(__CUDA_ARCH__)
    return __uint_as_float(u);
#else
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
#endif
}

// Two's-complement views of the same bits (what integer offsets of ulps need).
SHPRT_HD_INLINE std::int32_t float_as_i32(float f) {
    return static_cast<std::int32_t>(float_as_u32(f));
}
SHPRT_HD_INLINE float i32_as_float(std::int32_t i) {
    return u32_as_float(static_cast<std::uint32_t>(i));
}

}  // namespace shprt
