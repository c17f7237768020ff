// Counter-based random numbers: Philox-4x32-10 (Salmon, Moraes, Dror, Shaw, "Parallel Random
// Numbers: As Easy as 1, 2, 3", SC 2011), written from the paper and checked against the
// Random123 known-answer vectors in tests/sh/test_sampler.cpp.
//
// A counter-based generator has no state: the random value is a pure function of
// (seed, counter, stream). So the i-th sample of a set is the same bits whatever the thread that
// computes it, the thread count, or the device (all arithmetic here is 32-bit integer).
//
// Mapping of the arguments onto Philox's 128-bit counter and 64-bit key:
//   key     = (seed & 0xffffffff, seed >> 32)
//   counter = (counter & 0xffffffff, counter >> 32, stream, 0)
// `stream` separates independent uses of the same (seed, counter): shprt's samplers use the
// streams kStream* in sampler.hpp (0x53500000 + small numbers); other users pick other values.
#pragma once

#include "shprt/core/hd.hpp"

#include <cstdint>

namespace shprt {

// One Philox block: four independent 32-bit words.
struct RngBlock {
    std::uint32_t v[4];
};

namespace detail {

SHPRT_HD_INLINE void philox_mulhilo(std::uint32_t a, std::uint32_t b, std::uint32_t& hi,
                                    std::uint32_t& lo) {
    const std::uint64_t p = static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b);
    hi = static_cast<std::uint32_t>(p >> 32);
    lo = static_cast<std::uint32_t>(p);
}

}  // namespace detail

// Raw Philox-4x32 with R rounds on the 128-bit counter ctr[4] and the 64-bit key key[2]
// (Salmon et al. 2011, section 4.2; multipliers and Weyl key increments from table 2).
template <int Rounds = 10>
SHPRT_HD_INLINE RngBlock philox4x32(RngBlock ctr, std::uint32_t key0, std::uint32_t key1) {
    constexpr std::uint32_t kM0 = 0xD2511F53u, kM1 = 0xCD9E8D57u;  // round multipliers
    constexpr std::uint32_t kW0 = 0x9E3779B9u, kW1 = 0xBB67AE85u;  // key schedule (golden, √3)
    for (int r = 0; r < Rounds; ++r) {
        if (r > 0) {
            key0 += kW0;
            key1 += kW1;
        }
        std::uint32_t hi0, lo0, hi1, lo1;
        detail::philox_mulhilo(kM0, ctr.v[0], hi0, lo0);
        detail::philox_mulhilo(kM1, ctr.v[2], hi1, lo1);
        ctr = RngBlock{{hi1 ^ ctr.v[1] ^ key0, lo1, hi0 ^ ctr.v[3] ^ key1, lo0}};
    }
    return ctr;
}

// The four words of the Philox-4x32-10 block for (seed, counter, stream), mapped as above.
SHPRT_HD_INLINE RngBlock rng_block(std::uint64_t seed, std::uint64_t counter,
                                   std::uint32_t stream) {
    const RngBlock ctr{{static_cast<std::uint32_t>(counter),
                        static_cast<std::uint32_t>(counter >> 32), stream, 0u}};
    return philox4x32<10>(ctr, static_cast<std::uint32_t>(seed),
                          static_cast<std::uint32_t>(seed >> 32));
}

// Word 0 of the block: a uniformly distributed 32-bit integer.
SHPRT_HD_INLINE std::uint32_t rng_u32(std::uint64_t seed, std::uint64_t counter,
                                      std::uint32_t stream) {
    return rng_block(seed, counter, stream).v[0];
}

// Conversions of random words to [0, 1). Both are exact (no rounding up to 1): the top 24 bits
// of a word for float, the top 53 bits of (hi, lo) for double; so
// to_unit_float(w) = floor(2^24 · to_unit_double(w, lo)) / 2^24 for any lo.
SHPRT_HD_INLINE float to_unit_float(std::uint32_t w) {
    return static_cast<float>(w >> 8) * (1.0f / 16777216.0f);  // 2^-24
}
SHPRT_HD_INLINE double to_unit_double(std::uint32_t hi, std::uint32_t lo) {
    const std::uint64_t bits = (static_cast<std::uint64_t>(hi) << 32) | lo;
    return static_cast<double>(bits >> 11) * (1.0 / 9007199254740992.0);  // 2^-53
}

// Uniform float in [0, 1) from word 0 of the block (24 random bits).
SHPRT_HD_INLINE float rng_float(std::uint64_t seed, std::uint64_t counter, std::uint32_t stream) {
    return to_unit_float(rng_u32(seed, counter, stream));
}

// Uniform double in [0, 1) from words 0 and 1 of the block (53 random bits); rng_float for the
// same arguments is this value rounded down to a multiple of 2^-24.
SHPRT_HD_INLINE double rng_double(std::uint64_t seed, std::uint64_t counter, std::uint32_t stream) {
    const RngBlock b = rng_block(seed, counter, stream);
    return to_unit_double(b.v[0], b.v[1]);
}

}  // namespace shprt
