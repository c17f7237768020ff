// A program outside the project, built against an installed shprt (the test `consumer`,
// tests/consumer/check.cmake): bakes the built-in plane through the public headers and checks
// the first coefficient, an open plane's clamped cosine: L00 = sqrt(pi)/2.
#include <shprt/bake/bake.hpp>
#include <shprt/scene/builtin.hpp>

#include <cmath>
#include <cstdio>

int main() {
    shprt::BakeOptions options;
    options.K = 4;
    options.samples = 256;
    const shprt::TransferSet t = shprt::bake(shprt::make_builtin("plane"), options);
    const double l00 = t.coeffs.at(0), expected = std::sqrt(std::acos(-1.0)) / 2;
    std::printf("baked %zu receivers, L00 %.4f (expected %.4f)\n", t.receiver_count(), l00, expected);
    return std::fabs(l00 - expected) < 0.02 ? 0 : 1;
}
