// Subcommand registry of the `shprt` tool. Each tools/cmd_NAME.cpp registers itself at static
// initialisation:
//
//   static const bool registered = shprt::tools::register_command(
//       {"bake", "Bake per-vertex transfer", 20, [](CLI::App& app) { ...; app.callback(...); }});
//
// `setup` adds options to the subcommand and sets its callback. A callback reports failure by
// throwing shprt::Error (main prints one line and exits 1) or CLI::Error.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace shprt::tools {

struct Command {
    std::string name;
    std::string description;
    int order;  // position in --help (ascending)
    std::function<void(CLI::App&)> setup;
};

bool register_command(Command command);
const std::vector<Command>& commands();

}  // namespace shprt::tools
