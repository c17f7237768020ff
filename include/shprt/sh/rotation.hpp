// Rotation of real SH coefficient vectors (the paper's convention, see sh/basis.hpp).
//
// Convention: for a 3x3 rotation R, the SH rotation maps the coefficients c of a function f to
// the coefficients c' of the rotated function
//
//     g(d) = f(R⁻¹ d),    i.e. Σ c'_i y_i(d) = Σ c_i y_i(R⁻¹ d),
//
// so a lobe of f pointing along v points along R v in g. Rotation is block diagonal: band l
// mixes only its own 2l+1 coefficients, through an orthogonal (2l+1)×(2l+1) block D^l(R) with
// c'_{l,m'} = Σ_m D^l(R)[m'][m] · c_{l,m}. D is a homomorphism: D(R2·R1) = D(R2)·D(R1), and
// D(R⁻¹) = D(R)ᵀ.
//
// Two independent constructions; their matrices agree to ~1e-14 in double at 20–32 bands
// (~1e-11 at 64; the tests demand 1e-10 at 20 bands):
// * RotationMethod::ivanic: Ivanic & Ruedenberg 1996 recurrences (with the 1998 errata), band
//   l built from band 1 (the 3x3 matrix itself, permuted) and band l−1: O(1) per entry, so
//   O((2l+1)²) per band. The default: the cheapest way to build the matrices.
// * RotationMethod::paper: the paper's factorisation R = Rz(γ)·Rx(−π/2)·Rz(β)·Rx(π/2)·Rz(α)
//   (ZYZ Euler angles, since Ry(β) = Rx(−π/2)·Rz(β)·Rx(π/2)): z-rotations in closed form and
//   D(Rx(π/2)) blocks for every band, computed once by exact quadrature and cached (see
//   rotation_x90_block). Forming the matrices costs one dense product, O((2l+1)³) per band;
//   rotate_zyz_paper applies the factorisation to a vector in O((2l+1)²) without any matrix.
//
// A "basis size K" that is not a full square (the paper's 32, 48, 128) leaves band L = ⌈√K⌉−1
// partly filled. apply() then treats the missing coefficients of band L as zero and returns the
// first K coefficients of the rotated vector: the orthogonal projection of the rotated,
// zero-padded function onto the first K basis functions. This is not rotation invariant
// (composition and inverse hold only for full bands) — tools say so.
#pragma once

#include "shprt/core/rotation3.hpp"
#include "shprt/core/vec.hpp"

#include <string>
#include <vector>

namespace shprt {

enum class RotationMethod { paper, ivanic };

const char* to_string(RotationMethod method);
// "paper" or "ivanic"; throws Error(invalid_argument) naming the value otherwise.
RotationMethod parse_rotation_method(const std::string& name);

class ShRotation {
public:
    // An empty rotation (bands() == 0, apply() accepts only K = 0); assign one from a factory.
    ShRotation() = default;

    // The SH rotation for the 3x3 rotation R, for bands l = 0..bands−1: maps coefficients of f to
    // those of g(d) = f(R⁻¹ d). Throws Error(invalid_argument) when bands is outside
    // [1, kMaxBands] or R is not a rotation (orthonormal, det +1, to 1e-6).
    static ShRotation from_matrix(const Mat3d& R, int bands,
                                  RotationMethod method = RotationMethod::ivanic);
    // From a quaternion (normalised first; zero throws).
    static ShRotation from_quat(const Quat& q, int bands,
                                RotationMethod method = RotationMethod::ivanic);
    // From ZYZ Euler angles in radians: R = Rz(gamma)·Ry(beta)·Rz(alpha). With
    // RotationMethod::paper the angles are used as given (no extraction from a matrix).
    static ShRotation from_zyz(double alpha, double beta, double gamma, int bands,
                               RotationMethod method = RotationMethod::ivanic);

    int bands() const { return m_bands; }
    // Block of band l (0 ≤ l < bands): (2l+1)×(2l+1), row-major, rows and columns indexed by
    // m = −l..l (row m' + l, column m + l), so c'[l(l+1)+m'] = Σ_m block[(m'+l)(2l+1) + m+l] c[..].
    const double* block(int l) const;

    // out[0..K) = rotation of in[0..K), O(Σ(2l+1)²). Preconditions (checked,
    // Error(invalid_argument)): 0 ≤ K ≤ bands², in and out do not overlap. A partial last band:
    // see the file comment. The float overload uses float copies of the blocks and accumulates
    // in float (relative error ~1e-6).
    void apply(const double* in, double* out, int K) const;
    void apply(const float* in, float* out, int K) const;

    // The dense K×K matrix (row-major) of apply() for basis size K, for tests and exports.
    std::vector<double> dense(int K) const;

private:
    void init_storage(int bands);
    void finish();  // fills the float copy

    void build_ivanic(const Mat3d& R);                          // rotation_ivanic.cpp
    void build_paper(double alpha, double beta, double gamma);  // rotation_paper.cpp
    double* block_mut(int l) { return m_blocks.data() + m_offsets[l]; }

    int m_bands = 0;
    std::vector<double> m_blocks;  // all bands' blocks, band l at m_offsets[l]
    std::vector<float> m_blocks_f;
    std::vector<long> m_offsets;
};

// The paper's factorisation applied directly to a coefficient vector, without forming any
// matrix: out = Z(γ)·X(−π/2)·Z(β)·X(π/2)·Z(α)·in band by band, O(Σ(2l+1)²) — how a light
// vector is rotated. Same partial-band rule and preconditions as ShRotation::apply, with
// K ≤ kMaxBands². Angles in radians, R = Rz(gamma)·Ry(beta)·Rz(alpha).
void rotate_zyz_paper(double alpha, double beta, double gamma, const double* in, double* out,
                      int K);

// Rotation about +Z by `alpha` radians in closed form (only m and −m mix):
// c'_{l,m} = cos(mα) c_{l,m} − sin(mα) c_{l,−m},  c'_{l,−m} = sin(mα) c_{l,m} + cos(mα) c_{l,−m}
// for m > 0. In-place allowed (in == out). Any K ≥ 0.
void rotate_z(double alpha, const double* in, double* out, int K);

// D^l(Rx(π/2)) for band l (0 ≤ l < kMaxBands), (2l+1)², row-major as ShRotation::block. Built on
// first use for all bands up to l by exact quadrature (Gauss–Legendre in cos θ × uniform φ) of
// ∫ y_{l,m'}(d) y_{l,m}(Rx(−π/2) d) dω, then cached for the life of the process (thread-safe).
// One grid serves all bands built together; from scratch this takes ~1 ms for 16 bands, ~0.07 s
// for 32 and ~2 s for 64 (measured on a loaded 2-core machine).
const double* rotation_x90_block(int l);

}  // namespace shprt
