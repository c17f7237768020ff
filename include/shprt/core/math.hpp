// Mathematical constants, defined once for host and device code (CUDA-safe: plain constexpr
// scalars, usable in SHPRT_HD functions and .cu files).
#pragma once

namespace shprt {

// π to double precision (the double nearest to π, as std::numbers::pi).
inline constexpr double kPi = 3.14159265358979323846264338327950288;
// π rounded to float (float(kPi), the float nearest to π): for float-only code.
inline constexpr float kPiF = static_cast<float>(kPi);
// Radians per degree.
inline constexpr double kDeg = kPi / 180.0;

}  // namespace shprt
