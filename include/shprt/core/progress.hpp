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
};

// Called from one thread at a time, at most a few dozen times per second.
using ProgressFn = std::function<bool(const ProgressInfo&)>;

}  // namespace shprt
