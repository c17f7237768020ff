// An error-bounded bake's per-receiver estimates, summarised (estimates.hpp).
#include "shprt/transfer/estimates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace shprt {

ErrorSpread error_spread(std::vector<double> values) {
    ErrorSpread s;
    if (values.empty()) return s;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    s.worst = values.back();
    const auto rank = static_cast<std::size_t>(std::ceil(0.99 * double(n)));
    s.p99 = values[std::clamp<std::size_t>(rank, 1, n) - 1];
    double sum = 0;
    for (double v : values) sum += v;
    s.mean = sum / double(n);
    return s;
}

EstimateSummary summarize_estimates(const TransferSet& set) {
    EstimateSummary out;
    if (set.receiver_samples.empty()) return out;
    std::map<std::uint32_t, std::size_t> counts;
    double total = 0;
    for (std::uint32_t s : set.receiver_samples) {
        ++counts[s];
        total += double(s);
    }
    out.receivers_per_samples.assign(counts.begin(), counts.end());
    out.mean_samples = total / double(set.receiver_samples.size());
    out.error =
        error_spread(std::vector<double>(set.receiver_error.begin(), set.receiver_error.end()));
    if (set.target_error > 0) {
        const double E = set.target_error;
        for (const float e : set.receiver_error) {
            const std::size_t band = e <= E / 4 ? 0 : e <= E / 2 ? 1 : e <= E ? 2 : 3;
            ++out.receivers_per_error_band[band];
        }
    }
    return out;
}

std::string samples_histogram_text(const EstimateSummary& summary) {
    std::string text;
    for (const auto& [samples, receivers] : summary.receivers_per_samples)
        text += fmt::format("{}{}: {}", text.empty() ? "" : ", ", samples, receivers);
    return fmt::format("{} (mean {:.0f})", text, summary.mean_samples);
}

std::string error_bands_text(const EstimateSummary& summary) {
    const auto& n = summary.receivers_per_error_band;
    return fmt::format("≤ E/4: {}, ≤ E/2: {}, ≤ E: {}, over E: {}", n[0], n[1], n[2], n[3]);
}

std::string error_spread_text(const ErrorSpread& spread) {
    return fmt::format("worst {:.3g}, 99th percentile {:.3g}, mean {:.3g}", spread.worst,
                       spread.p99, spread.mean);
}

}  // namespace shprt
