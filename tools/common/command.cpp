#include "common/command.hpp"

#include "common/signals.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace shprt::tools {
namespace {
std::vector<Command>& registry() {
    static std::vector<Command> r;
    return r;
}
}  // namespace

bool register_command(Command command) {
    auto& r = registry();
    r.push_back(std::move(command));
    std::stable_sort(r.begin(), r.end(),
                     [](const Command& a, const Command& b) { return a.order < b.order; });
    return true;
}

const std::vector<Command>& commands() { return registry(); }

void print_error(const char* what, const char* suffix) {
    quiet_signals();  // this is the one error line: a later signal adds none
    std::string message = what;
    while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back())))
        message.pop_back();
    std::string line;
    for (std::size_t start = 0; start <= message.size();) {
        std::size_t end = message.find('\n', start);
        if (end == std::string::npos) end = message.size();
        std::string part = message.substr(start, end - start);
        while (!part.empty() && std::isspace(static_cast<unsigned char>(part.back())))
            part.pop_back();
        if (!part.empty()) line += (line.empty() ? "" : "; ") + part;
        start = end + 1;
    }
    std::fprintf(stderr, "shprt: error: %s%s\n", line.c_str(), suffix);
}

bool is_secondary_rank() {
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) {
        const char* value = std::getenv(name);
        if (value != nullptr) return std::strcmp(value, "0") != 0;
    }
    return false;
}

}  // namespace shprt::tools
