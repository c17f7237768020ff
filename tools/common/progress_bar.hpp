// Progress display for the `shprt` tools. The library reports progress through a ProgressFn
// (core/progress.hpp); a tool passes ProgressBar::callback() and the bar draws it.
//
//   * Nothing below the info log level (core/log.hpp: the command line's -q, --log-level warn).
//   * On a terminal that takes escape codes (core/terminal.hpp: not TERM=dumb): one line redrawn in
//   place, at most 10 times a
//     second, e.g.
//       bake [##############..............]  48%  51.2 Mrays/s  ETA 3.1 s
//     and where work follows that the stage cannot time yet (ProgressInfo::then), it is named
//     after the ETA: "ETA 3.1 s + 3 bounces" (an interreflected bake's tracing; its bounces'
//     stage then shows the ETA of the whole rest).
//   * Otherwise (a log file, a pipe, CI): one plain line each time 25, 50, 75 and 100 % are
//     passed, e.g. "shprt: bake: 50% (2.41 M of 4.82 M rays, 51.2 Mrays/s, 0.05 s)": prefixed
//     like every other line the tool writes to stderr, so a log read line by line tells the
//     tool's lines apart, and a failure's "shprt: error: ..." line stays the last one.
//
// Ctrl-C: after install_interrupt_handler() (core/interrupt.hpp), the first SIGINT (or SIGTERM,
// SIGHUP) makes the next update() return false, so the library cancels cleanly (no half-written
// output); a second one ends the process at once.
#pragma once

#include "shprt/core/format.hpp"  // format_si, format_duration
#include "shprt/core/interrupt.hpp"
#include "shprt/core/progress.hpp"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace shprt::tools {

class ProgressBar {
public:
    // `label` names the work ("bake"); when empty, each report's stage is shown. With a label,
    // the stages after the first are shown after it ("bake: bounces"). Each new stage starts a new
    // line with its own rate, ETA and percentages. Writes to `out` (stderr by default, so stdout
    // stays clean for results).
    explicit ProgressBar(std::string label = {}, std::FILE* out = stderr);
    // Finishes the line if one was drawn.
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    // Takes one report. Returns false when the user interrupted (see above), true otherwise:
    // the signature of ProgressFn.
    bool update(const ProgressInfo& info);
    // A ProgressFn that forwards to update(); the bar must outlive the operation.
    ProgressFn callback();
    // Ends the in-place line with a newline (terminal) so that later output starts afresh.
    // Idempotent; also called by the destructor.
    void finish();

    bool is_terminal() const { return m_terminal; }

private:
    void draw_terminal(const ProgressInfo& info, double elapsed);
    void print_plain(const ProgressInfo& info, double elapsed, int percent);
    static std::string error_text(const ProgressInfo& info);
    std::string label(std::string_view stage) const;

    std::string m_label;
    std::string m_stage, m_first_stage;  // the stages of the last and the first report
    bool m_started = false;              // a report arrived
    std::FILE* m_out;
    bool m_terminal;
    bool m_line_open = false;  // an in-place line is on screen and not yet ended
    int m_next_plain_percent = 25;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_last_draw{};
};

}  // namespace shprt::tools
