// Every numeric option of the `shprt` tools is read by core/parse.hpp, not by CLI11's own
// conversion (which reads "010" as 8, takes hexadecimal, saturates 99999999999999999999 to
// 2^63 - 1 and wraps "-1" into 2^64 - 1 for unsigned options). check_numeric_options walks a
// fully set-up command tree and gives each integer and floating-point option a check that runs on
// the text before CLI11 converts it.
//
// A bad value is an Error(invalid_argument) naming the option and the text, in one line, exactly
// like a value outside an option's own range (exit code 1 for both, see tools/main.cpp):
//   --samples 'abc': not an integer
//   --samples 99999999999999999999: out of range
//   --seed -1: must not be negative
//   --k 'nan': not a finite number
#pragma once

#include <CLI/CLI.hpp>

namespace shprt::tools {

// Adds the checks to every option of `app` and of its subcommands, recursively, whose CLI11 type
// is an integer (INT, UINT) or floating point (FLOAT). Call once, after every command's setup.
void check_numeric_options(CLI::App& app);

// Shows every value option's default in the help (`--uv-set INT=0`), from the variable it writes
// into, where the option has not set one itself (option_table.hpp does): so that the help says
// what a command takes when an option is left out, and the test of the front ends' defaults
// (python/tests/test_option_table.py) can read it. Flags are left alone. Call once, after every
// command's setup.
void show_defaults(CLI::App& app);

}  // namespace shprt::tools
