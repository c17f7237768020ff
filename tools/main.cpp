// shprt: precomputed radiance transfer in spherical harmonics. Thin shell over the library: it
// parses arguments, calls the library, reports. One-line errors, non-zero exit codes.
#include "common/command.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>
#include <string>

namespace {

// The one error line and the exit code. Under an MPI launcher a rank other than 0 says nothing and
// exits 0: an error found before the ranks connect (a bad argument) is met by rank 0 too, which
// reports it for the job, and a rank that exits non-zero first would make mpirun kill rank 0
// before it prints. (Errors after the ranks connect are agreed on: dist/mpi_bake.hpp.)
int report_error(const char* what, int exit_code, const char* suffix = "") {
    if (shprt::tools::is_secondary_rank()) return 0;
    shprt::tools::print_error(what, suffix);
    return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"shprt — precomputed radiance transfer in a spherical-harmonics basis"};
    app.set_version_flag("--version", std::string("shprt ") + SHPRT_VERSION_STRING +
                                          (SHPRT_HAS_CUDA ? " (CUDA)" : " (no CUDA)"));
    app.require_subcommand(1);
    std::string log_level = "info";
    app.add_option("--log-level", log_level, "debug, info, warn or error")
        ->check(CLI::IsMember({"debug", "info", "warn", "error"}));

    for (const auto& command : shprt::tools::commands()) {
        CLI::App* sub = app.add_subcommand(command.name, command.description);
        command.setup(*sub);
    }

    auto logger = spdlog::stderr_color_mt("shprt");
    logger->set_pattern("%^%l%$: %v");
    app.parse_complete_callback([&] { logger->set_level(spdlog::level::from_str(log_level)); });
    shprt::set_log_sink([logger](shprt::LogLevel level, std::string_view message) {
        switch (level) {
            case shprt::LogLevel::debug:
                logger->debug("{}", message);
                break;
            case shprt::LogLevel::info:
                logger->info("{}", message);
                break;
            case shprt::LogLevel::warn:
                logger->warn("{}", message);
                break;
            case shprt::LogLevel::error:
                logger->error("{}", message);
                break;
        }
    });

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version end here too (exit code 0): CLI11 prints them.
        if (e.get_exit_code() == 0) return app.exit(e);
        // A usage error: one line like every other error, and exit code 2 (as getopt tools).
        return report_error(e.what(), 2, " (see --help)");
    } catch (const shprt::tools::ExitQuietly& e) {
        return e.exit_code;
    } catch (const shprt::Error& e) {
        return report_error(e.what(), 1);
    } catch (const std::exception& e) {
        return report_error(e.what(), 2);
    }
    return 0;
}
