// Option tables (core/options.hpp).
#include "shprt/core/options.hpp"

#include "shprt/core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace shprt {

std::string option_text(Spelling spelling, std::string_view name, std::string_view value) {
    if (spelling == Spelling::python) return fmt::format("{}={}", name, value);
    std::string option = "--" + std::string(name);
    std::replace(option.begin(), option.end(), '_', '-');
    return value.empty() ? option : fmt::format("{} {}", option, value);
}

std::string OptionInfo::spelled(Spelling spelling, std::string_view value) const {
    return option_text(spelling, spelling == Spelling::python ? python : name, value);
}

std::string OptionInfo::label(Spelling spelling) const {
    return spelling == Spelling::python ? python : option_text(spelling, name);
}

std::string limits_description(const OptionLimits& l) {
    const bool low = !std::isnan(l.min), high = !std::isnan(l.max);
    if (low && high)
        return l.exclusive ? fmt::format("between {} and {}", l.min, l.max)
                           : fmt::format("{} to {}", l.min, l.max);
    if (low) return fmt::format("{} {}", l.exclusive ? ">" : "≥", l.min);
    if (high) return fmt::format("{} {}", l.exclusive ? "<" : "≤", l.max);
    return {};
}

std::string default_text(bool value) { return value ? "true" : std::string(); }
std::string default_text(long long value) { return std::to_string(value); }
std::string default_text(std::uint64_t value) { return std::to_string(value); }
std::string default_text(double value) { return fmt::format("{}", value); }
std::string default_text(const std::string& value) { return value; }

const OptionInfo& find_option(const std::vector<const OptionInfo*>& table, std::string_view name) {
    for (const OptionInfo* row : table)
        if (row->name == name) return *row;
    fail(ErrorCode::invalid_argument, "option table: no option '{}'", name);
}

namespace {

// A value within the limits: finite (an open end is no licence for infinity), and inside them.
bool within(const OptionLimits& l, double v) {
    if (!std::isfinite(v)) return false;
    if (l.exclusive) return !(v <= l.min) && !(v >= l.max);
    return !(v < l.min) && !(v > l.max);
}

}  // namespace

void check_limits(const OptionInfo& row, double value, Spelling spelling, std::string_view extra) {
    SHPRT_CHECK(within(row.limits, value), invalid_argument, "{}: must be {}{}",
                row.spelled(spelling, fmt::format("{}", value)), row.limits_text, extra);
}

void check_limits(const OptionInfo& row, long long value, Spelling spelling,
                  std::string_view extra) {
    SHPRT_CHECK(within(row.limits, double(value)), invalid_argument, "{}: must be {}{}",
                row.spelled(spelling, std::to_string(value)), row.limits_text, extra);
}

}  // namespace shprt
