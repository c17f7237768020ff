// Wall-clock timing for stats and reports: one clock, one way to read it.
#pragma once

#include <chrono>

namespace shprt {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace shprt
