// The bake's progress reporter, shared by the CPU and GPU backends: counters that any thread may
// bump, and reports to BakeOptions::progress made only from the thread that called bake(), at
// most ~20 a second and once at the end. Shadowed transfer reports rays with the total estimated
// from the rays per receiver so far (S/2 before the first); unshadowed transfer reports samples.
#pragma once

#include "shprt/core/progress.hpp"

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <thread>

namespace shprt::detail {

class BakeProgress {
public:
    BakeProgress(const ProgressFn& callback, bool shadowed, std::uint64_t receivers,
                 std::uint64_t samples);
    // A stage counted in plain units (the rows of the bounces' products, say): reports
    // ProgressInfo{stage, done, total, unit}; add(n, 0) counts n units. `stage` and `unit` must
    // outlive the reporter (string literals).
    BakeProgress(const ProgressFn& callback, std::string_view stage, std::string_view unit,
                 std::uint64_t total);

    // Thread-safe: `receivers` more receivers are done, having cast `rays` rays.
    void add(std::uint64_t receivers, std::uint64_t rays) {
        m_rays.fetch_add(rays, std::memory_order_relaxed);
        m_receivers.fetch_add(receivers, std::memory_order_relaxed);
    }
    // Thread-safe: an error-bounded bake's finished receivers' estimated errors, for
    // ProgressInfo::error_p99 (a histogram of eighth octaves from 1e-6) and, against the bake's
    // `target`, ProgressInfo::over_target.
    void add_errors(const float* errors, std::size_t count, double target);

    // On the calling thread only (others return at once): reports when the last report is
    // ≥ 50 ms old. Returns false once the callback asked to stop (and from then on).
    bool poll();
    // The final report (on the calling thread): returns false when the callback asks to stop.
    bool finish();

    // What follows this stage outside its total (ProgressInfo::then); `then` must outlive the
    // reporter.
    void set_then(std::string_view then) { m_then = then; }
    // This stage's name in the reports ("bake" unless set); `stage` must outlive the reporter.
    void set_stage(std::string_view stage) { m_stage = stage; }

    bool stopped() const { return m_stop.load(std::memory_order_relaxed); }
    void stop() { m_stop.store(true, std::memory_order_relaxed); }
    std::uint64_t rays() const { return m_rays.load(); }
    std::uint64_t receivers_done() const { return m_receivers.load(); }

private:
    bool report(bool final);

    const ProgressFn& m_callback;
    bool m_shadowed;
    std::string_view m_stage = "bake", m_unit;  // m_unit empty: a bake (rays or samples)
    std::string_view m_then;
    std::uint64_t m_total, m_samples;
    std::atomic<std::uint64_t> m_rays{0}, m_receivers{0};
    std::atomic<bool> m_stop{false};
    static constexpr int kErrorBuckets = 224;  // 28 octaves above 1e-6, 8 an octave
    std::array<std::atomic<std::uint64_t>, kErrorBuckets> m_errors{};
    std::atomic<bool> m_has_errors{false};
    std::atomic<std::uint64_t> m_over{0};  // of the counted errors, those over the target
    double error_p99() const;
    double over_target() const;
    std::thread::id m_caller;
    std::chrono::steady_clock::time_point m_last;
};

}  // namespace shprt::detail
