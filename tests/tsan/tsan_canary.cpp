// The ThreadSanitizer stage's canary (docs/sanitizers.md; built with SHPRT_TSAN=ON only): two
// tasks of one shprt::parallel_for write one int without synchronisation. CTest passes it only
// when TSan reports the data race, under the stage's own TSAN_OPTIONS and suppressions, which
// shows that the fork/join annotations (shprt/core/tsan.hpp) and tests/tsan.supp do not hide a
// race between two tasks.
#include "shprt/core/parallel.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

int main() {
    volatile int shared = 0;  // volatile: each of the loop's writes happens
    std::atomic<int> started{0};
    std::atomic<bool> apart{true};
    shprt::parallel_each(2, 2, [&](std::size_t i) {
        // Both tasks wait until both have started, so they run on two threads at once (the
        // arena has two); the writes come after the wait and nothing orders them.
        // Relaxed: a release/acquire pair here would order the writes for ThreadSanitizer (its
        // clocks advance only at releases), which then, in some runs, saw no race at all.
        started.fetch_add(1, std::memory_order_relaxed);
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (started.load(std::memory_order_relaxed) < 2) {
            if (std::chrono::steady_clock::now() > give_up) {
                apart.store(false);
                return;
            }
            std::this_thread::yield();
        }
        // The race, many times over: two writes at the very same moment can slip past TSan's
        // shadow check (1 run in 8 with a single write each), a thousand cannot.
        for (int k = 0; k < 1000; ++k) {
            shared = int(i) + 1;
            std::this_thread::yield();
        }
    });
    if (!apart.load()) {
        std::puts("tsan_canary: the two tasks never ran at the same time (no second thread)");
        return 1;
    }
    std::printf("tsan_canary: shared = %d\n", int(shared));
    return 0;
}
