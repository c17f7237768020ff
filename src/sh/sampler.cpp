// Sphere direction sets and exact quadrature.
//  * Uniform set: Sloan, Kautz, Snyder 2002 / Green 2003, "Spherical Harmonic Lighting: The Gritty
//    Details" ((θ, φ) = (2·acos(√(1−x)), 2π·y)), with Philox-4x32-10 (Salmon et al. 2011).
//  * Spherical Fibonacci: Swinbank and Purser 2006; Marques et al. 2013.
//  * Sobol: Sobol 1967, Joe and Kuo 2008 (dimension 2 = polynomial x + 1); Owen 1995 scrambling
//    by hashing, Laine and Karras 2011, Burley 2020.
//  * Random rotation: Shoemake 1992.
//  * Coherent order: the octahedral map (Praun and Hoppe 2003) walked along a Hilbert curve
//    (direction_order.hpp).
//  * Gauss–Legendre nodes by Newton's method on the three-term Legendre recurrence (Golub and
//    Welsch 1969 give the same nodes; Newton is simpler and accurate to rounding here).
// The per-direction maps are in include/shprt/sh/sampler.hpp (SHPRT_HD); this file builds sets.
#include "shprt/sh/sampler.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/direction_order.hpp"

#include "sh/quadrature.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/names.hpp"

#include <algorithm>
#include <cmath>

namespace shprt {
namespace {

constexpr std::uint32_t kMaxDirections = 1u << 28;

template <class Set>
Set make_set(SamplerKind kind, std::uint64_t seed, std::uint32_t count) {
    SHPRT_CHECK(count >= 1 && count <= kMaxDirections, invalid_argument,
                "direction set ({}): count must be in [1, {}], got {}", to_string(kind),
                kMaxDirections, count);
    using T = typename decltype(Set::weights)::value_type;
    Set set;
    set.dirs.resize(3 * static_cast<std::size_t>(count));
    set.weights.assign(count, static_cast<T>(4.0 * kPi / count));
    for (std::uint32_t s = 0; s < count; ++s) {
        const Vec3d d = sphere_direction<double>(kind, seed, s, count);
        set.dirs[3 * static_cast<std::size_t>(s) + 0] = static_cast<T>(d.x);
        set.dirs[3 * static_cast<std::size_t>(s) + 1] = static_cast<T>(d.y);
        set.dirs[3 * static_cast<std::size_t>(s) + 2] = static_cast<T>(d.z);
    }
    return set;
}

// Legendre P_n(x) and P_{n−1}(x) by the recurrence (l+1)P_{l+1} = (2l+1)x P_l − l P_{l−1}.
void legendre_pair(int n, double x, double& pn, double& pn1) {
    double p0 = 1.0, p1 = x;
    if (n == 0) {
        pn = 1.0;
        pn1 = 0.0;
        return;
    }
    for (int l = 1; l < n; ++l) {
        const double p2 = ((2.0 * l + 1.0) * x * p1 - l * p0) / (l + 1.0);
        p0 = p1;
        p1 = p2;
    }
    pn = p1;
    pn1 = p0;
}

}  // namespace

void detail::gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.assign(n, 0.0);
    weights.assign(n, 0.0);
    const int half = (n + 1) / 2;
    for (int i = 0; i < half; ++i) {
        // Tricomi's estimate of the i-th largest root, then Newton.
        double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double dp = 0.0;
        for (int iter = 0; iter < 100; ++iter) {
            double pn, pn1;
            legendre_pair(n, x, pn, pn1);
            dp = n * (x * pn - pn1) / (x * x - 1.0);  // P_n'(x)
            const double dx = pn / dp;
            x -= dx;
            if (std::abs(dx) <= 1e-16) break;
        }
        double pn, pn1;
        legendre_pair(n, x, pn, pn1);
        dp = n * (x * pn - pn1) / (x * x - 1.0);
        const double w = 2.0 / ((1.0 - x * x) * dp * dp);
        // Mirror: the rule is symmetric; the middle node of an odd rule is exactly 0.
        if (n % 2 == 1 && i == half - 1) x = 0.0;
        nodes[i] = x;
        nodes[n - 1 - i] = -x;
        weights[i] = w;
        weights[n - 1 - i] = w;
    }
}

namespace {
constexpr Named<SamplerKind> kSamplerNames[] = {{SamplerKind::uniform, "uniform"},
                                                {SamplerKind::stratified, "stratified"},
                                                {SamplerKind::fibonacci, "fibonacci"},
                                                {SamplerKind::sobol, "sobol"}};
}  // namespace

const char* to_string(SamplerKind kind) { return name_of(kSamplerNames, kind); }
SamplerKind parse_sampler_kind(const std::string& name) {
    return parse_named(kSamplerNames, name, "sampler");
}

namespace {
constexpr Named<DirectionFrame> kFrameNames[] = {{DirectionFrame::sphere, "sphere"},
                                                 {DirectionFrame::local, "local"}};
}  // namespace

const char* to_string(DirectionFrame frame) { return name_of(kFrameNames, frame); }
DirectionFrame parse_direction_frame(const std::string& name) {
    return parse_named(kFrameNames, name, "directions");
}

DirectionSet make_local_direction_set(SamplerKind kind, std::uint64_t seed, std::uint32_t count,
                                      HemisphereDensity density) {
    DirectionSet set = make_set<DirectionSet>(kind, seed, count);  // checks count
    set.frame = DirectionFrame::local;
    const bool cosine = density == HemisphereDensity::cosine;
    set.weights.assign(count, static_cast<float>((cosine ? kPi : 2.0 * kPi) / count));
    for (std::uint32_t s = 0; s < count; ++s) {
        const Vec3d d = sphere_direction<double>(kind, seed, s, count);
        const Vec3d l = cosine ? sphere_to_cosine_hemisphere<double>(d)
                               : sphere_to_uniform_hemisphere<double>(d);
        set.dirs[3 * static_cast<std::size_t>(s) + 0] = static_cast<float>(l.x);
        set.dirs[3 * static_cast<std::size_t>(s) + 1] = static_cast<float>(l.y);
        set.dirs[3 * static_cast<std::size_t>(s) + 2] = static_cast<float>(l.z);
    }
    return set;
}

std::vector<double> open_hemisphere_transfer(int K, HemisphereDensity density) {
    SHPRT_CHECK(K >= 1 && K <= kMaxComputeBands * kMaxComputeBands, invalid_argument,
                "open hemisphere transfer: K must be in [1, {}], got {}",
                kMaxComputeBands * kMaxComputeBands, K);
    const bool cosine = density == HemisphereDensity::cosine;
    const int bands = sh_bands_for(K);
    const int n_theta = bands + 1, n_phi = 2 * bands + 1;
    std::vector<double> x, wx;
    detail::gauss_legendre(n_theta, x, wx);
    const std::size_t n = std::size_t(K);
    std::vector<double> out(cosine ? n : n * (n + 1) / 2, 0.0), y(n);
    for (int i = 0; i < n_theta; ++i) {
        const double z = 0.5 * (x[i] + 1.0);  // [−1, 1] → [0, 1]
        const double r = std::sqrt(std::max(0.0, (1.0 - z) * (1.0 + z)));
        for (int k = 0; k < n_phi; ++k) {
            const double phi = 2.0 * kPi * (k + 0.5) / n_phi;
            const double w = 0.5 * wx[i] * 2.0 * kPi / n_phi * (cosine ? z : 1.0);
            sh_eval_k(K, r * std::cos(phi), r * std::sin(phi), z, y.data());
            if (cosine) {
                for (std::size_t a = 0; a < n; ++a) out[a] += w * y[a];
                continue;
            }
            double* o = out.data();
            for (std::size_t a = 0; a < n; ++a)
                for (std::size_t b = a; b < n; ++b) *o++ += w * y[a] * y[b];
        }
    }
    return out;
}

DirectionSet make_direction_set(SamplerKind kind, std::uint64_t seed, std::uint32_t count) {
    return make_set<DirectionSet>(kind, seed, count);
}

DirectionSetD make_direction_set_d(SamplerKind kind, std::uint64_t seed, std::uint32_t count) {
    return make_set<DirectionSetD>(kind, seed, count);
}

DirectionSetD gauss_legendre_set_d(int n_theta, int n_phi) {
    SHPRT_CHECK(n_theta >= 1 && n_theta <= 65536 && n_phi >= 1 && n_phi <= 65536 &&
                    static_cast<long long>(n_theta) * n_phi <= kMaxDirections,
                invalid_argument,
                "Gauss-Legendre set: need 1 <= n_theta, n_phi <= 65536 and n_theta*n_phi <= {}, "
                "got n_theta={}, n_phi={}",
                kMaxDirections, n_theta, n_phi);
    std::vector<double> z, wz;
    detail::gauss_legendre(n_theta, z, wz);
    std::vector<double> cos_phi(n_phi), sin_phi(n_phi);
    for (int k = 0; k < n_phi; ++k) {
        const double phi = 2.0 * kPi * (k + 0.5) / n_phi;
        cos_phi[k] = std::cos(phi);
        sin_phi[k] = std::sin(phi);
    }
    DirectionSetD set;
    const std::size_t count = static_cast<std::size_t>(n_theta) * n_phi;
    set.dirs.resize(3 * count);
    set.weights.resize(count);
    const double dphi = 2.0 * kPi / n_phi;
    for (int i = 0; i < n_theta; ++i) {
        const double r = std::sqrt((1.0 - z[i]) * (1.0 + z[i]));
        for (int k = 0; k < n_phi; ++k) {
            const std::size_t s = static_cast<std::size_t>(i) * n_phi + k;
            set.dirs[3 * s + 0] = r * cos_phi[k];
            set.dirs[3 * s + 1] = r * sin_phi[k];
            set.dirs[3 * s + 2] = z[i];
            set.weights[s] = wz[i] * dphi;
        }
    }
    return set;
}

DirectionSet gauss_legendre_set(int n_theta, int n_phi) {
    return to_float(gauss_legendre_set_d(n_theta, n_phi));
}

DirectionSetD quadrature_set_for_bands_d(int bands) {
    SHPRT_CHECK(bands >= 1 && bands <= 4096, invalid_argument,
                "quadrature set: bands must be in [1, 4096], got {}", bands);
    return gauss_legendre_set_d(bands, 2 * bands - 1);
}

DirectionSet quadrature_set_for_bands(int bands) {
    return to_float(quadrature_set_for_bands_d(bands));
}

DirectionSet to_float(const DirectionSetD& set) {
    DirectionSet out;
    out.dirs.assign(set.dirs.begin(), set.dirs.end());
    out.weights.assign(set.weights.begin(), set.weights.end());
    return out;
}

std::vector<std::uint32_t> coherent_order(const DirectionSet& set) {
    return coherent_order(set, std::max<std::size_t>(set.size(), 1));
}

std::vector<std::uint32_t> coherent_order(const DirectionSet& set, std::size_t first_prefix) {
    const std::size_t S = set.size();
    std::vector<std::uint64_t> keyed(S);
    for (std::size_t s = 0; s < S; ++s) {
        const std::uint64_t key =
            octahedral_hilbert_key(set.dirs[3 * s], set.dirs[3 * s + 1], set.dirs[3 * s + 2]);
        keyed[s] = key << 32 | static_cast<std::uint32_t>(s);  // ties by index: a total order
    }
    // Each segment [a, b) sorted on its own: the segments are index ranges, in order.
    for (std::size_t a = 0, b = std::min(S, std::max<std::size_t>(first_prefix, 1)); a < S;
         a = b, b = std::min(S, 2 * b))
        std::sort(keyed.begin() + std::ptrdiff_t(a), keyed.begin() + std::ptrdiff_t(b));
    std::vector<std::uint32_t> order(S);
    for (std::size_t i = 0; i < S; ++i) order[i] = static_cast<std::uint32_t>(keyed[i]);
    return order;
}

}  // namespace shprt
