// IEEE 754 binary16 ("half") conversion, written once for host and device. The .shprt file stores
// transfer coefficients as float16 when asked to (`shprt bake --half`); readers widen them back
// to float32 with half_to_float, which is exact.
//
// binary16: 1 sign bit, 5 exponent bits (bias 15), 10 mantissa bits. Largest finite value 65504,
// smallest normal 2^-14, smallest subnormal 2^-24; relative rounding error at most 2^-11 for
// normal values.
#pragma once

#include "shprt/core/bits.hpp"
#include "shprt/core/hd.hpp"

#include <cstdint>

namespace shprt {

// Nearest binary16 to `f`, ties to even (the IEEE default, and what F16C's VCVTPS2PH with
// rounding mode 0 and CUDA's __float2half_rn give). Works on the bits, so the result does not
// depend on the FPU's flush-to-zero / denormals-are-zero state:
//   |f| >= 65520 (the midpoint above 65504)  -> ±inf
//   inf -> inf, NaN -> a quiet NaN of the same sign (top payload bits kept)
//   |f| < 2^-14 -> a binary16 subnormal (or ±0), float subnormal inputs included
SHPRT_HD_INLINE std::uint16_t float_to_half(float f) {
    const std::uint32_t x = float_as_u32(f);
    const std::uint32_t sign = (x >> 16) & 0x8000u;
    const std::uint32_t ax = x & 0x7fffffffu;
    if (ax >= 0x7f800000u) {  // inf or NaN
        if (ax == 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7c00u);
        return static_cast<std::uint16_t>(sign | 0x7e00u | ((ax >> 13) & 0x3ffu));
    }
    if (ax >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // >= 65520
    if (ax >= 0x38800000u) {  // normal binary16 range [2^-14, 65520)
        // Round the 13 dropped mantissa bits to nearest even without a branch: adding
        // 0xfff + (lowest kept bit) carries into the kept bits exactly when the dropped part is
        // above half, or exactly half with an odd kept part. A carry out of the mantissa
        // correctly bumps the exponent. Then rebias the exponent (127 -> 15).
        const std::uint32_t rounded = ax + 0xfffu + ((ax >> 13) & 1u);
        return static_cast<std::uint16_t>(sign | ((rounded >> 13) - (112u << 10)));
    }
    if (ax < 0x33000000u) return static_cast<std::uint16_t>(sign);  // < 2^-25 rounds to ±0
    // Subnormal: the result is |f| / 2^-24 rounded to an integer. With e the biased exponent and
    // m the 24-bit significand, |f| / 2^-24 = m · 2^(e-126), a right shift by 126 - e in [14, 24].
    const std::uint32_t e = ax >> 23;
    const std::uint32_t m = (ax & 0x7fffffu) | 0x800000u;
    const std::uint32_t shift = 126u - e;
    std::uint32_t h = m >> shift;
    const std::uint32_t rest = m & ((1u << shift) - 1u);
    const std::uint32_t half_ulp = 1u << (shift - 1u);
    if (rest > half_ulp || (rest == half_ulp && (h & 1u))) ++h;  // 0x3ff + 1 = smallest normal
    return static_cast<std::uint16_t>(sign | h);
}

// The float32 value of binary16 `h`; exact for every input (NaN payloads are kept).
SHPRT_HD_INLINE float half_to_float(std::uint16_t h) {
    const std::uint32_t sign = (std::uint32_t(h) & 0x8000u) << 16;
    const std::uint32_t e = (std::uint32_t(h) >> 10) & 0x1fu;
    const std::uint32_t m = std::uint32_t(h) & 0x3ffu;
    if (e == 31u) return u32_as_float(sign | 0x7f800000u | (m << 13));
    if (e != 0u) return u32_as_float(sign | ((e + 112u) << 23) | (m << 13));
    if (m == 0u) return u32_as_float(sign);
    // Subnormal m · 2^-24: shift the leading 1 of m up to the implicit-bit position (bit 10).
    std::uint32_t exp = 113u;  // biased float exponent of 2^-14
    std::uint32_t mant = m;
    while ((mant & 0x400u) == 0u) {
        mant <<= 1;
        --exp;
    }
    return u32_as_float(sign | (exp << 23) | ((mant & 0x3ffu) << 13));
}

}  // namespace shprt
