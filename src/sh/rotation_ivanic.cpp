// SH rotation matrices by recurrence over bands:
//   J. Ivanic, K. Ruedenberg, "Rotation Matrices for Real Spherical Harmonics. Direct
//   Determination by Recursion", J. Phys. Chem. 100(15):6342–6347, 1996, Tables 1 and 2;
//   with the corrections of "Additions and Corrections", J. Phys. Chem. A 102(45):9099, 1998
//   (the δ factors and signs of the V term, and the P function at b = ±l).
//
// Band l is built from band 1 (the 3x3 matrix itself, rows and columns permuted to (y, z, x))
// and band l−1; every entry costs O(1), so band l costs O((2l+1)²).
#include "shprt/sh/rotation.hpp"

#include "shprt/sh/basis.hpp"

#include <cmath>
#include <cstdlib>
#include <vector>

namespace shprt {
namespace {

// Views of band blocks by (row m, column n), m, n ∈ [−l, l].
struct BandView {
    const double* data;
    int l;
    double operator()(int m, int n) const { return data[(m + l) * (2 * l + 1) + (n + l)]; }
};

// P^i_{a,b} of Table 2 (with the errata), built from band 1 (r1) and band l−1 (prev).
double p_term(int i, int a, int b, int l, const BandView& r1, const BandView& prev) {
    if (b == l) return r1(i, 1) * prev(a, l - 1) - r1(i, -1) * prev(a, -l + 1);
    if (b == -l) return r1(i, 1) * prev(a, -l + 1) + r1(i, -1) * prev(a, l - 1);
    return r1(i, 0) * prev(a, b);
}

double u_term(int m, int n, int l, const BandView& r1, const BandView& prev) {
    return p_term(0, m, n, l, r1, prev);
}

double v_term(int m, int n, int l, const BandView& r1, const BandView& prev) {
    if (m == 0) return p_term(1, 1, n, l, r1, prev) + p_term(-1, -1, n, l, r1, prev);
    if (m > 0) {
        const double d = m == 1 ? 1.0 : 0.0;
        double v = p_term(1, m - 1, n, l, r1, prev) * std::sqrt(1.0 + d);
        if (m != 1) v -= p_term(-1, -m + 1, n, l, r1, prev);
        return v;
    }
    const double d = m == -1 ? 1.0 : 0.0;
    double v = p_term(-1, -m - 1, n, l, r1, prev) * std::sqrt(1.0 + d);
    if (m != -1) v += p_term(1, m + 1, n, l, r1, prev);
    return v;
}

double w_term(int m, int n, int l, const BandView& r1, const BandView& prev) {
    // Only called with 0 < |m| < l − 1 (w vanishes otherwise).
    if (m > 0) return p_term(1, m + 1, n, l, r1, prev) + p_term(-1, -m - 1, n, l, r1, prev);
    return p_term(1, m - 1, n, l, r1, prev) - p_term(-1, -m + 1, n, l, r1, prev);
}

}  // namespace

void ShRotation::build_ivanic(const Mat3d& R) {
    block_mut(0)[0] = 1.0;
    if (m_bands == 1) return;
    // Band 1 in Ivanic's real basis, whose band-1 functions are proportional to (y, z, x): for
    // g(d) = f(R⁻¹d) = f(Rᵀd), the function a·d becomes (R a)·d, so D¹[m'][m] = R[p(m')][p(m)].
    const int perm[3] = {1, 2, 0};  // m = −1, 0, 1 → y, z, x
    double* b1 = block_mut(1);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) b1[i * 3 + j] = R.m[perm[i]][perm[j]];
    const BandView r1{b1, 1};

    std::vector<double> inv_den(2 * m_bands + 1), su(2 * m_bands + 1), sv(2 * m_bands + 1),
        sw(2 * m_bands + 1);
    for (int l = 2; l < m_bands; ++l) {
        const BandView prev{block_mut(l - 1), l - 1};
        double* out = block_mut(l);
        const int size = 2 * l + 1;
        // u, v, w of Table 1 factor into a part depending on m and 1/sqrt(denominator(n)), so
        // no square root is taken per entry.
        for (int k = -l; k <= l; ++k) {
            const int ak = std::abs(k);
            const double d = k == 0 ? 1.0 : 0.0;
            inv_den[k + l] = 1.0 / std::sqrt(ak == l ? 2.0 * l * (2.0 * l - 1.0)
                                                     : static_cast<double>((l + k) * (l - k)));
            su[k + l] = std::sqrt(static_cast<double>((l + k) * (l - k)));
            sv[k + l] = 0.5 * std::sqrt((1.0 + d) * (l + ak - 1.0) * (l + ak)) * (1.0 - 2.0 * d);
            sw[k + l] = -0.5 * std::sqrt((l - ak - 1.0) * (l - ak)) * (1.0 - d);
        }
        for (int m = -l; m <= l; ++m) {
            for (int n = -l; n <= l; ++n) {
                const double u = su[m + l] * inv_den[n + l];
                const double v = sv[m + l] * inv_den[n + l];
                const double w = sw[m + l] * inv_den[n + l];
                double value = 0;
                if (u != 0) value += u * u_term(m, n, l, r1, prev);
                if (v != 0) value += v * v_term(m, n, l, r1, prev);
                if (w != 0) value += w * w_term(m, n, l, r1, prev);
                out[(m + l) * size + (n + l)] = value;
            }
        }
    }

    // Ivanic's real SH carry no Condon–Shortley phase; ours do: y_{l,m} = (−1)^m y^I_{l,m}. The
    // blocks in our basis are S·D·S with S = diag((−1)^m). (The recurrence above is linear in
    // products whose m indices add up, so running it in either basis gives the same result; we
    // run it in Ivanic's to follow the paper literally.)
    for (int l = 1; l < m_bands; ++l) {
        double* out = block_mut(l);
        const int size = 2 * l + 1;
        for (int m = -l; m <= l; ++m)
            for (int n = -l; n <= l; ++n)
                if ((m + n) & 1) out[(m + l) * size + (n + l)] = -out[(m + l) * size + (n + l)];
    }
}

}  // namespace shprt
