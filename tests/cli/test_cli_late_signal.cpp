// Signals once the output is in place, and a write past the file size limit (issue 41, items 1
// and 2). A signal between an output's rename and the end of the run must not say "nothing was
// written": AtomicFile::commit holds the signals across the rename, and the run then finishes
// (exit 0, a warning line) — a second signal ends it with a line saying the file is complete. The
// window is hit every time by the test hook SHPRT_TEST_STOP_AT=renamed (core/file.cpp: the process
// stops itself right after the rename, signals still held); a timed loop checks the same promise
// the way a user meets it. SIGXFSZ (`ulimit -f`) is ignored by the program itself: the write fails
// with EFBIG, one line, no temporary — tested with the signal at its default action.
#include "cli/cli_process.hpp"
#include "cli/cli_test.hpp"
#include "shprt/config.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

using shprt::test_support::RunResult;
using shprt::test_support::slurp;
using shprt::test_support::StartOptions;
using shprt::test_support::wait_stopped;

// Sends `signal` to the stopped program as a user does, to the process. Only the main thread
// takes it: TBB's workers block it (keep_signals_off_workers, core/parallel.hpp), the threads the
// libraries start while they load were started with it blocked (tools/launcher.cpp), and any
// other thread passes it on (src/core/interrupt.cpp). So while the main thread stands in
// AtomicFile::commit's hold the signal waits, and is handled when commit lets it go. Before, a
// worker took it and raced the main thread: the warning came after the summary or never (CI
// failed twice on it; with only the hand-over, 4 runs in 4 here failed on a quiet machine).
void signal_process(pid_t pid, int signal) {
    ASSERT_EQ(::kill(pid, signal), 0) << std::strerror(errno);
}

class CliLateSignal : public shprt::test_support::CliTest {
protected:
    pid_t start(const std::vector<std::string>& args, const StartOptions& how) const {
        return shprt::test_support::start_shprt(m_dir, args, how);
    }
    static void wait_for_main(pid_t pid) { shprt::test_support::wait_for_handlers(pid, SIGTERM); }
    RunResult finish(pid_t pid) const { return shprt::test_support::finish_shprt(m_dir, pid); }
    std::string last_line(const std::string& text) const {
        const std::size_t end = text.size() > 0 && text.back() == '\n' ? text.size() - 1 : 0;
        const std::size_t begin = text.rfind('\n', end > 0 ? end - 1 : 0);
        return text.substr(begin == std::string::npos || end == 0 ? 0 : begin + 1,
                           end - (begin == std::string::npos || end == 0 ? 0 : begin + 1));
    }
    // A small bake to shade and render: made once per test.
    std::string baked() {
        const std::string path = (m_dir / "room.shprt").string();
        if (!fs::exists(path)) {
            EXPECT_EQ(
                shprt("bake builtin:room --coeffs 16 --samples 32 -o '" + path + "'").exit_code, 0);
        }
        return path;
    }
    // The commands that write an output, each with -o OUTPUT appended by the caller.
    std::vector<std::vector<std::string>> writers() {
        std::vector<std::vector<std::string>> all = {
            {"bake", "builtin:plane", "--samples", "16", "--coeffs", "4", "--reproducible"},
            {"bake", "builtin:plane", "--samples", "16", "--coeffs", "4", "--reproducible",
             "--stream"},
        };
        if (SHPRT_HAS_RENDER) {  // shade and render come with the renderer
            const std::string room = baked();
            all.push_back({"shade", room, "--light", "constant:1"});
            all.push_back({"render", room, "--light", "constant:1", "--size", "64x48"});
        }
        return all;
    }
    static std::string extension(const std::vector<std::string>& args) {
        return args[0] == "shade" ? ".csv" : args[0] == "render" ? ".png" : ".shprt";
    }
};

std::vector<std::string> with_output(std::vector<std::string> args, const std::string& output) {
    args.push_back("-o");
    args.push_back(output);
    return args;
}

// Every writing command, every interrupt signal, sent while the process stands right after the
// rename (signals held): the run finishes, exit status 0, the complete file in place, a warning
// that names the signal — never "nothing was written".
TEST_F(CliLateSignal, SignalRightAfterTheRenameLetsTheRunFinish) {
    for (const std::vector<std::string>& args : writers()) {
        const std::string output = out("late" + extension(args));
        const std::string reference = (m_dir / ("reference" + extension(args))).string();
        ASSERT_EQ(::waitpid(start(with_output(args, reference), {}), nullptr, 0) > 0, true);
        for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
            SCOPED_TRACE(args[0] + (args.back() == "--stream" ? " --stream" : "") + ", signal " +
                         std::to_string(signal));
            fs::remove(output);
            const pid_t pid = start(with_output(args, output), {.stop_at = "renamed"});
            ASSERT_TRUE(wait_stopped(pid)) << "the test hook did not stop the process";
            EXPECT_TRUE(fs::exists(output));  // renamed into place
            signal_process(pid, signal);
            ::kill(pid, SIGCONT);
            const RunResult r = finish(pid);
            EXPECT_EQ(r.exit_code, 0) << r.err;
            EXPECT_EQ(r.err.find("nothing was written"), std::string::npos) << r.err;
            EXPECT_NE(last_line(r.err).find("arrived after " + output + " was written"),
                      std::string::npos)
                << r.err;
            ASSERT_TRUE(fs::exists(output));
            if (args[0] != "render") {
                EXPECT_EQ(slurp(output), slurp(reference));
            }
            EXPECT_EQ(fs::file_size(output), fs::file_size(reference));
        }
        // Two signals: the second ends the run at once, and says the file is complete.
        fs::remove(output);
        const pid_t pid = start(with_output(args, output), {.stop_at = "renamed"});
        ASSERT_TRUE(wait_stopped(pid));
        signal_process(pid, SIGTERM);
        signal_process(pid, SIGINT);
        ::kill(pid, SIGCONT);
        const RunResult r = finish(pid);
        EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 130 || r.exit_code == 143) << r.err;
        if (r.exit_code != 0) {
            EXPECT_NE(last_line(r.err).find(" after " + output + " was written (it is complete)"),
                      std::string::npos)
                << r.err;
        }
        EXPECT_EQ(r.err.find("nothing was written"), std::string::npos) << r.err;
        EXPECT_TRUE(fs::exists(output));
    }
}

// The loop, at timed moments around the end of `shade`: whenever the file is in place the
// run succeeded, and whenever the run says it was interrupted nothing is there.
TEST_F(CliLateSignal, TimedSignalsNeverContradictTheOutput) {
    if (!SHPRT_HAS_RENDER) GTEST_SKIP() << "`shade` comes with the renderer (SHPRT_RENDER=OFF)";
    const std::vector<std::string> args = {"shade", baked(), "--light", "constant:1"};
    const std::string output = out("s.csv");
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(finish(start(with_output(args, output), {})).exit_code, 0);
    const auto run_us =
        std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0)
            .count();
    std::mt19937 random(41);
    std::uniform_int_distribution<long> delay(run_us / 2, run_us * 5 / 4);
    int interrupted = 0, finished = 0;
    for (int i = 0; i < 30; ++i) {
        fs::remove(output);
        const pid_t pid = start(with_output(args, output), {});
        wait_for_main(pid);
        std::this_thread::sleep_for(std::chrono::microseconds(delay(random)));
        ::kill(pid, SIGTERM);
        const RunResult r = finish(pid);
        SCOPED_TRACE("run " + std::to_string(i) + ": " + r.err);
        EXPECT_TRUE(r.exit_code == 0 || r.err.rfind("shprt: ", 0) == 0) << "ended without a line";
        if (r.exit_code == 0) {
            ++finished;
            EXPECT_TRUE(fs::exists(output));
        } else {
            ++interrupted;
            EXPECT_EQ(r.exit_code, 128 + SIGTERM);
            if (r.err.find("nothing was written") != std::string::npos) {
                EXPECT_FALSE(fs::exists(output));
            } else {
                EXPECT_NE(r.err.find("(it is complete)"), std::string::npos);
            }
        }
    }
    std::printf("timed SIGTERM: %d interrupted, %d finished\n", interrupted, finished);
}

// `ulimit -f` with SIGXFSZ at its default action (no `trap '' XFSZ`: the program ignores it
// itself): the write fails with EFBIG, one line naming the file, nothing left.
TEST_F(CliLateSignal, FileSizeLimitIsOneLineAndLeavesNothing) {
    for (const char* mode : {"", "--stream", "--half"}) {
        SCOPED_TRACE(mode);
        const std::string output = out("fs.shprt");
        std::vector<std::string> args = {"bake", "builtin:room", "--coeffs",
                                         "32",   "--samples",    "64"};
        if (*mode) args.push_back(mode);
        const RunResult r =
            finish(start(with_output(args, output), {.stop_at = "", .file_size_limit = 64 * 1024}));
        shprt::test_support::expect_failure(r, 1, {"cannot write " + output, "File too large"});
        EXPECT_TRUE(out_dir_empty());
    }
}

}  // namespace
