// An error-bounded bake's estimates summarised (transfer/estimates.hpp): receivers per prefix, the
// estimated error's spread, and receivers per band of the error against the target — the lines
// `shprt info` and `shprt bake` print.
#include "shprt/transfer/estimates.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <vector>

namespace shprt {
namespace {

TransferSet with_estimates(double target, std::vector<std::uint32_t> samples,
                           std::vector<float> errors) {
    TransferSet t;
    t.target_error = target;
    t.receiver_samples = std::move(samples);
    t.receiver_error = std::move(errors);
    return t;
}

TEST(Estimates, ReceiversPerPrefixAndPerErrorBand) {
    // E = 0.5: E/4 = 0.125 and E/2 = 0.25 (exact in float); a band holds its upper edge.
    const TransferSet t = with_estimates(0.5, {64, 64, 128, 256, 256, 256},
                                         {0.0625f, 0.125f, 0.1875f, 0.375f, 0.5f, 0.625f});
    const EstimateSummary s = summarize_estimates(t);
    ASSERT_EQ(s.receivers_per_samples.size(), 3u);
    EXPECT_EQ(s.receivers_per_samples[0], (std::pair<std::uint32_t, std::size_t>{64, 2}));
    EXPECT_EQ(s.receivers_per_samples[2], (std::pair<std::uint32_t, std::size_t>{256, 3}));
    EXPECT_DOUBLE_EQ(s.mean_samples, (64 + 64 + 128 + 256 * 3) / 6.0);
    EXPECT_EQ(s.receivers_per_error_band, (std::array<std::size_t, 4>{2, 1, 2, 1}));
    EXPECT_EQ(error_bands_text(s), "≤ E/4: 2, ≤ E/2: 1, ≤ E: 2, over E: 1");
    EXPECT_DOUBLE_EQ(s.error.worst, 0.625);
    EXPECT_EQ(samples_histogram_text(s), "64: 2, 128: 1, 256: 3 (mean 171)");
}

TEST(Estimates, NoTargetNoBandsAndNoEstimatesNothing) {
    const EstimateSummary s = summarize_estimates(with_estimates(0, {64, 128}, {0.5f, 0.25f}));
    EXPECT_EQ(s.receivers_per_error_band, (std::array<std::size_t, 4>{}));
    EXPECT_EQ(s.receivers_per_samples.size(), 2u);
    EXPECT_TRUE(summarize_estimates(TransferSet{}).receivers_per_samples.empty());
}

}  // namespace
}  // namespace shprt
