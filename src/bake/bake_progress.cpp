// The bake's progress reporter (progress.hpp).
#include "bake/bake_progress.hpp"

#include <algorithm>
#include <cmath>

namespace shprt::detail {

namespace {
constexpr auto kReportInterval = std::chrono::milliseconds(50);  // ≤ 20 reports per second
}

BakeProgress::BakeProgress(const ProgressFn& callback, bool shadowed, std::uint64_t receivers,
                           std::uint64_t samples)
    : m_callback(callback),
      m_shadowed(shadowed),
      m_total(receivers),
      m_samples(samples),
      m_caller(std::this_thread::get_id()),
      m_last(std::chrono::steady_clock::now()) {}

BakeProgress::BakeProgress(const ProgressFn& callback, std::string_view stage,
                           std::string_view unit, std::uint64_t total)
    : m_callback(callback),
      m_shadowed(false),
      m_stage(stage),
      m_unit(unit),
      m_total(total),
      m_samples(1),
      m_caller(std::this_thread::get_id()),
      m_last(std::chrono::steady_clock::now()) {}

namespace {
constexpr double kSmallestError = 1e-6;
}

void BakeProgress::add_errors(const float* errors, std::size_t count, double target) {
    std::uint64_t over = 0;
    for (std::size_t i = 0; i < count; ++i) {
        over += double(errors[i]) > target ? 1 : 0;
        const double e = std::max(double(errors[i]), kSmallestError);
        const int b = std::clamp(int(8.0 * std::log2(e / kSmallestError)), 0, kErrorBuckets - 1);
        m_errors[std::size_t(b)].fetch_add(1, std::memory_order_relaxed);
    }
    m_over.fetch_add(over, std::memory_order_relaxed);
    m_has_errors.store(true, std::memory_order_relaxed);
}

double BakeProgress::over_target() const {
    if (!m_has_errors.load(std::memory_order_relaxed)) return -1;
    std::uint64_t total = 0;
    for (const auto& c : m_errors) total += c.load(std::memory_order_relaxed);
    // Workers may count between the two reads, so a share read mid-bake is approximate (kept ≤ 1);
    // the final report, after the workers, is exact.
    if (total == 0) return -1;
    return std::min(1.0, double(m_over.load(std::memory_order_relaxed)) / double(total));
}

// The upper edge of the bucket where the top 1 % of the counted errors begins.
double BakeProgress::error_p99() const {
    if (!m_has_errors.load(std::memory_order_relaxed)) return -1;
    std::uint64_t total = 0;
    for (const auto& c : m_errors) total += c.load(std::memory_order_relaxed);
    std::uint64_t above = 0;
    for (int b = kErrorBuckets - 1; b >= 0; --b) {
        above += m_errors[std::size_t(b)].load(std::memory_order_relaxed);
        if (100 * above > total || b == 0) return kSmallestError * std::exp2(double(b + 1) / 8.0);
    }
    return -1;
}

bool BakeProgress::report(bool final) {
    const std::uint64_t done = m_receivers.load(std::memory_order_relaxed);
    if (!m_unit.empty()) return m_callback(ProgressInfo{m_stage, done, m_total, m_unit, m_then});
    if (!m_shadowed)
        return m_callback(
            ProgressInfo{m_stage, done * m_samples, m_total * m_samples, "samples", m_then});
    const std::uint64_t rays = m_rays.load(std::memory_order_relaxed);
    const double per_receiver = done > 0 ? double(rays) / double(done) : double(m_samples) / 2;
    const std::uint64_t total =
        final
            ? rays
            : rays + std::uint64_t(per_receiver * double(m_total - std::min(done, m_total)) + 0.5);
    return m_callback(ProgressInfo{m_stage, rays, std::max(total, rays), "rays", m_then,
                                   error_p99(), over_target()});
}

bool BakeProgress::poll() {
    if (stopped()) return false;
    if (!m_callback || std::this_thread::get_id() != m_caller) return true;
    const auto now = std::chrono::steady_clock::now();
    if (now - m_last < kReportInterval) return true;
    m_last = now;
    if (!report(false)) stop();
    return !stopped();
}

bool BakeProgress::finish() {
    if (stopped()) return false;
    if (m_callback && !report(true)) stop();
    return !stopped();
}

}  // namespace shprt::detail
