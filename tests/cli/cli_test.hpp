// Shared pieces for tests that run the real `shprt` binary (SHPRT_CLI_PATH): `run_shprt` runs the
// program with stdout and stderr captured into files (neither is a terminal) and stdin from given
// text or /dev/null; `expect_one_line_error` checks how the program reports a failure; the fixture
// CliTest gives each test a fresh temporary directory with an empty out/ folder.
#pragma once

#include "shprt/core/sanitizers.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace shprt::test_support {

namespace fs = std::filesystem;

struct RunResult {
    // The shell reports a program killed by a signal as 128 + the signal; 128 when the shell
    // itself did not exit normally.
    int exit_code;
    std::string out, err;
};

// The default member initializers let callers name only what they set, `{.input = "1 2 3"}`,
// without -Wmissing-field-initializers warnings.
struct RunOptions {
    std::string prefix = "";  // shell text before the program: `VAR=value`, `xvfb-run -a`
    std::optional<std::string> input = std::nullopt;  // standard input; without it, /dev/null
};

// Shell text (for RunOptions::prefix) that turns LeakSanitizer off for the program it precedes,
// under ASan only; nothing otherwise. For programs whose leaks lie in third-party libraries that
// unload themselves before the process exits — Mesa's GLX driver behind GLFW's window, Open MPI's
// components and PMIx — so that LeakSanitizer reports them with frames in an "<unknown module>"
// that no suppression can name (docs/sanitizers.md). AddressSanitizer and UBSan stay on.
inline std::string without_leak_check() {
    return shprt::kAddressSanitizer
               ? "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\""
               : "";
}

// Whether `name` is a program on the PATH (xvfb-run, mpirun, ...).
inline bool has_program(const char* name) {
    const std::string cmd = std::string("command -v ") + name + " >/dev/null 2>&1";
    return std::system(cmd.c_str()) == 0;
}

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Runs `[PREFIX] shprt ARGS` (ARGS is shell text: quote paths). Writes only the files stdout,
// stderr and, with input, stdin into `work_dir`. A free function so that static suite set-up can
// use it too.
inline RunResult run_shprt(const std::string& args, const fs::path& work_dir,
                           const RunOptions& options = {}) {
    const fs::path out = work_dir / "stdout", err = work_dir / "stderr";
    fs::path in = "/dev/null";
    if (options.input) {
        in = work_dir / "stdin";
        std::ofstream(in, std::ios::binary) << *options.input;
    }
    const std::string cmd = options.prefix + " '" + SHPRT_CLI_PATH + "' " + args + " >'" +
                            out.string() + "' 2>'" + err.string() + "' <'" + in.string() + "'";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, slurp(out), slurp(err)};
}

// The caller's file and line, taken where a default argument is evaluated (the call site). Not
// std::source_location: clang 14 (the sanitizer build, scripts/test) lacks the builtin that
// libstdc++ 12's needs.
struct CallSite {
    CallSite(const char* f = __builtin_FILE(), int l = __builtin_LINE()) : file(f), line(l) {}
    const char* file;
    int line;
};

// Exit code `exit_code`, nothing on stdout, and on stderr exactly one line "shprt: error: ...\n"
// that contains `needle`. Failures name the caller's line, which identifies the case.
inline void expect_error_line(const RunResult& r, const std::string& needle, int exit_code,
                              const CallSite& where) {
    const ::testing::ScopedTrace trace(where.file, where.line,
                                       "expecting a one-line error containing '" + needle + "'");
    EXPECT_EQ(r.exit_code, exit_code) << "stderr: " << r.err;
    EXPECT_EQ(r.out, "") << "stdout of a failed run";
    EXPECT_THAT(r.err, ::testing::StartsWith("shprt: error: "));
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "stderr: " << r.err;
    EXPECT_THAT(r.err, ::testing::EndsWith("\n"));
    EXPECT_THAT(r.err, ::testing::HasSubstr(needle));
}

// A failure of the work (main catches a shprt::Error): exit code 1.
inline void expect_one_line_error(const RunResult& r, const std::string& needle,
                                  CallSite where = {}) {
    expect_error_line(r, needle, 1, where);
}

// A usage error found while parsing the arguments (CLI11): exit code 2, the line ends with
// "(see --help)".
inline void expect_usage_error(const RunResult& r, const std::string& needle, CallSite where = {}) {
    expect_error_line(r, needle, 2, where);
    EXPECT_THAT(r.err, ::testing::EndsWith(" (see --help)\n"));
}

// A failure after which progress or warning lines may stand before the error: exit code
// `exit_code`, nothing on stdout, every stderr line prefixed "shprt: ", exactly one
// "shprt: error: ..." line, the last, and it contains each of `needles`.
inline void expect_failure(const RunResult& r, int exit_code,
                           const std::vector<std::string>& needles, CallSite where = {}) {
    const ::testing::ScopedTrace trace(where.file, where.line, "expecting a failure");
    EXPECT_EQ(r.exit_code, exit_code) << r.err;
    EXPECT_EQ(r.out, "") << "stdout of a failed run";
    std::istringstream lines(r.err);
    std::string line, last;
    int errors = 0;
    while (std::getline(lines, line)) {
        EXPECT_EQ(line.rfind("shprt: ", 0), 0u) << "unprefixed stderr line: " << line;
        errors += line.rfind("shprt: error: ", 0) == 0;
        last = line;
    }
    EXPECT_EQ(errors, 1) << r.err;
    EXPECT_EQ(last.rfind("shprt: error: ", 0), 0u) << r.err;
    for (const std::string& needle : needles)
        EXPECT_NE(last.find(needle), std::string::npos) << "'" << needle << "' not in: " << last;
}

class CliTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() / ("shprt_" + std::string(info->test_suite_name()) + "_" +
                                             std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir / "out");
    }
    void TearDown() override { fs::remove_all(m_dir); }

    // Runs the program in this test's directory (see run_shprt).
    RunResult shprt(const std::string& args, const RunOptions& options = {}) const {
        return run_shprt(args, m_dir, options);
    }

    std::string out(const std::string& name) const { return (m_dir / "out" / name).string(); }
    bool out_dir_empty() const { return fs::is_empty(m_dir / "out"); }

    fs::path m_dir;
};

}  // namespace shprt::test_support
