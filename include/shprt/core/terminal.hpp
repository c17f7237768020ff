// What a program may write to a terminal, decided in one place for every shell (the command
// line's progress bar and log colours): escape codes only on a terminal whose TERM is not "dumb",
// colour only where escape codes are allowed and NO_COLOR is unset or empty (no-color.org).
// A file, a pipe or CI's log gets plain lines.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace shprt {

// True when `stream` is a terminal (isatty) and the environment's TERM is not "dumb": an in-place
// line ("\r...\x1b[K") may be drawn on it. False for a null stream.
bool terminal_escape_codes(std::FILE* stream);

// terminal_escape_codes(stream), and NO_COLOR unset or empty.
bool terminal_colour(std::FILE* stream);

// `message` as one line, for a program whose every failure is one line: its lines (a driver's
// shader log, a library's list of problems) joined by "; ", each without trailing blanks, the
// empty ones left out.
std::string one_line(std::string_view message);

}  // namespace shprt
