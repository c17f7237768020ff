// The command line's options from a library option table (core/options.hpp): one CLI11 option per
// row, `--name-text`, writing into the row's field of `target` (which must outlive the parse);
// the rows named in `leave_out` are not added, and where `only` is given, only the rows it names
// (in the table's order, so that a command can place a table's rows among its other options).
// A row marked hidden is left out of the help.
// The help shows the row's limits and default after the type (`INT:[1 to 16777216]=1024`); the
// values are checked by the library function the table belongs to, not by CLI11.
#pragma once

#include "shprt/core/options.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

namespace shprt::tools {

template <class Struct>
void add_table_options(CLI::App& app, const std::vector<OptionRow<Struct>>& table, Struct& target,
                       const std::vector<std::string>& leave_out = {},
                       const std::vector<std::string>& only = {}) {
    const auto named = [](const std::vector<std::string>& names, const std::string& name) {
        return std::find(names.begin(), names.end(), name) != names.end();
    };
    for (const OptionRow<Struct>& row : table) {
        if (named(leave_out, row.name) || (!only.empty() && !named(only, row.name))) continue;
        std::visit(
            [&](auto member) {
                auto& field = target.*member;
                std::string name = "--" + row.name;
                std::replace(name.begin(), name.end(), '_', '-');
                CLI::Option* option = nullptr;
                if constexpr (std::is_same_v<std::decay_t<decltype(field)>, bool>) {
                    option = app.add_flag(name, field, row.help);
                } else {
                    option = app.add_option(name, field, row.help);
                    if (!row.limits_text.empty())
                        option->check(CLI::Validator([](std::string&) { return std::string(); },
                                                     "[" + row.limits_text + "]"));
                    option->default_str(row.default_text);
                }
                if (row.hidden) option->group("");
            },
            row.field);
    }
}

}  // namespace shprt::tools
