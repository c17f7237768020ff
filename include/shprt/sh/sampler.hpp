// Direction sets on the unit sphere, as pure functions of (seed, index): the same set comes out
// on the CPU and the GPU. Exact quadrature sets (Gauss–Legendre in cos θ × uniform φ) for tests
// and lights.
//
// Every Monte Carlo sampler below is a map of a point (u, v) of the unit square (or of a cell of
// it) to the sphere by the paper's formula (θ, φ) = (2·acos(√(1−u)), 2π·v). Since
// cos(2·acos a) = 2a² − 1, that is z = cos θ = 1 − 2u (uniform in (−1, 1]: equal areas in u are
// equal solid angles) and sin θ = 2·√(u(1−u)), which is how it is evaluated (no acos, exact
// unit length up to rounding). θ is measured from +Z, φ from +X toward +Y (sh/basis.hpp).
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/sh/rng.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

// clang-format off
enum class SamplerKind {
    uniform,     // the paper's set: (θ, φ) = (2·acos(√(1−x)), 2π·y), x, y from the counter RNG
    stratified,  // jittered grid in (cos θ, φ)
    fibonacci,   // spherical Fibonacci lattice
    sobol,       // Sobol (0,2)-sequence mapped to the sphere, Owen-scrambled by seed
};
// clang-format on

// All kinds, in declaration order (for tools and tests that loop over them).
inline constexpr SamplerKind kAllSamplerKinds[] = {SamplerKind::uniform, SamplerKind::stratified,
                                                   SamplerKind::fibonacci, SamplerKind::sobol};

const char* to_string(SamplerKind kind);
SamplerKind parse_sampler_kind(const std::string& name);  // throws Error(invalid_argument)

// Where a bake's shared direction set lives (docs/sampling.md):
//  * sphere: one set on the whole sphere in world space, weights 4π/S (the paper's scheme); a
//    receiver uses the directions above its horizon, about S/2 of them.
//  * local:  one set on the hemisphere around +z of a receiver's tangent frame (cosine-weighted
//    for diffuse transfer, uniform for glossy), turned into each receiver's frame by the rotation
//    of local_frame.hpp: every direction is above the horizon and is traced; the coefficients
//    projected in the frame are rotated to world space band by band.
enum class DirectionFrame { sphere, local };
const char* to_string(DirectionFrame frame);
DirectionFrame parse_direction_frame(const std::string& name);  // "sphere", "local"; throws Error

// A direction set with integration weights: ∫ f dω ≈ Σ_s weights[s] · f(dirs[s]).
// Monte Carlo sets carry the constant weight 4π/S; quadrature sets carry exact weights.
struct DirectionSet {
    std::vector<float> dirs;     // xyz triples, unit length, S of them
    std::vector<float> weights;  // S weights
    // Where the directions live: world space (make_direction_set) or a receiver's tangent frame,
    // +z the normal (make_local_direction_set). A bake given a set reads it in this frame.
    DirectionFrame frame = DirectionFrame::sphere;
    std::size_t size() const { return weights.size(); }
};

// The same in double precision, for exact quadrature (a float set cannot integrate to better
// than ~1e-7) and for reference computations.
struct DirectionSetD {
    std::vector<double> dirs;     // xyz triples, unit length, S of them
    std::vector<double> weights;  // S weights
    std::size_t size() const { return weights.size(); }
};

// Philox streams used by the samplers (rng.hpp); other users of the RNG pick other streams.
inline constexpr std::uint32_t kStreamUniform = 0x53500001u;
inline constexpr std::uint32_t kStreamStratified = 0x53500002u;
inline constexpr std::uint32_t kStreamFibonacci = 0x53500003u;
inline constexpr std::uint32_t kStreamSobol = 0x53500004u;

// ---------------------------------------------------------------------------------------------
// Building blocks (SHPRT_HD; public so tests and kernels can check and reuse them)

// The paper's map of (u, v) ∈ [0,1)² to the unit sphere: z = 1 − 2u, φ = 2πv (see top).
template <class T>
SHPRT_HD_INLINE Vec3<T> square_to_sphere(T u, T v) {
    const T r = T(2) * std::sqrt(u * (T(1) - u));
    const T phi = T(6.28318530717958647692528676655900577) * v;
    return {r * std::cos(phi), r * std::sin(phi), T(1) - T(2) * u};
}

// A uniform value in [0,1) of type T from one or two random words: float keeps the top 24 bits
// of `hi`, double the top 53 bits of (hi, lo).
template <class T>
SHPRT_HD_INLINE T unit_from_bits(std::uint32_t hi, std::uint32_t lo) {
    if constexpr (sizeof(T) == sizeof(float)) {
        (void)lo;
        return to_unit_float(hi);
    } else {
        return static_cast<T>(to_unit_double(hi, lo));
    }
}

SHPRT_HD_INLINE std::uint32_t reverse_bits32(std::uint32_t x) {
#if defined(__CUDA_ARCH__)
    return __brev(x);
#else
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
#endif
}

// Unscrambled 2-D Sobol point `index` as 32-bit fractions (value = word / 2^32). Dimension 0 is
// the van der Corput sequence (bit reversal); dimension 1 uses the direction numbers of the
// primitive polynomial x + 1 (v_1 = 1/2, v_k = v_{k−1} ⊕ v_{k−1}/2: the Pascal matrix mod 2).
// Together they form a (0,2)-sequence: every 2^m consecutive points aligned at a multiple of 2^m
// put exactly one point in each elementary interval of area 2^−m.
SHPRT_HD_INLINE std::uint32_t sobol_u32(std::uint32_t index, int dim) {
    if (dim == 0) return reverse_bits32(index);
    std::uint32_t x = 0, v = 0x80000000u;
    for (; index != 0; index >>= 1, v ^= v >> 1)
        if (index & 1u) x ^= v;
    return x;
}

// Nested uniform (Owen) scramble of a 32-bit fraction by hashing (Burley 2020, "Practical
// Hash-based Owen Scrambling", after Laine and Karras 2011). In bit-reversed order each step
// (add, xor with a multiple by an even constant) changes bit k only as a function of bits < k,
// so in the original order every digit is permuted as a function of the digits above it:
// a nested scramble, and a bijection. It keeps the (0,m,2)-net property of Sobol points.
SHPRT_HD_INLINE std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
    x = reverse_bits32(x);
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return reverse_bits32(x);
}

// Owen-scrambled Sobol point `index`, dimension `dim` (0 or 1), for `seed`: the per-dimension
// scramble seeds are words 0 and 1 of Philox(seed, 0, kStreamSobol).
SHPRT_HD_INLINE std::uint32_t sobol_scrambled_u32(std::uint64_t seed, std::uint32_t index,
                                                  int dim) {
    const RngBlock key = rng_block(seed, 0, kStreamSobol);
    return owen_scramble(sobol_u32(index, dim), key.v[dim == 0 ? 0 : 1]);
}

// Stratified sets: the sphere is cut into `count` cells of equal solid angle 4π/count, one sample
// jittered uniformly inside each. Cells are rows of constant cos θ range × equal φ sectors.
// rows = max(1, round(√(count/π))) makes cells nearly square at the equator. When count is not
// rows × columns, row r holds cells [first_r, first_{r+1}) with first_r = ⌊r·count/rows⌋
// (⌊count/rows⌋ or ⌈count/rows⌉ cells) and its height in cos θ is 2·cells_r/count, so every cell
// still has solid angle exactly 4π/count: any count ≥ 1 is a proper stratification.
// Cell index = direction index, in row-major order from the north pole (+Z).
struct StratifiedCell {
    std::uint32_t row;    // row of the cell (0 at +Z)
    std::uint32_t rows;   // number of rows
    std::uint32_t first;  // index of the row's first cell
    std::uint32_t cells;  // number of cells in the row
};

SHPRT_HD_INLINE std::uint32_t stratified_rows(std::uint32_t count) {
    const double r = std::sqrt(static_cast<double>(count) * 0.31830988618379067154);  // /π
    const std::uint32_t rows = static_cast<std::uint32_t>(r + 0.5);
    return rows < 1u ? 1u : rows;
}

// Cell of direction `index` (< count) in the stratified set of `count` directions.
SHPRT_HD_INLINE StratifiedCell stratified_cell(std::uint32_t index, std::uint32_t count) {
    const std::uint64_t n = count, rows = stratified_rows(count);
    // Largest r with ⌊r·n/rows⌋ ≤ index, i.e. r = ⌈(index+1)·rows/n⌉ − 1.
    const std::uint64_t r = ((static_cast<std::uint64_t>(index) + 1) * rows - 1) / n;
    const std::uint64_t first = r * n / rows, next = (r + 1) * n / rows;
    return {static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(rows),
            static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(next - first)};
}

// Rotation matrix from a uniformly random unit quaternion (Shoemake 1992, "Uniform random
// rotations", Graphics Gems III); u1, u2 from Philox(seed, 0, stream), u3 from
// Philox(seed, 1, stream).
template <class T>
SHPRT_HD_INLINE Mat3<T> random_rotation(std::uint64_t seed, std::uint32_t stream) {
    const RngBlock b = rng_block(seed, 0, stream), c = rng_block(seed, 1, stream);
    const T u1 = unit_from_bits<T>(b.v[0], b.v[1]);
    const T u2 = unit_from_bits<T>(b.v[2], b.v[3]);
    const T u3 = unit_from_bits<T>(c.v[0], c.v[1]);
    const T two_pi = T(6.28318530717958647692528676655900577);
    const T s1 = std::sqrt(T(1) - u1), s2 = std::sqrt(u1);
    const T qx = s1 * std::sin(two_pi * u2), qy = s1 * std::cos(two_pi * u2);
    const T qz = s2 * std::sin(two_pi * u3), qw = s2 * std::cos(two_pi * u3);
    return {{{T(1) - T(2) * (qy * qy + qz * qz), T(2) * (qx * qy - qz * qw),
              T(2) * (qx * qz + qy * qw)},
             {T(2) * (qx * qy + qz * qw), T(1) - T(2) * (qx * qx + qz * qz),
              T(2) * (qy * qz - qx * qw)},
             {T(2) * (qx * qz - qy * qw), T(2) * (qy * qz + qx * qw),
              T(1) - T(2) * (qx * qx + qy * qy)}}};
}

// Point `index` of the unrotated spherical Fibonacci lattice of `count` points (Swinbank and
// Purser 2006; Marques et al. 2013): z = 1 − (2·index + 1)/count, φ = 2π·frac(index/Φ), Φ the
// golden ratio. frac(index/Φ) is computed in 64-bit fixed point, exactly the same on every
// device.
template <class T>
SHPRT_HD_INLINE Vec3<T> fibonacci_lattice_point(std::uint32_t index, std::uint32_t count) {
    const std::uint64_t frac = static_cast<std::uint64_t>(index) * 0x9E3779B97F4A7C15ull;  // 2^64/Φ
    const T u = (static_cast<T>(index) + T(0.5)) / static_cast<T>(count);
    return square_to_sphere<T>(u, unit_from_bits<T>(static_cast<std::uint32_t>(frac >> 32),
                                                    static_cast<std::uint32_t>(frac)));
}

// ---------------------------------------------------------------------------------------------
// The samplers

// Direction `index` (0 ≤ index < count) of the `count`-direction set of `kind` and `seed`, as a
// unit vector. A pure function: GPU kernels call it per ray and get the set make_direction_set
// builds. float and double differ only by the rounding of u, v to 24 bits (|Δu| < 2^-24), which
// moves the direction by ~2^-24/√(u(1−u)): ~1e-7 over most of the sphere, at most 2^-11 right
// at the poles. Precondition: count ≥ 1.
//  * uniform:    (u, v) from Philox(seed, index, kStreamUniform); independent of count, so the
//                first n directions of any set are the n-direction set (the paper's set).
//  * stratified: one jittered sample per equal-solid-angle cell (StratifiedCell above; any
//                count), jitter from Philox(seed, index, kStreamStratified).
//  * fibonacci:  the spherical Fibonacci lattice of `count` points, rotated by the uniformly
//                random rotation random_rotation(seed, kStreamFibonacci) (the seed only rotates
//                it: every seed gives the same point spacing).
//  * sobol:      Owen-scrambled Sobol point `index` (seeds from Philox(seed, 0, kStreamSobol));
//                independent of count; best when count is a power of two (a (0,m,2)-net).
// Nested prefixes: for uniform and sobol the first n directions of any set are the n-direction
// set; stratified and fibonacci sets depend on count and are not nested.
// Convergence is a property of the RMS error over seeds (tests/sh/test_sampler.cpp,
// ErrorFallsAsOneOverRootSForEverySampler: ∝ 1/√S for uniform, faster for the others). One
// seed's curve is one draw, and with nested prefixes the error at 4S contains the error at S: for
// a peaked light a quarter of the seeds show no fall from S to 4S, as an independent random
// generator does (issue 39; seed 1 on the unshadowed sphere under a sun-like lobe: 4.0 %, 11.1 %,
// 4.5 % at S = 4096, 16384, 65536, where the RMS over 8 seeds falls 11.5 %, 6.1 %, 4.1 %).
template <class T>
SHPRT_HD_INLINE Vec3<T> sphere_direction(SamplerKind kind, std::uint64_t seed, std::uint32_t index,
                                         std::uint32_t count) {
    switch (kind) {
        case SamplerKind::stratified: {
            const StratifiedCell c = stratified_cell(index, count);
            const RngBlock b = rng_block(seed, index, kStreamStratified);
            const T ju = unit_from_bits<T>(b.v[0], b.v[1]), jv = unit_from_bits<T>(b.v[2], b.v[3]);
            const T u =
                (static_cast<T>(c.first) + ju * static_cast<T>(c.cells)) / static_cast<T>(count);
            const T v = (static_cast<T>(index - c.first) + jv) / static_cast<T>(c.cells);
            return square_to_sphere<T>(u, v);
        }
        case SamplerKind::fibonacci:
            return random_rotation<T>(seed, kStreamFibonacci) *
                   fibonacci_lattice_point<T>(index, count);
        case SamplerKind::sobol: {
            const RngBlock key = rng_block(seed, 0, kStreamSobol);
            const std::uint32_t a = owen_scramble(sobol_u32(index, 0), key.v[0]);
            const std::uint32_t b = owen_scramble(sobol_u32(index, 1), key.v[1]);
            return square_to_sphere<T>(unit_from_bits<T>(a, 0u), unit_from_bits<T>(b, 0u));
        }
        case SamplerKind::uniform:
        default: {
            const RngBlock b = rng_block(seed, index, kStreamUniform);
            return square_to_sphere<T>(unit_from_bits<T>(b.v[0], b.v[1]),
                                       unit_from_bits<T>(b.v[2], b.v[3]));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Hemisphere maps (the local direction sets, docs/sampling.md)
//
// A direction d = (x, y, z) uniform on the sphere has z uniform on [−1, 1] and its azimuth φ
// uniform and independent of z, so u = (1 + z)/2 is uniform on [0, 1]. The maps below keep φ and
// send u to the polar angle θ' about +z of the hemisphere:
//  * cosine:  cos θ' = √u, density cos θ'/π (∫ cos θ' f dω ≈ (π/S)·Σ f over S directions);
//  * uniform: cos θ' = u,  density 1/(2π)   (∫ f dω ≈ (2π/S)·Σ f).
// Both are monotone in z and keep φ, so they carry a set's stratification (Sobol's elementary
// intervals, the stratified cells) and its nested prefixes to the hemisphere. With
// x² + y² = (1 − z)(1 + z): the cosine map is (x, y)/√(2(1 + z)), √((1 + z)/2); the uniform map
// scales (x, y) by sin θ'/sin θ = √(1 − u²)/√(1 − z²). The pole z = −1 goes to the horizon
// along +x.
template <class T>
SHPRT_HD_INLINE Vec3<T> sphere_to_cosine_hemisphere(Vec3<T> d) {
    const T up = T(1) + d.z;
    if (!(up > T(0))) return {T(1), T(0), T(0)};
    const T r = T(1) / std::sqrt(T(2) * up);
    return {d.x * r, d.y * r, std::sqrt(T(0.5) * up)};
}
template <class T>
SHPRT_HD_INLINE Vec3<T> sphere_to_uniform_hemisphere(Vec3<T> d) {
    const T u = T(0.5) * (T(1) + d.z);
    const T sin2 = (T(1) - d.z) * (T(1) + d.z);  // sin² θ of d
    if (!(sin2 > T(0))) return d.z > T(0) ? Vec3<T>{T(0), T(0), T(1)} : Vec3<T>{T(1), T(0), T(0)};
    const T r = std::sqrt((T(1) - u) * (T(1) + u) / sin2);
    return {d.x * r, d.y * r, u};
}

// ---------------------------------------------------------------------------------------------
// Host-side sets

// The `count`-direction set of `kind` and `seed` with weights 4π/count: direction s is
// sphere_direction<double>(kind, seed, s, count) rounded to float. Single-threaded (tens of
// millions of directions/s). Throws Error(invalid_argument) when count is 0 or above 2^28.
// (A GPU bake that needs the table's exact bits should upload these directions rather than
// recompute them in float.)
DirectionSet make_direction_set(SamplerKind kind, std::uint64_t seed, std::uint32_t count);
// The same set in double precision.
DirectionSetD make_direction_set_d(SamplerKind kind, std::uint64_t seed, std::uint32_t count);

// Exact product quadrature: n_theta Gauss–Legendre nodes in z = cos θ on [−1, 1] (weights w_i)
// × n_phi equally spaced φ_k = 2π(k + ½)/n_phi, weight w_i · 2π/n_phi (the weights sum to 4π).
// Integrates exactly every polynomial in (x, y, z) whose z-degree after averaging over φ is
// ≤ 2·n_theta − 1 and whose φ-frequencies are < n_phi. Directions ordered θ-major from +Z.
// Throws Error(invalid_argument) unless 1 ≤ n_theta, n_phi ≤ 65536 and n_theta·n_phi ≤ 2^28.
DirectionSetD gauss_legendre_set_d(int n_theta, int n_phi);
// The same rounded to float (exact only to ~1e-7).
DirectionSet gauss_legendre_set(int n_theta, int n_phi);

// The smallest product rule above that integrates exactly the product of two functions
// band-limited to `bands` bands (l ≤ bands − 1): the product has z-degree ≤ 2·bands − 2 and
// φ-frequencies ≤ 2·bands − 2, so n_theta = bands and n_phi = 2·bands − 1.
// Throws Error(invalid_argument) unless 1 ≤ bands ≤ 4096.
DirectionSetD quadrature_set_for_bands_d(int bands);
DirectionSet quadrature_set_for_bands(int bands);

// The density of a local set on its hemisphere (see the maps above).
enum class HemisphereDensity { cosine, uniform };

// The `count`-direction local set of `kind` and `seed`: direction s is
// sphere_direction<double>(kind, seed, s, count) mapped to the hemisphere around +z by the map of
// `density`, rounded to float; every weight is π/count (cosine: the weight of V·f in
// ∫ V·cos θ'·f dω, the cosine folded in) or 2π/count (uniform: the weight of V·f in ∫ V·f dω).
// Nested like the sphere set it maps (uniform, sobol). Throws as make_direction_set.
DirectionSet make_local_direction_set(SamplerKind kind, std::uint64_t seed, std::uint32_t count,
                                      HemisphereDensity density);

// What a local set of `density` estimates for an open receiver (nothing blocks its hemisphere),
// in its frame, exactly: the cosine density's vector ∫_H cos θ·y_i dω, i < K (z_l at m = 0,
// clamped_cosine_zonal), or the uniform density's matrix ∫_H y_i·y_j dω, 0 ≤ i ≤ j < K, packed
// row by row (K(K+1)/2 entries). H is the hemisphere around +z. Gauss–Legendre in z on [0, 1]
// (after the φ average both integrands are polynomials in z of degree ≤ 2·bands − 1) × equally
// spaced φ: exact to rounding. The local bake subtracts the set's error on it (docs/sampling.md,
// "The open part exactly"). Throws Error(invalid_argument) for K outside [1, kMaxComputeBands²].
std::vector<double> open_hemisphere_transfer(int K, HemisphereDensity density);

// Rounds a double set to float.
DirectionSet to_float(const DirectionSetD& set);

}  // namespace shprt
