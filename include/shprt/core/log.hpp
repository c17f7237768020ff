// The library's log: messages go to a replaceable sink (by default nowhere). Tools install a sink
// that forwards to spdlog; tests may install one that records. One threshold, the log level,
// decides what reaches the sink; a shell sets it once (the command line's --log-level, -q, -v)
// and asks log_enabled(LogLevel::info) before it draws progress, so the one setting quiets both.
#pragma once

#include <fmt/format.h>

#include <functional>
#include <string_view>

namespace shprt {

enum class LogLevel { debug, info, warn, error };

using LogSink = std::function<void(LogLevel, std::string_view)>;

// Replaces the sink; pass nullptr to discard messages. Not thread-safe against concurrent logging.
void set_log_sink(LogSink sink);
// Passes `message` to the sink when `level` is at or above the log level.
void log_message(LogLevel level, std::string_view message);

// The lowest level that reaches the sink: debug (everything) until a shell sets it.
void set_log_level(LogLevel level);
bool log_enabled(LogLevel level);
// "debug", "info", "warn" or "error"; Error(invalid_argument) "unknown log level ..." otherwise.
LogLevel parse_log_level(std::string_view text);

template <class... Args>
void log_debug(fmt::format_string<Args...> f, Args&&... a) {
    log_message(LogLevel::debug, fmt::format(f, std::forward<Args>(a)...));
}
template <class... Args>
void log_info(fmt::format_string<Args...> f, Args&&... a) {
    log_message(LogLevel::info, fmt::format(f, std::forward<Args>(a)...));
}
template <class... Args>
void log_warn(fmt::format_string<Args...> f, Args&&... a) {
    log_message(LogLevel::warn, fmt::format(f, std::forward<Args>(a)...));
}

}  // namespace shprt
