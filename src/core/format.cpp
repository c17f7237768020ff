// Numbers for people (core/format.hpp).
#include "shprt/core/format.hpp"

#include <fmt/format.h>

#include <cmath>

namespace shprt {

std::string format_si(double value) {
    static const char* const kPrefix[] = {"", " k", " M", " G", " T", " P"};
    int p = 0;
    double v = std::fabs(value);
    while (v >= 999.5 && p < 5) {
        v /= 1000;
        ++p;
    }
    const double signed_v = value < 0 ? -v : v;
    if (v >= 99.95) return fmt::format("{:.0f}{}", signed_v, kPrefix[p]);
    if (v >= 9.995) return fmt::format("{:.1f}{}", signed_v, kPrefix[p]);
    return fmt::format("{:.2f}{}", signed_v, kPrefix[p]);
}

std::string format_duration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    if (seconds < 1) return fmt::format("{:.2f} s", seconds);
    if (seconds < 60) return fmt::format("{:.1f} s", seconds);
    const auto total = static_cast<long long>(std::ceil(seconds));
    const long long h = total / 3600, m = total / 60 % 60, s = total % 60;
    if (h > 0) return fmt::format("{}:{:02}:{:02}", h, m, s);
    return fmt::format("{}:{:02}", m, s);
}

std::string format_percent(double fraction) {
    const double v = 100 * fraction;
    if (!std::isfinite(v) || v < 0) return "?";
    if (v >= 9.95) return fmt::format("{:.0f}", v);
    if (v >= 0.995) return fmt::format("{:.1f}", v);
    if (v < 0.001) return "< 0.001";
    return fmt::format("{:.2g}", v);
}

}  // namespace shprt
