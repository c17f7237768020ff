#include "common/command.hpp"

#include "shprt/core/interrupt.hpp"

#include "shprt/core/names.hpp"
#include "shprt/core/terminal.hpp"

#include <algorithm>
#include <cstdio>

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

std::string usage_error_message(const CLI::App& app, const CLI::ParseError& error) {
    const std::vector<std::string> unknown = app.remaining(true);
    if (unknown.empty()) return error.what();
    const CLI::App* scope = &app;  // the innermost subcommand given
    while (!scope->get_subcommands().empty()) scope = scope->get_subcommands().front();
    std::string word = unknown.front();
    const bool option = word.size() > 1 && word[0] == '-';
    std::vector<std::string> names;
    if (option) {
        word = word.substr(0, word.find('='));
        for (const CLI::App* a = scope; a != nullptr; a = a->get_parent())
            for (const CLI::Option* o : a->get_options()) {
                for (const std::string& name : o->get_lnames()) names.push_back("--" + name);
                for (const std::string& name : o->get_snames()) names.push_back("-" + name);
            }
    } else {
        for (const CLI::App* sub : scope->get_subcommands({})) names.push_back(sub->get_name());
        if (names.empty()) return error.what();  // an argument too many
    }
    return unknown_name_message(option ? "option" : "command", word, {names.begin(), names.end()});
}

void print_error(const char* what, const char* suffix) {
    quiet_signals();  // this is the one error line: a later signal adds none
    std::fprintf(stderr, "shprt: error: %s%s\n", one_line(what).c_str(), suffix);
}

}  // namespace shprt::tools
