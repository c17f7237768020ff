#include "shprt/core/log.hpp"

#include "shprt/core/names.hpp"

#include <atomic>
#include <mutex>
#include <utility>

namespace shprt {
namespace {
std::mutex g_mutex;
LogSink g_sink;
std::atomic<LogLevel> g_level{LogLevel::debug};

constexpr Named<LogLevel> kLogLevelNames[] = {{LogLevel::debug, "debug"},
                                              {LogLevel::info, "info"},
                                              {LogLevel::warn, "warn"},
                                              {LogLevel::error, "error"}};
}  // namespace

void set_log_sink(LogSink sink) {
    std::lock_guard lock(g_mutex);
    g_sink = std::move(sink);
}

void log_message(LogLevel level, std::string_view message) {
    if (!log_enabled(level)) return;
    std::lock_guard lock(g_mutex);
    if (g_sink) g_sink(level, message);
}

void set_log_level(LogLevel level) { g_level = level; }

bool log_enabled(LogLevel level) { return level >= g_level.load(); }

LogLevel parse_log_level(std::string_view text) {
    return parse_named(kLogLevelNames, text, "log level");
}

}  // namespace shprt
