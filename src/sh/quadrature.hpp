// Private to src/sh: the Gauss–Legendre rule that both the quadrature direction sets
// (sampler.cpp) and the paper rotation's exact X(π/2) blocks (rotation_paper.cpp) integrate with.
#pragma once

#include <vector>

namespace shprt::detail {

// n Gauss–Legendre nodes (descending, from +1 to −1) and weights on [−1, 1]: exact for
// polynomials of degree ≤ 2n − 1. Symmetric to the last bit; an odd rule's middle node is 0.
void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace shprt::detail
