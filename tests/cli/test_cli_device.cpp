// `shprt bake --device` run as a program: `cuda` without a usable GPU (or without a CUDA build) is
// a one-line error, exit ≠ 0 and no output file; with a GPU it bakes on it. `auto` always succeeds,
// on the GPU when there is one, else on the CPU.
#include "shprt/bake/gpu.hpp"

#include "cli/cli_test.hpp"

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

using shprt::test_support::RunResult;
using shprt::test_support::slurp;

class CliDevice : public shprt::test_support::CliTest {};

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
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.err, "shprt: error: device 'cuda': " + gpu.reason + "\n");
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_TRUE(out_dir_empty()) << "a failed bake must leave no file";
}

// --max-device-memory is accepted with --device auto: without a GPU the bake runs on the CPU and
// the budget has nothing to limit; with one, a plane's bake fits 64 MiB of device memory.
TEST_F(CliDevice, AutoTakesADeviceMemoryBudget) {
    const shprt::GpuInfo gpu = shprt::query_gpu();
    const std::string file = out("plane.shprt");
    const RunResult r = shprt(
        "bake builtin:plane --device auto --max-device-memory 64M "
        "--samples 64 -o '" +
        file + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(file));
    const std::string device = gpu.available ? gpu.name : std::string("cpu: ");
    EXPECT_NE(r.out.find(device), std::string::npos) << r.out;
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
