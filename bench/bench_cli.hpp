// The benchmarks' command line, one helper for all (bench_bake, bench_gpu_bake,
// bench_interreflect, bench_glossy): CLI11, as the `shprt` program uses it. Each option is bound
// to its variable, whose value before parse() is the default (shown by --help); the common ones
// (--K, --samples, --reps, --threads) check their range, so a bad value is one line naming the
// option and the problem and exit code 2, as `shprt` does for a command line it cannot use.
//
//     BenchCli cli("bench_glossy", "Glossy bake of the room against its limits");
//     cli.K(a.K).samples(a.samples).reps(a.reps).threads(a.threads);
//     cli.flag("--no-table", a.table, false, "Skip the table of K");
//     cli.parse(argc, argv);
#pragma once

#include "shprt/bake/bake.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace shprt::bench {

class BenchCli {
public:
    BenchCli(std::string name, const std::string& description)
        : m_name(std::move(name)), m_app(description, m_name) {}

    // --K K: the basis size, 1..max (kMaxGlossyCoeffs for a glossy bake).
    BenchCli& K(int& value, int max = kMaxBakeCoeffs) {
        m_app.add_option("--K", value, "Basis size K")
            ->check(CLI::Range(1, max))
            ->capture_default_str();
        return *this;
    }
    // --K K, repeatable: the list of K (empty: the benchmark's own list).
    BenchCli& Ks(std::vector<int>& values) {
        m_app.add_option("--K", values, "Basis size K (repeatable; default: the built-in list)")
            ->check(CLI::Range(1, kMaxBakeCoeffs))
            ->take_all();
        return *this;
    }
    // --samples S: directions, 1..kMaxBakeSamples.
    BenchCli& samples(int& value) {
        m_app.add_option("--samples", value, "Directions S")
            ->check(CLI::Range(1, int(kMaxBakeSamples)))
            ->capture_default_str();
        return *this;
    }
    // --reps N: runs per figure (the minimum is kept), ≥ 1.
    BenchCli& reps(int& value) {
        m_app.add_option("--reps", value, "Runs per figure (the minimum is reported)")
            ->check(CLI::Range(1, 1000000))
            ->capture_default_str();
        return *this;
    }
    // --threads N: worker threads, 0 (all) to kMaxBakeThreads.
    BenchCli& threads(int& value) {
        m_app.add_option("--threads", value, "Worker threads (0 = all)")
            ->check(CLI::Range(0, kMaxBakeThreads))
            ->capture_default_str();
        return *this;
    }
    // A flag that sets `value` to `set_to` when given.
    BenchCli& flag(const std::string& name, bool& value, bool set_to,
                   const std::string& description) {
        m_app.add_flag_callback(
            name, [&value, set_to] { value = set_to; }, description);
        return *this;
    }
    // A flag that runs `action` when given.
    template <typename Action>
    BenchCli& flag(const std::string& name, Action action, const std::string& description) {
        m_app.add_flag_callback(name, std::move(action), description);
        return *this;
    }
    // Any other option, as CLI11 takes it (for its own checks).
    template <typename T>
    CLI::Option* option(const std::string& name, T& value, const std::string& description) {
        return m_app.add_option(name, value, description)->capture_default_str();
    }

    // Parses the command line: --help prints the options and exits 0; a bad one prints
    // "NAME: error: WHAT" on stderr and exits 2.
    void parse(int argc, char** argv) {
        try {
            m_app.parse(argc, argv);
        } catch (const CLI::ParseError& e) {
            if (e.get_exit_code() == 0) std::exit(m_app.exit(e));
            std::fprintf(stderr, "%s: error: %s (see --help)\n", m_name.c_str(), e.what());
            std::exit(2);
        }
    }

private:
    std::string m_name;
    CLI::App m_app;
};

}  // namespace shprt::bench
