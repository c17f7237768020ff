// The clustered-PCA code's one size check (transfer/cpca_code.hpp).
#include "shprt/transfer/cpca_code.hpp"

#include "shprt/core/error.hpp"

#include <algorithm>

namespace shprt {

void validate(const CpcaCode& code, std::size_t rows, std::size_t D) {
    const std::size_t C = std::size_t(std::max(code.clusters, 0));
    const std::size_t V = std::size_t(std::max(code.vectors, 0));
    const bool none = code.clusters == 0 && code.vectors == 0 && code.cluster.empty() &&
                      code.weights.empty() && code.means.empty() && code.basis.empty();
    if (none) return;
    SHPRT_CHECK(
        C >= 1 && V >= 1 && code.cluster.size() == rows && code.weights.size() == rows * V &&
            code.means.size() == C * D && code.basis.size() == C * V * D,
        invalid_argument, "CPCA code does not fit: {} clusters, {} vectors, {} rows for {}, D = {}",
        code.clusters, code.vectors, code.cluster.size(), rows, D);
    const auto bad = std::find_if(code.cluster.begin(), code.cluster.end(),
                                  [&](std::uint32_t c) { return c >= C; });
    SHPRT_CHECK(bad == code.cluster.end(), invalid_argument,
                "CPCA cluster {} of receiver {} is not below {}", *bad, bad - code.cluster.begin(),
                C);
}

}  // namespace shprt
