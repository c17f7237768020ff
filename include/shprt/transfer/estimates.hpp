// An error-bounded bake's per-receiver estimates (TransferSet::receiver_samples and
// receiver_error, docs/sampling.md "Error-bounded bakes") in a few numbers: how many receivers
// took each prefix, the estimated error's worst, 99th percentile and mean, and how many receivers
// lie in each band of the estimated error against the target (over E: those the sample cap
// stopped before the target). `shprt info`, `shprt bake` and the bench print them; the same
// percentile rule serves true errors too.
#pragma once

#include "shprt/transfer/transfer.hpp"

#include <array>
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
    // Receivers whose estimated error e is ≤ E/4, in (E/4, E/2], in (E/2, E] and over E, with E
    // the set's target_error (all zero when it has none).
    std::array<std::size_t, 4> receivers_per_error_band{};
};
// Empty (no receivers_per_samples) for a set without estimates.
EstimateSummary summarize_estimates(const TransferSet& set);
// For reports: "64: 1200, 128: 300, … (mean 391)" (receivers per prefix), "worst 0.0099, 99th
// percentile 0.0093, mean 0.0052" and "≤ E/4: 310, ≤ E/2: 702, ≤ E: 488, over E: 0" (receivers
// per error band).
std::string samples_histogram_text(const EstimateSummary& summary);
std::string error_spread_text(const ErrorSpread& spread);
std::string error_bands_text(const EstimateSummary& summary);

}  // namespace shprt
