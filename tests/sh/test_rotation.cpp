// SH rotation: 3D rotation helpers; the convention g(d) = f(R⁻¹d) checked by evaluation; a slow
// reference (exact quadrature of the rotated basis) against both constructions; composition,
// inverse, per-band norms; the paper's factorisation equals Ivanic to 1e-10 at 20 bands; partial
// last bands; bad input.
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"

#include "common/gauss_legendre.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>
#include <vector>

namespace shprt {
namespace {

using test_support::gauss_legendre;

constexpr double kTightTol = 1e-12;   // identities that hold to rounding in double
constexpr double kMethodTol = 1e-10;  // paper vs Ivanic (the bound)
constexpr double kMatrixTol = 1e-14;  // 3x3 matrix identities

Mat3d random_rotation_matrix(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    return matrix_from_quat({n(rng), n(rng), n(rng), n(rng)});
}

Vec3d random_dir(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    return normalize(Vec3d{n(rng), n(rng), n(rng)});
}

std::vector<double> random_coeffs(int K, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> c(K);
    for (double& v : c) v = u(rng);
    return c;
}

double eval(const std::vector<double>& c, Vec3d d) {
    std::vector<double> y(c.size());
    sh_eval_k(static_cast<int>(c.size()), d.x, d.y, d.z, y.data());
    double s = 0;
    for (std::size_t i = 0; i < c.size(); ++i) s += c[i] * y[i];
    return s;
}

double max_abs_diff(const Mat3d& a, const Mat3d& b) {
    double e = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) e = std::max(e, std::abs(a.m[i][j] - b.m[i][j]));
    return e;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
    double e = 0;
    for (std::size_t i = 0; i < a.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]));
    return e;
}

// Slow reference: D^l(R)[m'][m] = ∫ y_{l,m'}(d) y_{l,m}(R⁻¹d) dω by exact quadrature.
std::vector<double> reference_block(const Mat3d& R, int l) {
    const int n = 2 * l + 1, K = sh_count(l + 1);
    std::vector<double> gx, gw, ya(K), yb(K), block(n * n, 0.0);
    gauss_legendre(l + 2, gx, gw);
    const int n_phi = 2 * l + 3;
    const Mat3d Rinv = transpose(R);
    for (int i = 0; i < l + 2; ++i)
        for (int j = 0; j < n_phi; ++j) {
            const double st = std::sqrt(1 - gx[i] * gx[i]), phi = 2 * kPi * j / n_phi;
            const Vec3d d{st * std::cos(phi), st * std::sin(phi), gx[i]};
            const Vec3d e = Rinv * d;
            sh_eval_k(K, d.x, d.y, d.z, ya.data());
            sh_eval_k(K, e.x, e.y, e.z, yb.data());
            for (int r = 0; r < n; ++r)
                for (int c = 0; c < n; ++c)
                    block[r * n + c] += gw[i] * 2 * kPi / n_phi * ya[l * l + r] * yb[l * l + c];
        }
    return block;
}

std::vector<double> block_vec(const ShRotation& rot, int l) {
    const double* b = rot.block(l);
    return std::vector<double>(b, b + (2 * l + 1) * (2 * l + 1));
}

// ---------------------------------------------------------------------------------------------
// 3D rotations

TEST(Rotation3, AxisRotationsAreRightHanded) {
    const Vec3d x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const auto near = [](Vec3d a, Vec3d b) { return length(a - b) < kMatrixTol; };
    EXPECT_TRUE(near(rotation_z(kPi / 2) * x, y));
    EXPECT_TRUE(near(rotation_x(kPi / 2) * y, z));
    EXPECT_TRUE(near(rotation_y(kPi / 2) * z, x));
}

TEST(Rotation3, EulerYawPitchRollAndQuaternionConventions) {
    EXPECT_LT(max_abs_diff(matrix_from_zyz(0.3, 1.1, -2.0),
                           rotation_z(-2.0) * rotation_y(1.1) * rotation_z(0.3)),
              kMatrixTol);
    EXPECT_LT(max_abs_diff(matrix_from_yaw_pitch_roll_deg(30, -20, 75),
                           rotation_y(kPi / 6) * rotation_x(-kPi / 9) * rotation_z(75 * kPi / 180)),
              kMatrixTol);
    // Yaw 90° turns the forward axis −Z toward −X (+Y up, right-handed).
    const Vec3d f = matrix_from_yaw_pitch_roll_deg(90, 0, 0) * Vec3d{0, 0, -1};
    EXPECT_LT(length(f - Vec3d{-1, 0, 0}), kMatrixTol);
    // Quaternions: axis-angle about each axis equals the axis rotation; q and −q agree; scale
    // does not matter.
    EXPECT_LT(max_abs_diff(matrix_from_quat(quat_from_axis_angle({0, 0, 2}, 0.7)), rotation_z(0.7)),
              kMatrixTol);
    EXPECT_LT(
        max_abs_diff(matrix_from_quat(quat_from_axis_angle({1, 0, 0}, -1.3)), rotation_x(-1.3)),
        kMatrixTol);
    const Quat q = quat_from_axis_angle({0, 1, 0}, 2.2);
    EXPECT_LT(
        max_abs_diff(matrix_from_quat({-3 * q.w, -3 * q.x, -3 * q.y, -3 * q.z}), rotation_y(2.2)),
        kMatrixTol);
    EXPECT_THROW(matrix_from_quat({0, 0, 0, 0}), Error);
    EXPECT_THROW(matrix_from_quat({NAN, 0, 0, 1}), Error);
    EXPECT_THROW(quat_from_axis_angle({0, 0, 0}, 1.0), Error);
}

TEST(Rotation3, ZyzExtractionRoundTripsIncludingPoles) {
    std::mt19937_64 rng(7);
    std::vector<Mat3d> cases;
    for (int i = 0; i < 200; ++i) cases.push_back(random_rotation_matrix(rng));
    for (double beta : {0.0, 1e-12, 1e-7, kPi - 1e-7, kPi - 1e-12, kPi})
        cases.push_back(matrix_from_zyz(0.4, beta, -1.9));
    cases.push_back(Mat3d::identity());
    for (const Mat3d& R : cases) {
        const EulerZyz e = zyz_from_matrix(R);
        EXPECT_GE(e.beta, 0.0);
        EXPECT_LE(e.beta, kPi);
        EXPECT_LT(max_abs_diff(matrix_from_zyz(e.alpha, e.beta, e.gamma), R), 1e-13);
    }
    // Non-degenerate angles come back exactly as given.
    const EulerZyz e = zyz_from_matrix(matrix_from_zyz(0.5, 1.0, -2.5));
    EXPECT_NEAR(e.alpha, 0.5, 1e-13);
    EXPECT_NEAR(e.beta, 1.0, 1e-13);
    EXPECT_NEAR(e.gamma, -2.5, 1e-13);
}

TEST(Rotation3, IsRotationRejectsScalesAndReflections) {
    std::mt19937_64 rng(3);
    const Mat3d R = random_rotation_matrix(rng);
    EXPECT_TRUE(is_rotation(R));
    Mat3d scaled = R;
    for (auto& row : scaled.m)
        for (double& v : row) v *= 1.01;
    EXPECT_FALSE(is_rotation(scaled));
    Mat3d mirrored = R;
    for (double& v : mirrored.m[0]) v = -v;
    EXPECT_FALSE(is_rotation(mirrored));
    EXPECT_TRUE(is_rotation(rotation_z_to(normalize(Vec3d{1, -2, 0.5}))));
    const Vec3d d = normalize(Vec3d{1, -2, 0.5});
    EXPECT_LT(length(rotation_z_to(d) * Vec3d{0, 0, 1} - d), kMatrixTol);
    EXPECT_LT(length(rotation_z_to({0, 0, -1}) * Vec3d{0, 0, 1} - Vec3d{0, 0, -1}), kMatrixTol);
}

// ---------------------------------------------------------------------------------------------
// SH rotation

class ShRotationMethods : public ::testing::TestWithParam<RotationMethod> {};

TEST_P(ShRotationMethods, RotateThenEvaluateEqualsEvaluateAtInverseRotatedDirection) {
    std::mt19937_64 rng(11);
    const int bands = 10, K = sh_count(bands);
    for (int trial = 0; trial < 10; ++trial) {
        const Mat3d R = random_rotation_matrix(rng);
        const ShRotation rot = ShRotation::from_matrix(R, bands, GetParam());
        const std::vector<double> c = random_coeffs(K, rng);
        std::vector<double> g(K);
        rot.apply(c.data(), g.data(), K);
        for (int k = 0; k < 20; ++k) {
            const Vec3d d = random_dir(rng);
            EXPECT_NEAR(eval(g, d), eval(c, transpose(R) * d), kTightTol * 10);
        }
    }
}

TEST_P(ShRotationMethods, MatchesQuadratureReference) {
    std::mt19937_64 rng(12);
    const int bands = 7;
    for (int trial = 0; trial < 3; ++trial) {
        const Mat3d R = random_rotation_matrix(rng);
        const ShRotation rot = ShRotation::from_matrix(R, bands, GetParam());
        for (int l = 0; l < bands; ++l)
            EXPECT_LT(max_abs_diff(block_vec(rot, l), reference_block(R, l)), kTightTol)
                << "band " << l;
    }
}

TEST_P(ShRotationMethods, CompositionInverseAndBandNorms) {
    std::mt19937_64 rng(13);
    const int bands = 12, K = sh_count(bands);
    const Mat3d R1 = random_rotation_matrix(rng), R2 = random_rotation_matrix(rng);
    const auto m = GetParam();
    const ShRotation a = ShRotation::from_matrix(R1, bands, m);
    const ShRotation b = ShRotation::from_matrix(R2, bands, m);
    const ShRotation ab = ShRotation::from_matrix(R2 * R1, bands, m);
    const ShRotation inv = ShRotation::from_matrix(transpose(R1), bands, m);
    const std::vector<double> c = random_coeffs(K, rng);
    std::vector<double> t(K), u(K), v(K);
    a.apply(c.data(), t.data(), K);
    b.apply(t.data(), u.data(), K);
    ab.apply(c.data(), v.data(), K);
    EXPECT_LT(max_abs_diff(u, v), kTightTol);  // R1 then R2 = R2·R1
    inv.apply(t.data(), u.data(), K);
    EXPECT_LT(max_abs_diff(u, c), kTightTol);  // R then R⁻¹ = identity
    for (int l = 0; l < bands; ++l) {
        double n0 = 0, n1 = 0;
        for (int i = l * l; i < (l + 1) * (l + 1); ++i) {
            n0 += c[i] * c[i];
            n1 += t[i] * t[i];
        }
        EXPECT_NEAR(std::sqrt(n1), std::sqrt(n0), kTightTol) << "band " << l;
    }
}

TEST_P(ShRotationMethods, BlocksStayOrthogonalAtManyBands) {
    std::mt19937_64 rng(14);
    // Ivanic's recurrence is what could drift; the paper's blocks come from quadrature (32 bands
    // keeps the test quick under sanitizers).
    const int bands = GetParam() == RotationMethod::ivanic ? 48 : 32;
    const ShRotation rot = ShRotation::from_matrix(random_rotation_matrix(rng), bands, GetParam());
    double worst = 0;
    for (int l = 0; l < bands; ++l) {
        const int n = 2 * l + 1;
        const double* b = rot.block(l);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double s = 0;
                for (int k = 0; k < n; ++k) s += b[k * n + i] * b[k * n + j];
                worst = std::max(worst, std::abs(s - (i == j ? 1.0 : 0.0)));
            }
    }
    EXPECT_LT(worst, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Both, ShRotationMethods,
                         ::testing::Values(RotationMethod::paper, RotationMethod::ivanic),
                         [](const auto& param_info) {
                             return std::string(to_string(param_info.param));
                         });

TEST(ShRotation, PaperEqualsIvanicAt20Bands) {
    std::mt19937_64 rng(21);
    const int bands = 20;
    std::vector<Mat3d> cases;
    for (int i = 0; i < 20; ++i) cases.push_back(random_rotation_matrix(rng));
    // Near and at the gimbal poles, where the Euler extraction is delicate.
    for (double beta : {0.0, 1e-9, kPi - 1e-9, kPi})
        cases.push_back(matrix_from_zyz(1.2, beta, 0.3));
    cases.push_back(Mat3d::identity());
    double worst = 0;
    for (const Mat3d& R : cases) {
        const ShRotation p = ShRotation::from_matrix(R, bands, RotationMethod::paper);
        const ShRotation v = ShRotation::from_matrix(R, bands, RotationMethod::ivanic);
        for (int l = 0; l < bands; ++l)
            worst = std::max(worst, max_abs_diff(block_vec(p, l), block_vec(v, l)));
    }
    EXPECT_LT(worst, kMethodTol);
    // From Euler angles directly (no extraction on the paper side).
    const ShRotation p = ShRotation::from_zyz(2.0, 0.7, -0.4, bands, RotationMethod::paper);
    const ShRotation v = ShRotation::from_zyz(2.0, 0.7, -0.4, bands, RotationMethod::ivanic);
    for (int l = 0; l < bands; ++l)
        EXPECT_LT(max_abs_diff(block_vec(p, l), block_vec(v, l)), kMethodTol) << "band " << l;
}

TEST(ShRotation, EveryBandIsRotatedNotJustTheFirstFew) {
    // A peer hard-codes R^x(π/2) to band 3 and zeroes band 4: make sure high bands carry energy
    // and match the reference.
    const Mat3d R = matrix_from_zyz(0.3, 1.0, 0.8);
    const ShRotation p = ShRotation::from_matrix(R, 9, RotationMethod::paper);
    for (int l : {4, 5, 8}) {
        EXPECT_LT(max_abs_diff(block_vec(p, l), reference_block(R, l)), kTightTol);
        double frob = 0;
        for (double v : block_vec(p, l)) frob += v * v;
        EXPECT_NEAR(frob, 2 * l + 1, 1e-10);  // orthogonal block: ‖B‖_F² = 2l+1
    }
}

TEST(ShRotation, X90BlocksAreRotationAboutX) {
    const ShRotation v = ShRotation::from_matrix(rotation_x(kPi / 2), 16, RotationMethod::ivanic);
    for (int l = 0; l < 16; ++l) {
        const double* x = rotation_x90_block(l);
        EXPECT_LT(
            max_abs_diff(std::vector<double>(x, x + (2 * l + 1) * (2 * l + 1)), block_vec(v, l)),
            kTightTol);
    }
    // Band 1 by hand: y_{1,·} ∝ (−y, z, −x), and f(d) = a·d becomes (R a)·d. Rx(π/2) takes
    // e_y → e_z, e_z → −e_y, e_x → e_x, so y_{1,−1} → −y_{1,0}, y_{1,0} → y_{1,−1},
    // y_{1,1} → y_{1,1}: D[0][−1] = −1, D[−1][0] = +1, D[1][1] = 1.
    const double* b1 = rotation_x90_block(1);
    const double expected[9] = {0, 1, 0, -1, 0, 0, 0, 0, 1};
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(b1[i], expected[i], kTightTol) << i;
}

TEST(ShRotation, PaperCacheIsSafeUnderConcurrentFirstUse) {
    // Threads race to extend the R^x(π/2) cache to different band counts (beyond what the other
    // tests use); every result must still equal Ivanic.
    std::vector<double> worst(4, 1.0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([t, &worst] {
            const int bands = 33 + t;
            const ShRotation p =
                ShRotation::from_zyz(0.1 * t, 1.0, -0.5, bands, RotationMethod::paper);
            const ShRotation v = ShRotation::from_zyz(0.1 * t, 1.0, -0.5, bands);
            double w = 0;
            for (int l = 0; l < bands; ++l)
                w = std::max(w, max_abs_diff(block_vec(p, l), block_vec(v, l)));
            worst[t] = w;
        });
    for (auto& th : threads) th.join();
    for (double w : worst) EXPECT_LT(w, kMethodTol);
}

TEST(ShRotation, DirectPaperRotationAndZRotationMatchMatrices) {
    std::mt19937_64 rng(31);
    const int bands = 15, K = sh_count(bands);
    const std::vector<double> c = random_coeffs(K, rng);
    const ShRotation rot = ShRotation::from_zyz(0.9, 2.1, -1.4, bands, RotationMethod::ivanic);
    std::vector<double> a(K), b(K);
    rot.apply(c.data(), a.data(), K);
    rotate_zyz_paper(0.9, 2.1, -1.4, c.data(), b.data(), K);
    EXPECT_LT(max_abs_diff(a, b), kMethodTol);

    const ShRotation rz = ShRotation::from_matrix(rotation_z(0.77), bands);
    rz.apply(c.data(), a.data(), K);
    rotate_z(0.77, c.data(), b.data(), K);
    EXPECT_LT(max_abs_diff(a, b), kTightTol);
    b = c;
    rotate_z(0.77, b.data(), b.data(), K);  // in place
    EXPECT_LT(max_abs_diff(a, b), kTightTol);
}

TEST(ShRotation, PartialLastBandIsZeroPaddedThenTruncated) {
    std::mt19937_64 rng(41);
    const ShRotation rot = ShRotation::from_matrix(random_rotation_matrix(rng), 8);
    for (int K : {1, 2, 7, 32, 48, 63, 64}) {
        std::vector<double> c = random_coeffs(K, rng), padded(64, 0.0), full(64), out(K), dir(K);
        std::copy(c.begin(), c.end(), padded.begin());
        rot.apply(padded.data(), full.data(), 64);
        rot.apply(c.data(), out.data(), K);
        for (int i = 0; i < K; ++i) EXPECT_NEAR(out[i], full[i], kTightTol) << "K=" << K;
        const EulerZyz e{0.2, 0.4, 0.6};
        const ShRotation r2 = ShRotation::from_zyz(e.alpha, e.beta, e.gamma, 8);
        r2.apply(padded.data(), full.data(), 64);
        rotate_zyz_paper(e.alpha, e.beta, e.gamma, c.data(), dir.data(), K);
        for (int i = 0; i < K; ++i) EXPECT_NEAR(dir[i], full[i], kMethodTol) << "K=" << K;
        rotate_z(0.5, c.data(), dir.data(), K);
        ShRotation::from_matrix(rotation_z(0.5), 8).apply(padded.data(), full.data(), 64);
        for (int i = 0; i < K; ++i) EXPECT_NEAR(dir[i], full[i], kTightTol) << "K=" << K;
    }
    // The dense matrix of a partial basis is the top-left K×K corner of the full one.
    const std::vector<double> d7 = rot.dense(7), d9 = rot.dense(9);
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 7; ++j) EXPECT_EQ(d7[i * 7 + j], d9[i * 9 + j]);
}

TEST(ShRotation, FloatApplyMatchesDouble) {
    std::mt19937_64 rng(51);
    const int bands = 16, K = sh_count(bands);
    const ShRotation rot = ShRotation::from_quat({0.3, -0.5, 0.2, 0.9}, bands);
    const std::vector<double> c = random_coeffs(K, rng);
    std::vector<float> cf(c.begin(), c.end()), of(K);
    std::vector<double> od(K);
    rot.apply(c.data(), od.data(), K);
    rot.apply(cf.data(), of.data(), K);
    for (int i = 0; i < K; ++i) EXPECT_NEAR(of[i], od[i], 1e-5) << i;
}

TEST(ShRotation, BadInputThrows) {
    EXPECT_THROW(ShRotation::from_matrix(Mat3d::identity(), 0), Error);
    EXPECT_THROW(ShRotation::from_matrix(Mat3d::identity(), kMaxBands + 1), Error);
    Mat3d bad = Mat3d::identity();
    bad.m[0][0] = 2;
    EXPECT_THROW(ShRotation::from_matrix(bad, 4), Error);
    Mat3d mirror = Mat3d::identity();
    mirror.m[2][2] = -1;
    EXPECT_THROW(ShRotation::from_matrix(mirror, 4, RotationMethod::paper), Error);
    EXPECT_THROW(ShRotation::from_zyz(NAN, 0, 0, 4), Error);
    EXPECT_THROW(ShRotation::from_quat({0, 0, 0, 0}, 4), Error);
    const ShRotation rot = ShRotation::from_zyz(0.1, 0.2, 0.3, 3);
    std::vector<double> a(16, 1.0), b(16);
    EXPECT_THROW(rot.apply(a.data(), b.data(), 10), Error);  // K > bands²
    EXPECT_THROW(rot.apply(a.data(), b.data(), -1), Error);
    EXPECT_THROW(rot.apply(a.data(), a.data(), 9), Error);      // in place
    EXPECT_THROW(rot.apply(a.data(), a.data() + 2, 9), Error);  // overlapping
    EXPECT_THROW(rot.block(3), Error);
    EXPECT_THROW(rot.block(-1), Error);
    EXPECT_THROW(rotate_zyz_paper(0, 0, 0, a.data(), a.data(), 9), Error);
    EXPECT_THROW(rotate_zyz_paper(0, 0, 0, a.data(), b.data(), sh_count(kMaxBands) + 1), Error);
    EXPECT_THROW(rotation_x90_block(kMaxBands), Error);
    EXPECT_THROW(parse_rotation_method("wigner"), Error);
    EXPECT_EQ(parse_rotation_method("paper"), RotationMethod::paper);
    EXPECT_EQ(parse_rotation_method("ivanic"), RotationMethod::ivanic);
}

}  // namespace
}  // namespace shprt
