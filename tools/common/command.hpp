// Subcommand registry of the `shprt` tool. Each tools/cmd_NAME.cpp registers itself at static
// initialisation, under a name of its own (unity builds put several commands in one file):
//
//   static const bool bake_registered = shprt::tools::register_command(
//       {"bake", "Bake per-vertex transfer", 20, [](CLI::App& app) { ...; app.callback(...); }});
//
// `setup` adds options to the subcommand and sets its callback. A callback reports failure by
// throwing shprt::Error (main prints one line and exits 1) or CLI::Error; ExitQuietly ends a
// process whose failure another process reports (the other ranks of an MPI job: rank 0 prints).
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

struct ExitQuietly {
    int exit_code = 1;
};

// Prints "shprt: error: WHAT[SUFFIX]" as one line on stderr: a message that spans lines (a
// driver's shader log, a library's list of problems) has its line breaks turned into "; ".
void print_error(const char* what, const char* suffix = "");

// The message of a usage error: for a word the command line does not know, "unknown command
// 'bkae'; did you mean 'bake'?" or "unknown option '--coefs'; did you mean '--coeffs'?" (among
// the options of the subcommand given and the ones above it); CLI11's own otherwise.
std::string usage_error_message(const CLI::App& app, const CLI::ParseError& error);

bool register_command(Command command);
const std::vector<Command>& commands();

}  // namespace shprt::tools
