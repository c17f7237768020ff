// The library's log: messages go to a replaceable sink (by default nowhere). Tools install a sink
// that forwards to spdlog; tests may install one that records.
#pragma once

#include <fmt/format.h>

#include <functional>
#include <string_view>

namespace shprt {

enum class LogLevel { debug, info, warn, error };

using LogSink = std::function<void(LogLevel, std::string_view)>;

// Replaces the sink; pass nullptr to discard messages. Not thread-safe against concurrent logging.
void set_log_sink(LogSink sink);
void log_message(LogLevel level, std::string_view message);

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
