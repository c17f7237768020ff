#include "common/progress_bar.hpp"

#include "shprt/core/log.hpp"
#include "shprt/core/terminal.hpp"

#include <fmt/format.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <atomic>

namespace shprt::tools {
namespace {

using Clock = std::chrono::steady_clock;

int terminal_width(std::FILE* out) {
    winsize ws{};
    if (::ioctl(::fileno(out), TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 20) return ws.ws_col;
    return 80;
}

}  // namespace

ProgressBar::ProgressBar(std::string label, std::FILE* out)
    : m_label(std::move(label)),
      m_out(log_enabled(LogLevel::info) ? out : nullptr),
      m_terminal(terminal_escape_codes(m_out)),
      m_start(Clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

ProgressFn ProgressBar::callback() {
    return [this](const ProgressInfo& info) { return update(info); };
}

std::string ProgressBar::label(std::string_view stage) const {
    if (m_label.empty()) return std::string(stage);
    if (stage == m_first_stage) return m_label;
    return m_label + ": " + std::string(stage);
}

bool ProgressBar::update(const ProgressInfo& info) {
    if (m_out != nullptr) {
        if (info.stage != m_stage) {
            // A new stage (the bounces after the rays): its own line, rate, ETA and percentages.
            if (m_started) {
                finish();
                m_start = Clock::now();
                m_next_plain_percent = 25;
            } else {
                m_first_stage = std::string(info.stage);
            }
            m_started = true;
            m_stage = std::string(info.stage);
        }
        const auto now = Clock::now();
        const double elapsed = std::chrono::duration<double>(now - m_start).count();
        const bool complete = info.total > 0 && info.done >= info.total;
        if (m_terminal) {
            // Redraw at most 10 times a second, and always the final state.
            if (complete || now - m_last_draw >= std::chrono::milliseconds(100)) {
                m_last_draw = now;
                draw_terminal(info, elapsed);
            }
        } else if (info.total > 0) {
            const int percent = static_cast<int>(100.0 * double(info.done) / double(info.total));
            if (percent >= m_next_plain_percent) {
                print_plain(info, elapsed, percent);
                while (m_next_plain_percent <= percent) m_next_plain_percent += 25;
            }
        }
    }
    return !interrupted();
}

// "  err 99%: 0.8 %": an error-bounded bake's estimated error (ProgressInfo::error_p99), and
// ", 12 % over E" when the sample cap stopped some receivers above the target (over_target).
std::string ProgressBar::error_text(const ProgressInfo& info) {
    std::string text = "  err 99%: " + format_percent(info.error_p99) + " %";
    if (info.over_target > 0) text += ", " + format_percent(info.over_target) + " % over E";
    return text;
}

void ProgressBar::draw_terminal(const ProgressInfo& info, double elapsed) {
    const std::string label = this->label(info.stage);
    const double fraction =
        info.total > 0 ? std::clamp(double(info.done) / double(info.total), 0.0, 1.0) : 0.0;
    const double rate = elapsed > 0 ? double(info.done) / elapsed : 0.0;
    std::string tail = fmt::format(" {:3d}%", static_cast<int>(fraction * 100));
    if (rate > 0) tail += fmt::format("  {}{}/s", format_si(rate), info.unit);
    if (info.error_p99 >= 0) tail += error_text(info);
    if (info.total > 0 && rate > 0 && info.done < info.total) {
        tail += "  ETA " + format_duration(double(info.total - info.done) / rate);
        if (!info.then.empty()) tail += " + " + std::string(info.then);
    } else if (info.done >= info.total && info.total > 0)
        tail += "  " + format_duration(elapsed);
    const int width = terminal_width(m_out);
    // "label [" + bar + "]" + tail, fitted to the terminal (one column spare: no auto-wrap).
    const int bar = std::clamp(width - 1 - int(label.size()) - 3 - int(tail.size()), 0, 50);
    const int filled = static_cast<int>(fraction * bar + 0.5);
    std::string line = label;
    if (bar >= 5) {
        line += " [";
        line.append(std::size_t(filled), '#');
        line.append(std::size_t(bar - filled), '.');
        line += "]";
    }
    line += tail;
    // \r returns to the line start, \x1b[K clears what a longer previous line left behind.
    std::fprintf(m_out, "\r%s\x1b[K", line.c_str());
    std::fflush(m_out);
    m_line_open = true;
}

void ProgressBar::print_plain(const ProgressInfo& info, double elapsed, int percent) {
    const std::string label = this->label(info.stage);
    const double rate = elapsed > 0 ? double(info.done) / elapsed : 0.0;
    const std::string unit(info.unit);
    std::fprintf(m_out, "shprt: %s: %d%% (%s of %s %s, %s%s/s, %s)%s\n", label.c_str(),
                 std::min(percent, 100), format_si(double(info.done)).c_str(),
                 format_si(double(info.total)).c_str(), unit.c_str(), format_si(rate).c_str(),
                 unit.c_str(), format_duration(elapsed).c_str(),
                 info.error_p99 >= 0 ? error_text(info).c_str() : "");
    std::fflush(m_out);
}

void ProgressBar::finish() {
    if (m_line_open && m_out != nullptr) {
        std::fputc('\n', m_out);
        std::fflush(m_out);
    }
    m_line_open = false;
}

}  // namespace shprt::tools
