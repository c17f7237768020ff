// Projection of environment maps (equirect, cube cross, six faces) onto real SH with exact
// pixel / texel solid angles, each pixel a patch of constant radiance (Sloan, Kautz & Snyder 2002,
// §4: lighting projected onto SH once per environment; Green 2003 for the basis). The equirect fast
// path separates each row into Fourier sums over the columns, as in the fast spherical-harmonic
// transforms of Driscoll & Healy (1994), in a frame whose pole is the map's pole +Y, then rotates
// the result to world axes with one SH rotation (Ivanic & Ruedenberg 1996).
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/light/cubemap.hpp"
#include "shprt/light/equirect.hpp"
#include "shprt/light/light.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/sh/sampler.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace shprt {
namespace {

void check_map(const Image& map, const char* what) {
    SHPRT_CHECK(!map.empty() && map.rgb.size() == 3 * map.pixel_count(), invalid_argument,
                "{}: image is empty or its pixel buffer has the wrong size ({}x{}, {} floats)",
                what, map.width, map.height, map.rgb.size());
}

// Gauss–Legendre nodes x ∈ (0, 1) and weights (summing to 1) for integrating over one row (or
// column) of a map of `cells` rows spanning π. The integrand (basis functions up to band
// bands−1) oscillates at most bands·π/cells radians across a cell; n = 6 + ⌈bands·π/cells⌉
// nodes integrate it to rounding.
struct EquirectRowRule {
    int n = 0;
    std::vector<double> x, w;
};

EquirectRowRule equirect_row_rule(int bands, int cells) {
    EquirectRowRule rule;
    rule.n = 6 + static_cast<int>(std::ceil(bands * kPi / cells));
    // Nodes and weights on [−1, 1] from the sphere rule with one azimuth (z_i, 2π·w_i).
    const DirectionSetD set = gauss_legendre_set_d(rule.n, 1);
    for (int i = 0; i < rule.n; ++i) {
        rule.x.push_back(0.5 * (set.dirs[3 * std::size_t(i) + 2] + 1.0));
        rule.w.push_back(set.weights[i] / (4.0 * kPi));
    }
    return rule;
}

ShLight to_light(const std::vector<double>& acc, int K) {
    ShLight light = ShLight::zero(K);
    for (std::size_t i = 0; i < acc.size(); ++i) light.coeffs[i] = static_cast<float>(acc[i]);
    return light;
}

// Adds w · L(texel) · y(d) for every texel of one face into acc (3·K, channel-major).
void accumulate_face(const Image& image, int x0, int y0, int n, const CubeFaceFrame& frame, int K,
                     std::vector<double>& acc) {
    std::vector<double> y(static_cast<std::size_t>(K));
    for (int ty = 0; ty < n; ++ty) {
        const double b = (2.0 * ty + 1.0) / n - 1.0;
        for (int tx = 0; tx < n; ++tx) {
            const double a = (2.0 * tx + 1.0) / n - 1.0;
            const Vec3d d = cube_face_direction(frame, a, b);
            const double w = cube_texel_solid_angle(tx, ty, n);
            const float* px = image.pixel(x0 + tx, y0 + ty);
            sh_eval_k(K, d.x, d.y, d.z, y.data());
            for (int c = 0; c < 3; ++c) {
                const double wl = w * double(px[c]);
                double* out = acc.data() + std::size_t(c) * K;
                for (int i = 0; i < K; ++i) out[i] += wl * y[i];
            }
        }
    }
}

}  // namespace

// ---- EquirectProjection: the fast path, one row at a time ----------------------------------

struct EquirectProjection::State {
    int K = 0, bands = 0, full = 0, W = 0, H = 0, next_row = 0;
    double dphi = 0;
    std::vector<double> cos_tab, sin_tab;
    EquirectRowRule rule;
    std::vector<double> cf;  // coefficients in frame F
    std::vector<double> q, qrow, a, b;
};

EquirectProjection::EquirectProjection(int width, int height, int K)
    : m_state(std::make_unique<State>()) {
    SHPRT_CHECK(width > 0 && height > 0, invalid_argument,
                "project_equirect: image is empty ({}x{})", width, height);
    ShLight::zero(K);  // validates K
    State& s = *m_state;
    s.K = K;
    s.bands = sh_bands_for(K);
    s.full = sh_count(s.bands);
    s.W = width;
    s.H = height;
    const int W = width, bands = s.bands;
    s.dphi = 2.0 * kPi / W;

    // Frame F: x_F = world z, y_F = world x, z_F = world y (a cyclic permutation, so a proper
    // rotation M with d_F = M d). Rows of the map are bands of constant z_F = cos θ.
    // Column azimuth in F: with φ' = 2π(u − ½) the map azimuth, d.x = s·sin φ', d.z = −s·cos φ',
    // so φ_F = atan2(d.x, d.z) = π − φ'. Over a column, ∫ cos(mφ) dφ = Δφ·sinc(mΔφ/2)·cos(mφ_c)
    // (likewise sin): the column tables carry the sinc factor, so the φ integral is exact.
    s.cos_tab.resize(std::size_t(W) * bands);
    s.sin_tab.resize(std::size_t(W) * bands);
    for (int x = 0; x < W; ++x) {
        const double phi_f = kPi - 2.0 * kPi * ((x + 0.5) / W - 0.5);
        for (int m = 0; m < bands; ++m) {
            const double h = 0.5 * m * s.dphi;
            const double sinc = m == 0 ? 1.0 : std::sin(h) / h;
            s.cos_tab[std::size_t(x) * bands + m] = sinc * std::cos(m * phi_f);
            s.sin_tab[std::size_t(x) * bands + m] = sinc * std::sin(m * phi_f);
        }
    }
    s.rule = equirect_row_rule(bands, height);
    s.cf.assign(3 * std::size_t(s.full), 0.0);
    s.q.resize(s.full);
    s.qrow.resize(s.full);
    s.a.resize(3 * std::size_t(bands));
    s.b.resize(3 * std::size_t(bands));
}

EquirectProjection::~EquirectProjection() = default;
EquirectProjection::EquirectProjection(EquirectProjection&&) noexcept = default;
EquirectProjection& EquirectProjection::operator=(EquirectProjection&&) noexcept = default;

int EquirectProjection::width() const { return m_state->W; }
int EquirectProjection::height() const { return m_state->H; }
int EquirectProjection::rows_added() const { return m_state->next_row; }

void EquirectProjection::add_row(const float* rgb) {
    State& s = *m_state;
    SHPRT_CHECK(s.next_row < s.H, invalid_argument,
                "EquirectProjection::add_row: all {} rows were already added", s.H);
    const int y = s.next_row++, W = s.W, H = s.H, bands = s.bands, full = s.full;
    // qrow = ∫_row q_lm(θ) sin θ dθ, where q_lm(θ) is y_lm at φ = 0: for m > 0
    // y_{l,±m}(θ, φ) = q_lm(θ)·cos(mφ) / q_lm(θ)·sin(mφ), and y_{l,0} = q_l0(θ).
    std::fill(s.qrow.begin(), s.qrow.end(), 0.0);
    const double t0 = kPi * y / H, t1 = kPi * (y + 1) / H;
    for (int k = 0; k < s.rule.n; ++k) {
        const double theta = t0 + (t1 - t0) * s.rule.x[k];
        const double w = (t1 - t0) * s.rule.w[k] * std::sin(theta);
        sh_eval_k(full, std::sin(theta), 0.0, std::cos(theta), s.q.data());
        for (int i = 0; i < full; ++i) s.qrow[i] += w * s.q[i];
    }
    std::fill(s.a.begin(), s.a.end(), 0.0);
    std::fill(s.b.begin(), s.b.end(), 0.0);
    for (int x = 0; x < W; ++x) {
        const float* px = rgb + 3 * std::size_t(x);
        const double* ct = s.cos_tab.data() + std::size_t(x) * bands;
        const double* st = s.sin_tab.data() + std::size_t(x) * bands;
        for (int c = 0; c < 3; ++c) {
            const double L = px[c];
            double* ac = s.a.data() + std::size_t(c) * bands;
            double* bc = s.b.data() + std::size_t(c) * bands;
            for (int m = 0; m < bands; ++m) {
                ac[m] += L * ct[m];
                bc[m] += L * st[m];
            }
        }
    }
    for (int c = 0; c < 3; ++c) {
        double* out = s.cf.data() + std::size_t(c) * full;
        const double* ac = s.a.data() + std::size_t(c) * bands;
        const double* bc = s.b.data() + std::size_t(c) * bands;
        for (int l = 0; l < bands; ++l) {
            out[sh_index(l, 0)] += s.dphi * s.qrow[sh_index(l, 0)] * ac[0];
            for (int m = 1; m <= l; ++m) {
                const double qm = s.dphi * s.qrow[sh_index(l, m)];
                out[sh_index(l, m)] += qm * ac[m];
                out[sh_index(l, -m)] += qm * bc[m];
            }
        }
    }
}

ShLight EquirectProjection::finish() const {
    const State& s = *m_state;
    SHPRT_CHECK(s.next_row == s.H, invalid_argument,
                "EquirectProjection::finish: {} of {} rows added", s.next_row, s.H);
    // World light f(d) = g(M d) where g has coefficients cf; ShRotation(R) maps g to g(R⁻¹ d),
    // so R = M⁻¹ = Mᵀ.
    ShLight light = ShLight::zero(s.K);
    const Mat3d M{{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
    const ShRotation rot = ShRotation::from_matrix(transpose(M), s.bands);
    std::vector<double> world(s.full);
    for (int c = 0; c < 3; ++c) {
        rot.apply(s.cf.data() + std::size_t(c) * s.full, world.data(), s.full);
        for (int i = 0; i < s.K; ++i) light.channel(c)[i] = static_cast<float>(world[i]);
    }
    return light;
}

ShLight project_equirect(const Image& map, int K) {
    check_map(map, "project_equirect");
    EquirectProjection projection(map.width, map.height, K);
    for (int y = 0; y < map.height; ++y) projection.add_row(map.pixel(0, y));
    return projection.finish();
}

ShLight project_equirect_reference(const Image& map, int K) {
    check_map(map, "project_equirect_reference");
    ShLight zero = ShLight::zero(K);  // validates K
    const int W = map.width, H = map.height;
    const int bands = sh_bands_for(K);
    // The same pixel integral, done the obvious way: a tensor Gauss–Legendre rule over each
    // pixel's (θ, φ) rectangle in world coordinates, weight sin θ dθ dφ.
    const EquirectRowRule rt = equirect_row_rule(bands, H);
    const EquirectRowRule rp = equirect_row_rule(bands, W / 2 > 0 ? W / 2 : 1);
    std::vector<double> acc(3 * std::size_t(K), 0.0), yv(K), integral(K);
    for (int py = 0; py < H; ++py) {
        const double t0 = kPi * py / H, t1 = kPi * (py + 1) / H;
        for (int px = 0; px < W; ++px) {
            const double u0 = double(px) / W, u1 = double(px + 1) / W;
            std::fill(integral.begin(), integral.end(), 0.0);
            for (int i = 0; i < rt.n; ++i) {
                const double theta = t0 + (t1 - t0) * rt.x[i];
                for (int j = 0; j < rp.n; ++j) {
                    const double u = u0 + (u1 - u0) * rp.x[j];
                    const double w =
                        (t1 - t0) * rt.w[i] * std::sin(theta) * (2.0 * kPi / W) * rp.w[j];
                    const Vec3d d = equirect_direction(u, theta / kPi);
                    sh_eval_k(K, d.x, d.y, d.z, yv.data());
                    for (int k = 0; k < K; ++k) integral[k] += w * yv[k];
                }
            }
            const float* p = map.pixel(px, py);
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < K; ++k)
                    acc[std::size_t(c) * K + k] += double(p[c]) * integral[k];
        }
    }
    return to_light(acc, zero.K);
}

ShLight project_cube_cross(const Image& cross, int K) {
    check_map(cross, "project_cube_cross");
    const int W = cross.width, H = cross.height;
    CrossLayout layout;
    int n = 0;
    if (W % 4 == 0 && H % 3 == 0 && W / 4 == H / 3) {
        layout = CrossLayout::horizontal;
        n = W / 4;
    } else if (W % 3 == 0 && H % 4 == 0 && W / 3 == H / 4) {
        layout = CrossLayout::vertical;
        n = W / 3;
    } else {
        fail(ErrorCode::format,
             "a cube cross must be 4:3 (horizontal, face size W/4 = H/3) or 3:4 (vertical, "
             "W/3 = H/4); got {}x{}",
             W, H);
    }
    ShLight zero = ShLight::zero(K);
    CrossCell cells[6];
    cross_cells(layout, cells);
    std::vector<double> acc(3 * std::size_t(K), 0.0);
    for (const CrossCell& cell : cells)
        accumulate_face(cross, cell.col * n, cell.row * n, n, cell.frame, K, acc);
    return to_light(acc, zero.K);
}

ShLight project_cube_faces(const std::array<Image, 6>& faces, int K) {
    const char* names[6] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};
    for (int f = 0; f < 6; ++f) {
        check_map(faces[f], "project_cube_faces");
        SHPRT_CHECK(faces[f].width == faces[f].height, format, "cube face {} is {}x{}, not square",
                    names[f], faces[f].width, faces[f].height);
        SHPRT_CHECK(faces[f].width == faces[0].width, format,
                    "cube face {} is {}x{} but face +X is {}x{}: all faces must be the same size",
                    names[f], faces[f].width, faces[f].height, faces[0].width, faces[0].height);
    }
    ShLight zero = ShLight::zero(K);
    std::vector<double> acc(3 * std::size_t(K), 0.0);
    for (int f = 0; f < 6; ++f)
        accumulate_face(faces[f], 0, 0, faces[f].width, cube_face_frame(static_cast<CubeFace>(f)),
                        K, acc);
    return to_light(acc, zero.K);
}

}  // namespace shprt
