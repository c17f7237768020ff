// An error-bounded bake's per-receiver estimates (TransferSet::receiver_samples and
// receiver_error, docs/sampling.md "Error-bounded bakes") in a few numbers: how many receivers
// took each prefix, and the estimated error's worst, 99th percentile and mean. `shprt info`,
// `shprt bake` and the bench print them; the same percentile rule serves true errors too.
#pragma once

#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace shprt {

// Worst, 99th percentile (the value at rank ⌈0.99·n⌉ of the sorted values) and mean of `values`
// (all 0 when empty).
struct ErrorSpread {
    double worst = 0, p99 = 0, mean = 0;
};
ErrorSpread error_spread(std::vector<double> values);

struct EstimateSummary {
    std::vector<std::pair<std::uint32_t, std::size_t>> receivers_per_samples;  // increasing S
    double mean_samples = 0;
    ErrorSpread error;
};
// Empty (no receivers_per_samples) for a set without estimates.
EstimateSummary summarize_estimates(const TransferSet& set);
// For reports: "64: 1200, 128: 300, … (mean 391)" (receivers per prefix) and "worst 0.0099, 99th
// percentile 0.0093, mean 0.0052".
std::string samples_histogram_text(const EstimateSummary& summary);
std::string error_spread_text(const ErrorSpread& spread);

}  // namespace shprt
