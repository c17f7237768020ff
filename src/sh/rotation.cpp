// SH rotation: storage, construction dispatch, application, and the closed-form z-rotation.
// The two constructions live in rotation_ivanic.cpp (Ivanic & Ruedenberg 1996/1998) and
// rotation_paper.cpp (the paper's R^z·R^x(±π/2) factorisation).
#include "shprt/sh/rotation.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/names.hpp"
#include "shprt/sh/basis.hpp"

#include <cmath>
#include <cstdint>
#include <functional>

namespace shprt {

namespace {
constexpr Named<RotationMethod> kRotationMethodNames[] = {{RotationMethod::paper, "paper"},
                                                          {RotationMethod::ivanic, "ivanic"}};
}  // namespace

const char* to_string(RotationMethod method) { return name_of(kRotationMethodNames, method); }
RotationMethod parse_rotation_method(const std::string& name) {
    return parse_named(kRotationMethodNames, name, "SH rotation method");
}

namespace {

void check_bands(int bands) {
    SHPRT_CHECK(bands >= 1 && bands <= kMaxBands, invalid_argument,
                "SH rotation: bands must be in [1, {}], got {}", kMaxBands, bands);
}

// in[0..K) and out[0..K) must not overlap (the block product reads all of a band's inputs).
template <class T>
void check_apply_args(const T* in, const T* out, int K, int max_k, const char* what) {
    SHPRT_CHECK(K >= 0 && K <= max_k, invalid_argument, "{}: basis size K={} outside [0, {}]", what,
                K, max_k);
    if (K == 0) return;
    SHPRT_CHECK(in != nullptr && out != nullptr, invalid_argument, "{}: null coefficient pointer",
                what);
    const auto a = reinterpret_cast<std::uintptr_t>(in);
    const auto b = reinterpret_cast<std::uintptr_t>(out);
    const std::uintptr_t bytes = sizeof(T) * static_cast<std::uintptr_t>(K);
    SHPRT_CHECK(a + bytes <= b || b + bytes <= a, invalid_argument,
                "{}: input and output coefficient arrays overlap (in-place is not supported)",
                what);
}

// Accumulates in the block type (double blocks for double vectors, float for float), four rows
// at a time for instruction-level parallelism.
template <class T>
void apply_blocks(const T* blocks, const long* offsets, const T* in, T* out, int K) {
    if (K <= 0) return;
    const int last = sh_bands_for(K) - 1;
    for (int l = 0; l <= last; ++l) {
        const int n = 2 * l + 1, base = l * l;
        const int nb = (K - base < n) ? K - base : n;  // partial last band: missing inputs = 0
        const T* blk = blocks + offsets[l];
        const T* x = in + base;
        int r = 0;
        for (; r + 4 <= nb; r += 4) {
            const T* r0 = blk + static_cast<long>(r) * n;
            const T *r1 = r0 + n, *r2 = r1 + n, *r3 = r2 + n;
            T a0 = 0, a1 = 0, a2 = 0, a3 = 0;
            for (int c = 0; c < nb; ++c) {
                a0 += r0[c] * x[c];
                a1 += r1[c] * x[c];
                a2 += r2[c] * x[c];
                a3 += r3[c] * x[c];
            }
            out[base + r] = a0;
            out[base + r + 1] = a1;
            out[base + r + 2] = a2;
            out[base + r + 3] = a3;
        }
        for (; r < nb; ++r) {
            const T* row = blk + static_cast<long>(r) * n;
            T acc = 0;
            for (int c = 0; c < nb; ++c) acc += row[c] * x[c];
            out[base + r] = acc;
        }
    }
}

}  // namespace

void ShRotation::init_storage(int bands) {
    m_bands = bands;
    m_offsets.assign(bands + 1, 0);
    for (int l = 0; l < bands; ++l) m_offsets[l + 1] = m_offsets[l] + (2L * l + 1) * (2L * l + 1);
    m_blocks.assign(m_offsets[bands], 0.0);
}

void ShRotation::finish() {
    m_blocks_f.resize(m_blocks.size());
    for (std::size_t i = 0; i < m_blocks.size(); ++i)
        m_blocks_f[i] = static_cast<float>(m_blocks[i]);
}

ShRotation ShRotation::from_matrix(const Mat3d& R, int bands, RotationMethod method) {
    check_bands(bands);
    SHPRT_CHECK(is_rotation(R, 1e-6), invalid_argument,
                "SH rotation: the 3x3 matrix [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]] is not a "
                "rotation (orthonormal with determinant +1)",
                R.m[0][0], R.m[0][1], R.m[0][2], R.m[1][0], R.m[1][1], R.m[1][2], R.m[2][0],
                R.m[2][1], R.m[2][2]);
    ShRotation rot;
    rot.init_storage(bands);
    if (method == RotationMethod::ivanic) {
        rot.build_ivanic(R);
    } else {
        const EulerZyz e = zyz_from_matrix(R);
        rot.build_paper(e.alpha, e.beta, e.gamma);
    }
    rot.finish();
    return rot;
}

ShRotation ShRotation::from_quat(const Quat& q, int bands, RotationMethod method) {
    return from_matrix(matrix_from_quat(q), bands, method);
}

ShRotation ShRotation::from_zyz(double alpha, double beta, double gamma, int bands,
                                RotationMethod method) {
    check_bands(bands);
    SHPRT_CHECK(std::isfinite(alpha) && std::isfinite(beta) && std::isfinite(gamma),
                invalid_argument, "SH rotation: Euler angles ({}, {}, {}) are not finite", alpha,
                beta, gamma);
    if (method == RotationMethod::ivanic)
        return from_matrix(matrix_from_zyz(alpha, beta, gamma), bands, method);
    ShRotation rot;
    rot.init_storage(bands);
    rot.build_paper(alpha, beta, gamma);
    rot.finish();
    return rot;
}

const double* ShRotation::block(int l) const {
    SHPRT_CHECK(l >= 0 && l < m_bands, invalid_argument,
                "ShRotation::block: band {} outside [0, {})", l, m_bands);
    return m_blocks.data() + m_offsets[l];
}

void ShRotation::apply(const double* in, double* out, int K) const {
    check_apply_args(in, out, K, sh_count(m_bands), "ShRotation::apply");
    apply_blocks(m_blocks.data(), m_offsets.data(), in, out, K);
}

void ShRotation::apply(const float* in, float* out, int K) const {
    check_apply_args(in, out, K, sh_count(m_bands), "ShRotation::apply");
    apply_blocks(m_blocks_f.data(), m_offsets.data(), in, out, K);
}

std::vector<double> ShRotation::dense(int K) const {
    SHPRT_CHECK(K >= 0 && K <= sh_count(m_bands), invalid_argument,
                "ShRotation::dense: basis size K={} outside [0, {}]", K, sh_count(m_bands));
    std::vector<double> d(static_cast<std::size_t>(K) * K, 0.0);
    for (int i = 0; i < K; ++i) {
        const int l = sh_band(i), n = 2 * l + 1, r = i - l * l;
        for (int c = 0; c < n && l * l + c < K; ++c)
            d[static_cast<std::size_t>(i) * K + l * l + c] = m_blocks[m_offsets[l] + r * n + c];
    }
    return d;
}

void rotate_z(double alpha, const double* in, double* out, int K) {
    SHPRT_CHECK(K >= 0, invalid_argument, "rotate_z: negative basis size K={}", K);
    if (K == 0) return;
    const int bands = sh_bands_for(K);
    for (int l = 0; l < bands; ++l) {
        const int c0 = sh_index(l, 0);
        if (c0 < K) out[c0] = in[c0];
    }
    for (int m = 1; m < bands; ++m) {
        const double c = std::cos(m * alpha), s = std::sin(m * alpha);
        for (int l = m; l < bands; ++l) {
            const int ip = sh_index(l, m), in_ = sh_index(l, -m);
            if (in_ >= K) break;                     // later bands start even further out
            const double a = ip < K ? in[ip] : 0.0;  // partial band: missing = 0
            const double b = in[in_];
            if (ip < K) out[ip] = c * a - s * b;
            out[in_] = s * a + c * b;
        }
    }
}

}  // namespace shprt
