// Shared fixture for tests that run the real `shprt` binary (SHPRT_CLI_PATH): a fresh temporary
// directory per test with an empty out/ folder, and `shprt(ARGS)` running the program with stdout
// and stderr captured into files (neither is a terminal) and no standard input.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace shprt::test_support {

namespace fs = std::filesystem;

struct RunResult {
    int exit_code;  // 128 when the program did not exit normally (a crash)
    std::string out, err;
};

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
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

    // Runs `shprt ARGS` (ARGS is shell text: quote paths).
    RunResult shprt(const std::string& args) {
        const std::string cmd = std::string("'") + SHPRT_CLI_PATH + "' " + args + " >'" +
                                (m_dir / "stdout").string() + "' 2>'" +
                                (m_dir / "stderr").string() + "' </dev/null";
        const int status = std::system(cmd.c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, slurp(m_dir / "stdout"),
                slurp(m_dir / "stderr")};
    }

    std::string out(const std::string& name) const { return (m_dir / "out" / name).string(); }
    bool out_dir_empty() const { return fs::is_empty(m_dir / "out"); }

    fs::path m_dir;
};

}  // namespace shprt::test_support
