// Slow reference evaluation of real SH, written as directly from Green 2003 as possible.
#include "shprt/sh/basis.hpp"

#include "shprt/core/error.hpp"

#include <cmath>
#include <cstdlib>

namespace shprt {
namespace {

// Associated Legendre P_l^m(x), m ≥ 0, Condon–Shortley phase included (Green's recurrences).
long double legendre(int l, int m, long double x) {
    long double pmm = 1.0L;
    if (m > 0) {
        const long double somx2 = std::sqrt((1.0L - x) * (1.0L + x));
        long double fact = 1.0L;
        for (int i = 1; i <= m; ++i) {
            pmm *= -fact * somx2;
            fact += 2.0L;
        }
    }
    if (l == m) return pmm;
    long double pmmp1 = x * (2.0L * m + 1.0L) * pmm;
    if (l == m + 1) return pmmp1;
    long double pll = 0.0L;
    for (int ll = m + 2; ll <= l; ++ll) {
        pll = ((2.0L * ll - 1.0L) * x * pmmp1 - (ll + m - 1.0L) * pmm) / (ll - m);
        pmm = pmmp1;
        pmmp1 = pll;
    }
    return pll;
}

long double normalisation(int l, int m) {
    const long double pi = 3.141592653589793238462643383279502884L;
    const long double ratio = std::exp(std::lgamma(static_cast<long double>(l - m + 1)) -
                                       std::lgamma(static_cast<long double>(l + m + 1)));
    return std::sqrt((2.0L * l + 1.0L) * ratio / (4.0L * pi));
}

}  // namespace

double sh_eval_reference(int l, int m, double theta, double phi) {
    SHPRT_CHECK(l >= 0 && l <= 80 && std::abs(m) <= l, invalid_argument,
                "sh_eval_reference: need 0 <= l <= 80 and |m| <= l, got l={}, m={}", l, m);
    const long double sqrt2 = 1.414213562373095048801688724209698079L;
    const long double ct = std::cos(static_cast<long double>(theta));
    if (m == 0) return static_cast<double>(normalisation(l, 0) * legendre(l, 0, ct));
    const int am = std::abs(m);
    const long double p = legendre(l, am, ct);
    const long double k = normalisation(l, am);
    const long double trig = m > 0 ? std::cos(am * static_cast<long double>(phi))
                                   : std::sin(am * static_cast<long double>(phi));
    return static_cast<double>(sqrt2 * k * trig * p);
}

}  // namespace shprt
