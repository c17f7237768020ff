// Wall-clock timing for stats and reports: one clock, one way to read it.
#pragma once

#include <chrono>
#include <ctime>

namespace shprt {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU seconds of the calling thread. Work split between phases on worker threads accumulates this
// per worker rather than wall intervals: on a machine shared with other work, a preempted worker's
// wall interval would charge the waiting to whichever phase it happened in.
inline double thread_cpu_seconds() {
    timespec ts{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace shprt
