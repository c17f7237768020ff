// `shprt bake --device` run as a program: `cuda` without a usable GPU (or without a CUDA build) is
// a one-line error, exit ≠ 0 and no output file; with a GPU it bakes on it. `auto` always succeeds,
// on the GPU when there is one, else on the CPU.
#include "shprt/bake/gpu.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

struct RunResult {
    int exit_code;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

class CliDevice : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("shprt_cli_device_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir / "out");
    }
    void TearDown() override { fs::remove_all(m_dir); }

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

TEST_F(CliDevice, CudaWithoutAGpuIsAOneLineError) {
    const shprt::GpuInfo gpu = shprt::query_gpu();
    const std::string file = out("plane.shprt");
    const RunResult r = shprt("bake builtin:plane --device cuda --samples 64 -o '" + file + "'");
    if (gpu.available) {
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(fs::exists(file));
        EXPECT_NE(r.out.find(gpu.name), std::string::npos) << r.out;
        return;
    }
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(r.err, "shprt: error: device 'cuda': " + gpu.reason + "\n");
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_TRUE(out_dir_empty()) << "a failed bake must leave no file";
}

TEST_F(CliDevice, AutoAlwaysBakes) {
    const shprt::GpuInfo gpu = shprt::query_gpu();
    const std::string file = out("plane.shprt");
    const RunResult r = shprt("bake builtin:plane --device auto --samples 64 -o '" + file + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(file));
    // The summary line names the device the bake ran on.
    const std::string device = gpu.available ? gpu.name : std::string("cpu: ");
    EXPECT_NE(r.out.find(device), std::string::npos) << r.out;
}

}  // namespace
