// Gauss–Legendre nodes and weights on [−1, 1] by Newton iteration on P_n: the tests' own exact
// quadrature in cos θ, written independently of the library's quadrature sets so that tests of
// those sets (and of everything checked against exact integrals) compare two implementations.
#pragma once

#include "shprt/core/math.hpp"

#include <cmath>
#include <vector>

namespace shprt::test_support {

// n nodes x (descending) and weights w: Σ w_i p(x_i) = ∫ p for polynomials of degree < 2n.
inline void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

}  // namespace shprt::test_support
