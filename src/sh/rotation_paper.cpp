// SH rotation by the paper's factorisation (Parubets & Berestneva 2011, "SH rotation"; the
// standard form is in R. Green, "Spherical Harmonic Lighting: The Gritty Details", 2003, and
// Kautz, Sloan & Snyder, "Fast, Arbitrary BRDF Shading for Low-Frequency Lighting Using
// Spherical Harmonics", EGWR 2002):
//
//   R = Rz(γ)·Ry(β)·Rz(α) = Rz(γ)·Rx(−π/2)·Rz(β)·Rx(π/2)·Rz(α)          (note 1)
//   D(R) = Z(γ)·X(π/2)ᵀ·Z(β)·X(π/2)·Z(α)                                  (note 2)
//
// Z(·) is closed form (cos mα / sin mα pairs, rotation.cpp). X(π/2) = D(Rx(π/2)) is built here
// for EVERY band requested — never a hard-coded table that stops at some band — by exact
// quadrature of its definition, independently of the Ivanic recurrences, so the comparison of
// the two methods in the tests means something.
#include "sh/quadrature.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <vector>

namespace shprt {
namespace {

// D^l(Rx(π/2))[m'][m] = ∫ y_{l,m'}(d) · y_{l,m}(Rx(−π/2) d) dω for l in [first, last). The
// integrand is a spherical polynomial of degree 2l ≤ 2(last−1): Gauss–Legendre with `last`
// nodes in cos θ (exact to degree 2·last − 1) times 2·last equally spaced φ (exact for
// frequencies |k| < 2·last) integrates it exactly. One grid serves every band of the range, so
// the basis is evaluated O(last⁴) times in all rather than O(last⁵).
//
// Half of each block is zero by symmetry (note 3): Rx commutes with the mirror x → −x, which
// multiplies y_{l,m} by s_m = (−1)^m (m ≥ 0) or −(−1)^m (m < 0), so D[m'][m] = 0 unless
// s_m' = s_m. Only the two same-sign sub-blocks are accumulated; the zeros are exact.
void compute_x90_blocks(int first, int last, std::vector<double>* blocks) {
    const int K = sh_count(last), n_theta = last, n_phi = 2 * last;
    std::vector<double> gx, gw;
    detail::gauss_legendre(n_theta, gx, gw);
    const auto mirror_sign = [](int m) { return ((m < 0 ? -m : m) % 2 == 0) == (m >= 0); };
    // classes[l][k]: band offsets (m + l) of the k-th member of class 0 (s = +1) then class 1.
    std::vector<std::vector<int>> members(last);
    std::vector<int> class0(last, 0);
    std::vector<std::vector<double>> acc(last);  // class-0 block then class-1 block
    for (int l = first; l < last; ++l) {
        for (int m = -l; m <= l; ++m)
            if (mirror_sign(m)) members[l].push_back(m + l);
        class0[l] = static_cast<int>(members[l].size());
        for (int m = -l; m <= l; ++m)
            if (!mirror_sign(m)) members[l].push_back(m + l);
        const std::size_t n0 = class0[l], n1 = 2 * l + 1 - n0;
        acc[l].assign(n0 * n0 + n1 * n1, 0.0);
    }
    std::vector<double> ya(K), yb(K), pa(2 * last), pb(2 * last);
    for (int i = 0; i < n_theta; ++i) {
        const double z = gx[i], s = std::sqrt((1.0 - z) * (1.0 + z));
        for (int j = 0; j < n_phi; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / n_phi;
            const double x = s * std::cos(phi), y = s * std::sin(phi);
            const double weight = gw[i] * 2.0 * kPi / n_phi;
            sh_eval_k(K, x, y, z, ya.data());
            sh_eval_k(K, x, z, -y, yb.data());  // Rx(−π/2)·(x, y, z) = (x, z, −y)
            for (int l = first; l < last; ++l) {
                const int n = 2 * l + 1, base = l * l, n0 = class0[l];
                for (int k = 0; k < n; ++k) {
                    pa[k] = weight * ya[base + members[l][k]];
                    pb[k] = yb[base + members[l][k]];
                }
                double* a0 = acc[l].data();
                for (int r = 0; r < n0; ++r, a0 += n0)
                    for (int c = 0; c < n0; ++c) a0[c] += pa[r] * pb[c];
                const int n1 = n - n0;
                double* a1 = acc[l].data() + static_cast<std::size_t>(n0) * n0;
                for (int r = 0; r < n1; ++r, a1 += n1)
                    for (int c = 0; c < n1; ++c) a1[c] += pa[n0 + r] * pb[n0 + c];
            }
        }
    }
    for (int l = first; l < last; ++l) {
        const int n = 2 * l + 1, n0 = class0[l], n1 = n - n0;
        blocks[l].assign(static_cast<std::size_t>(n) * n, 0.0);
        const std::vector<int>& mem = members[l];
        for (int r = 0; r < n0; ++r)
            for (int c = 0; c < n0; ++c) blocks[l][mem[r] * n + mem[c]] = acc[l][r * n0 + c];
        const double* a1 = acc[l].data() + static_cast<std::size_t>(n0) * n0;
        for (int r = 0; r < n1; ++r)
            for (int c = 0; c < n1; ++c) blocks[l][mem[n0 + r] * n + mem[n0 + c]] = a1[r * n1 + c];
    }
}

struct X90Cache {
    std::mutex mutex;
    std::array<std::vector<double>, kMaxBands> blocks;
    int ready = 0;  // blocks[0..ready) are final and never written again
};

X90Cache& x90_cache() {
    static X90Cache cache;
    return cache;
}

// Makes bands [0, bands) available; the returned blocks are immutable afterwards, so readers
// need no lock once this has returned.
const std::array<std::vector<double>, kMaxBands>& ensure_x90(int bands) {
    X90Cache& c = x90_cache();
    std::lock_guard<std::mutex> lock(c.mutex);
    if (c.ready < bands) {
        compute_x90_blocks(c.ready, bands, c.blocks.data());
        c.ready = bands;
    }
    return c.blocks;
}

// Z(α) in the block layout (rows/cols m = −l..l): for m > 0
//   Z[m][m] = Z[−m][−m] = cos mα,  Z[m][−m] = −sin mα,  Z[−m][m] = sin mα,  Z[0][0] = 1.
struct ZAngles {
    std::array<double, kMaxBands> c, s;
    explicit ZAngles(double a, int bands) {
        for (int m = 0; m < bands; ++m) {
            c[m] = std::cos(m * a);
            s[m] = std::sin(m * a);
        }
    }
};

// v ← Z·v for one band vector v (length 2l+1).
void z_times_vector(const ZAngles& z, int l, double* v) {
    for (int m = 1; m <= l; ++m) {
        const double p = v[l + m], q = v[l - m];
        v[l + m] = z.c[m] * p - z.s[m] * q;
        v[l - m] = z.s[m] * p + z.c[m] * q;
    }
}

// A ← Z·A (mixes rows m and −m) for an n×n row-major band block.
void z_times_rows(const ZAngles& z, int l, double* a) {
    const int n = 2 * l + 1;
    for (int m = 1; m <= l; ++m) {
        double* rp = a + static_cast<std::size_t>(l + m) * n;
        double* rq = a + static_cast<std::size_t>(l - m) * n;
        for (int k = 0; k < n; ++k) {
            const double p = rp[k], q = rq[k];
            rp[k] = z.c[m] * p - z.s[m] * q;
            rq[k] = z.s[m] * p + z.c[m] * q;
        }
    }
}

// A ← A·Z (mixes columns m and −m).
void z_times_cols(const ZAngles& z, int l, double* a) {
    const int n = 2 * l + 1;
    for (int r = 0; r < n; ++r) {
        double* row = a + static_cast<std::size_t>(r) * n;
        for (int m = 1; m <= l; ++m) {
            const double p = row[l + m], q = row[l - m];
            // (A·Z)[r][m] = A[r][m] Z[m][m] + A[r][−m] Z[−m][m] = p cos + q sin
            row[l + m] = p * z.c[m] + q * z.s[m];
            row[l - m] = -p * z.s[m] + q * z.c[m];
        }
    }
}

}  // namespace

const double* rotation_x90_block(int l) {
    SHPRT_CHECK(l >= 0 && l < kMaxBands, invalid_argument,
                "rotation_x90_block: band {} outside [0, {})", l, kMaxBands);
    return ensure_x90(l + 1)[l].data();
}

void ShRotation::build_paper(double alpha, double beta, double gamma) {
    const auto& x90 = ensure_x90(m_bands);
    const ZAngles za(alpha, m_bands), zb(beta, m_bands), zg(gamma, m_bands);
    std::vector<double> t;
    for (int l = 0; l < m_bands; ++l) {
        const int n = 2 * l + 1;
        const double* x = x90[l].data();
        // t = Z(β)·X·Z(α): copy X, mix its columns, then its rows.
        t.assign(x, x + static_cast<std::size_t>(n) * n);
        z_times_cols(za, l, t.data());
        z_times_rows(zb, l, t.data());
        // out = Xᵀ·t, then Z(γ)·out.
        double* out = block_mut(l);
        for (int r = 0; r < n; ++r) {
            double* orow = out + static_cast<std::size_t>(r) * n;
            for (int c = 0; c < n; ++c) orow[c] = 0.0;
            for (int k = 0; k < n; ++k) {
                const double xkr = x[static_cast<std::size_t>(k) * n + r];  // Xᵀ[r][k]
                const double* trow = t.data() + static_cast<std::size_t>(k) * n;
                for (int c = 0; c < n; ++c) orow[c] += xkr * trow[c];
            }
        }
        z_times_rows(zg, l, out);
    }
}

void rotate_zyz_paper(double alpha, double beta, double gamma, const double* in, double* out,
                      int K) {
    SHPRT_CHECK(K >= 0 && K <= sh_count(kMaxBands), invalid_argument,
                "rotate_zyz_paper: basis size K={} outside [0, {}]", K, sh_count(kMaxBands));
    if (K == 0) return;
    SHPRT_CHECK(in != nullptr && out != nullptr, invalid_argument,
                "rotate_zyz_paper: null coefficient pointer");
    const auto a = reinterpret_cast<std::uintptr_t>(in), b = reinterpret_cast<std::uintptr_t>(out);
    const std::uintptr_t bytes = sizeof(double) * static_cast<std::uintptr_t>(K);
    SHPRT_CHECK(a + bytes <= b || b + bytes <= a, invalid_argument,
                "rotate_zyz_paper: input and output coefficient arrays overlap");
    const int bands = sh_bands_for(K);
    const auto& x90 = ensure_x90(bands);
    const ZAngles za(alpha, bands), zb(beta, bands), zg(gamma, bands);
    std::array<double, 2 * kMaxBands> u{}, v{};
    for (int l = 0; l < bands; ++l) {
        const int n = 2 * l + 1, base = l * l;
        const int nb = (K - base < n) ? K - base : n;  // partial last band: missing inputs = 0
        for (int i = 0; i < n; ++i) u[i] = i < nb ? in[base + i] : 0.0;
        const double* x = x90[l].data();
        z_times_vector(za, l, u.data());
        for (int r = 0; r < n; ++r) {  // v = X·u
            const double* row = x + static_cast<std::size_t>(r) * n;
            double acc = 0;
            for (int c = 0; c < n; ++c) acc += row[c] * u[c];
            v[r] = acc;
        }
        z_times_vector(zb, l, v.data());
        for (int c = 0; c < n; ++c) u[c] = 0.0;  // u = Xᵀ·v
        for (int k = 0; k < n; ++k) {
            const double* row = x + static_cast<std::size_t>(k) * n;
            const double vk = v[k];
            for (int c = 0; c < n; ++c) u[c] += row[c] * vk;
        }
        z_times_vector(zg, l, u.data());
        for (int i = 0; i < nb; ++i) out[base + i] = u[i];
    }
}

}  // namespace shprt

// Note 1: Rx(π/2) takes +Y to +Z, so Rx(−π/2)·Rz(β)·Rx(π/2) is a rotation by β about
// Rx(−π/2)·ẑ = +Y, i.e. Ry(β).
// Note 2: D is a homomorphism for the convention g(d) = f(R⁻¹d), and D(Rx(−π/2)) =
// D(Rx(π/2))⁻¹ = D(Rx(π/2))ᵀ because the blocks are orthogonal.
