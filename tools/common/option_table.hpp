// The command line's options from a library option table (core/options.hpp): one CLI11 option per
// row, `--name-text`, writing into the row's field of `target` (which must outlive the parse);
// the rows named in `leave_out` are not added.
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
                       const std::vector<std::string>& leave_out = {}) {
    for (const OptionRow<Struct>& row : table) {
        if (std::find(leave_out.begin(), leave_out.end(), row.name) != leave_out.end()) continue;
        std::visit(
            [&](auto member) {
                auto& field = target.*member;
                std::string name = "--" + row.name;
                std::replace(name.begin(), name.end(), '_', '-');
                if constexpr (std::is_same_v<std::decay_t<decltype(field)>, bool>) {
                    app.add_flag(name, field, row.help);
                } else {
                    CLI::Option* option = app.add_option(name, field, row.help);
                    if (!row.limits_text.empty())
                        option->check(CLI::Validator([](std::string&) { return std::string(); },
                                                     "[" + row.limits_text + "]"));
                    option->default_str(row.default_text);
                }
            },
            row.field);
    }
}

}  // namespace shprt::tools
