// Real spherical harmonics in the paper's convention (Green 2003, "Spherical Harmonic Lighting:
// The Gritty Details"), the single convention of shprt:
//
//   y_l^m(θ,φ) = √2 K_l^m cos(mφ)  P_l^m(cos θ)    m > 0
//              = √2 K_l^m sin(−mφ) P_l^−m(cos θ)   m < 0
//              =    K_l^0          P_l^0(cos θ)     m = 0
//   K_l^m = sqrt((2l+1)(l−|m|)! / (4π (l+|m|)!)),  P_l^m with the Condon–Shortley phase (−1)^m.
//
// * Directions are unit world vectors (x, y, z); θ is measured from +Z, φ from +X toward +Y:
//   x = sinθ cosφ, y = sinθ sinφ, z = cosθ. (World space is right-handed, +Y up; the SH frame is
//   the same axes, so "the pole" of zonal functions is +Z.)
// * Flat index i = l(l+1) + m. "n bands" means l = 0..n−1, i.e. n² coefficients. A "basis size
//   K" is the first K coefficients in index order; K need not be a square, but only full bands
//   are rotation invariant.
// * The basis is orthonormal over the unit sphere: ∫ y_i y_j dω = δ_ij.
//
// The fast path evaluates normalised associated Legendre functions with the standard
// three-term recurrence in z, with the sin^m θ factor carried by Re/Im (x + iy)^m, so no
// factorial or power of sinθ is ever formed: stable to well beyond 30 bands in double and
// 20 in float. `sh_eval_reference` is the slow, obvious formula, for tests.
#pragma once

#include "shprt/core/hd.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

namespace shprt {

SHPRT_HD_INLINE constexpr int sh_index(int l, int m) { return l * (l + 1) + m; }
SHPRT_HD_INLINE constexpr int sh_count(int bands) { return bands * bands; }

// The limits, in one place. kMaxBands: the most bands the library evaluates or stores anywhere
// (the SH toolbox and tests go this far with the double path; a .shprt file may hold K up to
// sh_count(kMaxBands), transfer/transfer.hpp kMaxTransferK). kMaxComputeBands: the most bands a
// bake computes and a light is projected with (K ≤ 1024; float holds to l = 30, tests/sh),
// bake.hpp kMaxBakeCoeffs and light.hpp kMaxLightK.
inline constexpr int kMaxBands = 64;
inline constexpr int kMaxComputeBands = 32;
// Band l of flat index i.
SHPRT_HD_INLINE int sh_band(int i) {
    int l = static_cast<int>(std::sqrt(static_cast<double>(i)));
    while (l * l > i) --l;
    while ((l + 1) * (l + 1) <= i) ++l;
    return l;
}
// Fewest bands that hold K coefficients (ceil(sqrt(K))).
SHPRT_HD_INLINE int sh_bands_for(int K) {
    int n = sh_band(K > 0 ? K - 1 : 0);
    return K > 0 ? n + 1 : 0;
}

namespace detail {

// The recurrence's factors, computed where they are used (device code, one-off evaluations);
// ShBasisEvaluator tabulates the same expressions once, so both give the same bits.
template <class T>
struct ShFactors {
    // q_mm = q_{m−1,m−1} · mm(m)
    SHPRT_HD T mm(int m) const { return -std::sqrt(T(2 * m + 1) / T(2 * m)); }
    // q_{m+1,m} = (first(m) · z) · q_mm
    SHPRT_HD T first(int m) const { return std::sqrt(T(2 * m + 3)); }
    // q_l = a(l, m) · (z · q_{l−1} − b(l, m) · q_{l−2}), l ≥ m + 2
    SHPRT_HD T a(int l, int m) const {
        const T ll = T(l), mm = T(m);
        return std::sqrt((T(4) * ll * ll - T(1)) / (ll * ll - mm * mm));
    }
    SHPRT_HD T b(int l, int m) const {
        const T ll = T(l), mm = T(m);
        return std::sqrt(((ll - T(1)) * (ll - T(1)) - mm * mm) /
                         (T(4) * (ll - T(1)) * (ll - T(1)) - T(1)));
    }
};

// sh_eval_k with the recurrence's factors from `f` (ShFactors or a table of them).
template <class T, class Factors>
SHPRT_HD void sh_eval_k_with(int K, T x, T y, T z, T* out, const Factors& f) {
    if (K <= 0) return;
    const int bands = sh_bands_for(K);
    constexpr T kInv4Pi = T(0.0795774715459476678844418816862571);  // 1/(4π)
    const T sqrt2 = T(1.41421356237309504880168872420969808);
    // q_mm = K_m^m P_m^m / sin^m θ, built band by band from q_00 = sqrt(1/4π).
    T q_mm = std::sqrt(kInv4Pi);
    // c_m + i s_m = (x + iy)^m = sin^m θ · (cos mφ + i sin mφ).
    T c_m = T(1), s_m = T(0);
    for (int m = 0; m < bands; ++m) {
        if (m > 0) {
            q_mm *= f.mm(m);
            const T c = c_m * x - s_m * y;
            s_m = c_m * y + s_m * x;
            c_m = c;
        }
        const T wc = m == 0 ? T(1) : sqrt2 * c_m;
        const T ws = sqrt2 * s_m;
        // Walk l = m, m+1, ... with q_l = a_l (z q_{l−1} − b_l q_{l−2}).
        T q_prev = T(0), q = q_mm;
        for (int l = m; l < bands; ++l) {
            if (l == m + 1) {
                q_prev = q;
                q = f.first(m) * z * q;
            } else if (l > m + 1) {
                const T next = f.a(l, m) * (z * q - f.b(l, m) * q_prev);
                q_prev = q;
                q = next;
            }
            const int ip = sh_index(l, m);
            if (ip < K) out[ip] = q * wc;
            if (m > 0) {
                const int in = sh_index(l, -m);
                if (in < K) out[in] = q * ws;
            }
        }
    }
}

}  // namespace detail

// Evaluates the first K basis functions at the unit direction (x, y, z) into out[0..K).
// Precondition: x² + y² + z² = 1 (not checked), 0 ≤ K ≤ kMaxBands². Works for float and double.
template <class T>
SHPRT_HD void sh_eval_k(int K, T x, T y, T z, T* out) {
    detail::sh_eval_k_with(K, x, y, z, out, detail::ShFactors<T>{});
}

// sh_eval_k for many directions on the host: the recurrence's square roots and quotients (two
// of each per coefficient) tabulated once for K, the same bits as sh_eval_k.
template <class T>
class ShBasisEvaluator {
public:
    explicit ShBasisEvaluator(int K) : m_K(K) {
        const int bands = sh_bands_for(K);
        const detail::ShFactors<T> f;
        m_mm.resize(std::size_t(bands) + 1);
        m_first.resize(std::size_t(bands) + 1);
        m_a.resize(std::size_t(bands) * std::size_t(bands + 1) / 2 + 1);
        m_b.resize(m_a.size());
        for (int m = 0; m < bands; ++m) {
            m_mm[std::size_t(m)] = m > 0 ? f.mm(m) : T(1);
            m_first[std::size_t(m)] = f.first(m);
            for (int l = m + 2; l < bands; ++l) {
                m_a[index(l, m)] = f.a(l, m);
                m_b[index(l, m)] = f.b(l, m);
            }
        }
    }
    void operator()(T x, T y, T z, T* out) const {
        detail::sh_eval_k_with(m_K, x, y, z, out, Table{this});
    }

private:
    static std::size_t index(int l, int m) {
        return std::size_t(l) * std::size_t(l + 1) / 2 + std::size_t(m);
    }
    struct Table {
        const ShBasisEvaluator* e;
        T mm(int m) const { return e->m_mm[std::size_t(m)]; }
        T first(int m) const { return e->m_first[std::size_t(m)]; }
        T a(int l, int m) const { return e->m_a[index(l, m)]; }
        T b(int l, int m) const { return e->m_b[index(l, m)]; }
    };
    int m_K;
    std::vector<T> m_mm, m_first, m_a, m_b;
};

// Evaluates all n² = bands² basis functions at (x, y, z).
template <class T>
SHPRT_HD_INLINE void sh_eval(int bands, T x, T y, T z, T* out) {
    sh_eval_k(sh_count(bands), x, y, z, out);
}

// Evaluates the first K functions for `count` directions stored as xyz triples in `dirs`;
// row d of `out` (stride `out_stride` ≥ K) receives direction d's values. This builds the
// paper's basis table Y[S×K], evaluated once per direction and shared by every vertex.
template <class T>
void sh_eval_batch(int K, const T* dirs, long count, T* out, long out_stride) {
    for (long d = 0; d < count; ++d)
        sh_eval_k(K, dirs[3 * d], dirs[3 * d + 1], dirs[3 * d + 2], out + d * out_stride);
}

// Slow reference: y_l^m(θ, φ) from the formula above with explicit factorial ratios (lgamma) and
// the textbook recurrence for P_l^m, in long double. Valid for 0 ≤ l ≤ 80, |m| ≤ l.
double sh_eval_reference(int l, int m, double theta, double phi);

}  // namespace shprt
