// shprt: precomputed radiance transfer in spherical harmonics. Thin shell over the library: it
// parses arguments, calls the library, reports. One-line errors, non-zero exit codes.
#include "common/command.hpp"
#include "common/number_options.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/interrupt.hpp"
#include "shprt/core/job.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/terminal.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>
#include <new>
#include <string>

namespace {

// The one error line and the exit code. Under an MPI launcher a rank other than 0 says nothing and
// exits 0: an error found before the ranks connect (a bad argument) is met by rank 0 too, which
// reports it for the job, and a rank that exits non-zero first would make mpirun kill rank 0
// before it prints. (Errors after the ranks connect are agreed on: dist/mpi_bake.hpp.)
int report_error(const char* what, int exit_code, const char* suffix = "") {
    if (shprt::is_secondary_rank()) return 0;
    shprt::tools::print_error(what, suffix);
    return exit_code;
}

// CLI11 says "Could not convert: --coeffs = 99999999999" when a number that passed
// check_numeric_options does not fit its option's type (an int): say it as the range checks do.
std::string value_error_message(const std::string& what) {
    static const std::string kPrefix = "Could not convert: ";
    const std::size_t equals = what.find(" = ");
    if (what.rfind(kPrefix, 0) != 0 || equals == std::string::npos) return what;
    return what.substr(kPrefix.size(), equals - kPrefix.size()) + " " + what.substr(equals + 3) +
           ": out of range";
}

// "interrupted by SIGINT; nothing was written", exit status 128 + the signal (core/interrupt.hpp).
int report_interrupted(int signal) {
    const std::string what =
        std::string("interrupted by ") + shprt::signal_name(signal) + "; nothing was written";
    return report_error(what.c_str(), shprt::interrupted_exit_code(signal));
}

}  // namespace

// The command line's entry, called by the `shprt` program (launcher.cpp) once the libraries are
// loaded; `early_signal` says which signal arrived while they loaded (0: none).
extern "C" __attribute__((visibility("default"))) int shprt_main(int argc, char** argv,
                                                                 int (*early_signal)()) {
    // First of all: from here on a signal never ends the process without its one line, and one
    // that arrived before (held by the launcher) ends it now, before anything is read or written.
    shprt::install_signal_handlers();
    if (const int signal = early_signal()) return report_interrupted(signal);
    // TBB's workers have exited when shprt_main returns (core/parallel.hpp).
    const shprt::WorkerThreads workers;
    using shprt::tools::check_numeric_options;
    // Named, so that usage lines say "shprt bake", not the path the program was run by.
    CLI::App app{"shprt — precomputed radiance transfer in a spherical-harmonics basis", "shprt"};
    app.set_version_flag("--version", std::string("shprt ") + SHPRT_VERSION_STRING +
                                          (SHPRT_HAS_CUDA ? " (CUDA)" : " (no CUDA)"));
    app.require_subcommand(1);
    app.fallthrough();  // the options below are taken after the subcommand too
    std::string log_level = "info";
    auto* log_level_option =
        app.add_option("--log-level", log_level,
                       "debug, info, warn or error; taken after the subcommand too")
            ->check(CLI::IsMember({"debug", "info", "warn", "error"}));
    auto* quiet = app.add_flag_callback(
        "-q,--quiet", [&] { log_level = "warn"; }, "Warnings and errors only, no progress");
    auto* verbose = app.add_flag_callback(
        "-v,--verbose", [&] { log_level = "debug"; }, "Debug messages too");
    quiet->excludes(log_level_option)->excludes(verbose);
    verbose->excludes(log_level_option);

    for (const auto& command : shprt::tools::commands()) {
        CLI::App* sub = app.add_subcommand(command.name, command.description);
        command.setup(*sub);
    }
    check_numeric_options(app);
    shprt::tools::show_defaults(app);

    // Every line on stderr starts with "shprt: " (README, "The command line"): warnings are
    // "shprt: warning: ...", errors "shprt: error: ...". Colour as core/terminal.hpp decides.
    auto logger = spdlog::stderr_color_mt("shprt", shprt::terminal_colour(stderr)
                                                       ? spdlog::color_mode::always
                                                       : spdlog::color_mode::never);
    logger->set_pattern("shprt: %^%l%$: %v");
    logger->set_level(spdlog::level::trace);  // the library's log level filters (core/log.hpp)
    app.parse_complete_callback([&] { shprt::set_log_level(shprt::parse_log_level(log_level)); });
    shprt::set_log_sink([logger](shprt::LogLevel level, std::string_view message) {
        using spdlog::level::level_enum;
        constexpr level_enum kLevels[] = {level_enum::debug, level_enum::info, level_enum::warn,
                                          level_enum::err};
        logger->log(kLevels[static_cast<int>(level)], "{}", message);
    });

    // Exit codes, one rule (README, "The command line"): 2 when the command line cannot be
    // parsed (an unknown option or subcommand, a missing or extra argument); 1 for every other
    // failure, a bad option value included, whether it is not a number, out of its range or
    // not one of the allowed words.
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version end here too (exit code 0): CLI11 prints them.
        if (e.get_exit_code() == 0) return app.exit(e);
        // A value CLI11 itself refused (a number too large for its option's type, a word not in
        // an option's list): a bad value like any other.
        if (dynamic_cast<const CLI::ConversionError*>(&e) ||
            dynamic_cast<const CLI::ValidationError*>(&e)) {
            return report_error(value_error_message(e.what()).c_str(), 1);
        }
        // A usage error: one line like every other error, and exit code 2 (as getopt tools).
        return report_error(shprt::tools::usage_error_message(app, e).c_str(), 2, " (see --help)");
    } catch (const shprt::tools::ExitQuietly& e) {
        return e.exit_code;
    } catch (const shprt::Interrupted& e) {
        return report_interrupted(e.signal);
    } catch (const std::bad_alloc&) {
        return report_error("out of memory (an allocation failed)", 1);
    } catch (const std::exception& e) {
        // A computation the signal cancelled (Error(cancelled)) reports the signal.
        if (shprt::interrupted()) return report_interrupted(shprt::interrupt_signal());
        return report_error(e.what(), 1);
    }
    // A signal that arrived once the output was in place: the run finished (core/interrupt.hpp).
    shprt::report_late_signal();
    return 0;
}
