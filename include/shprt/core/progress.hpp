// Progress reporting for long operations. The library never prints: it calls a callback that the
// caller owns (the CLI draws a bar with rate and ETA). Returning false from the callback asks the
// operation to stop; it then throws shprt::Error with ErrorCode::cancelled.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>

namespace shprt {

struct ProgressInfo {
    std::string_view stage;  // e.g. "bake", "project", "write"
    std::uint64_t done;      // units of work finished in this stage
    std::uint64_t total;     // units of work in this stage (0 if unknown)
    std::string_view unit;   // what a unit is, e.g. "rays", "vertices"
    // Work that follows this stage and is not in its total, when it cannot be timed yet (the
    // bounces of an interreflected bake, whose cost is known only once the operator exists):
    // e.g. "3 bounces". Empty: this stage's ETA is the operation's. A display says so after the
    // ETA ("ETA 3.1 s + 3 bounces") instead of predicting what it has not measured.
    std::string_view then = {};
    // An error-bounded bake (bake.hpp, BakeOptions::target_error): the estimated error that 99 %
    // of the receivers finished so far are under (to an eighth of an octave, rounded up); negative:
    // none. A display shows it ("err 99%: 0.8 %").
    double error_p99 = -1;
    // … and the share of those receivers whose estimated error is over the target: the sample cap
    // (BakeOptions::max_samples) stopped them there. Negative: none finished yet. A display shows
    // it when it is not 0 ("12 % over E"): a cap too low shows long before the bake ends.
    double over_target = -1;
};

// Called from one thread at a time, at most a few dozen times per second.
using ProgressFn = std::function<bool(const ProgressInfo&)>;

}  // namespace shprt
