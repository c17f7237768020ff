// What a program may write to a terminal (core/terminal.hpp).
#include "shprt/core/terminal.hpp"

#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <cstring>

namespace shprt {

bool terminal_escape_codes(std::FILE* stream) {
    if (stream == nullptr || ::isatty(::fileno(stream)) == 0) return false;
    const char* term = std::getenv("TERM");
    return term == nullptr || std::strcmp(term, "dumb") != 0;
}

bool terminal_colour(std::FILE* stream) {
    const char* no_colour = std::getenv("NO_COLOR");
    return terminal_escape_codes(stream) && (no_colour == nullptr || no_colour[0] == '\0');
}

std::string one_line(std::string_view message) {
    std::string line;
    for (std::size_t start = 0; start <= message.size();) {
        std::size_t end = message.find('\n', start);
        if (end == std::string_view::npos) end = message.size();
        std::string_view part = message.substr(start, end - start);
        while (!part.empty() && std::isspace(static_cast<unsigned char>(part.back())))
            part.remove_suffix(1);
        if (!part.empty()) (line += line.empty() ? "" : "; ") += part;
        start = end + 1;
    }
    return line;
}

}  // namespace shprt
