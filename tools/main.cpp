// shprt: precomputed radiance transfer in spherical harmonics. Thin shell over the library: it
// parses arguments, calls the library, reports. One-line errors, non-zero exit codes.
#include "common/command.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <cstdio>
#include <exception>
#include <string>

namespace {

// Every error is one line on stderr: a message that spans lines (a driver's shader log, a
// library's list of problems) has its line breaks turned into "; ".
void print_error(const char* what, const char* suffix = "") {
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
        print_error(e.what(), " (see --help)");
        return 2;
    } catch (const shprt::Error& e) {
        print_error(e.what());
        return 1;
    } catch (const std::exception& e) {
        print_error(e.what());
        return 2;
    }
    return 0;
}
