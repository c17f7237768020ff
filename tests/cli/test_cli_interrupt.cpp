// Interrupted and failing bakes (issue 15): signals at known moments (the program stops itself at
// a named point when SHPRT_TEST_STOP_AT says so: core/interrupt.hpp) and at timed ones, SIGKILL
// and the temporaries it leaves, checkpoints and resumes that end in the uninterrupted bake's
// bytes, the memory estimate, and a write that fails (a file size limit). Every failure: its exit
// code, one last line "shprt: error: ...", no output file and no temporary.
#include "cli/cli_process.hpp"
#include "cli/cli_test.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

using shprt::test_support::expect_one_line_error;
using shprt::test_support::RunResult;
using shprt::test_support::slurp;
using shprt::test_support::wait_stopped;

// A bake of a few tenths of a second on one thread: long enough to be interrupted while it runs.
const std::vector<std::string> kBake = {"bake", "builtin:room",  "--samples", "256", "--threads",
                                        "1",    "--reproducible"};

class CliInterrupt : public shprt::test_support::CliTest {
protected:
    // `shprt ARGS` in the background (cli_process.hpp), stopping itself at `stop_at` when given.
    pid_t start(const std::vector<std::string>& args, const std::string& stop_at = "") const {
        return shprt::test_support::start_shprt(m_dir, args, {.stop_at = stop_at});
    }
    static void wait_for_main(pid_t pid) { shprt::test_support::wait_for_handlers(pid, SIGINT); }
    RunResult finish(pid_t pid) const { return shprt::test_support::finish_shprt(m_dir, pid); }
    // Sends `signal` to a stopped program and lets it go on.
    static void signal_stopped(pid_t pid, int signal) {
        ::kill(pid, signal);
        ::kill(pid, SIGCONT);
    }
    std::vector<std::string> out_files() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(m_dir / "out"))
            names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
    // An interrupted run: exit 128 + signal, every stderr line prefixed, the last the error line
    // that contains `needle`, nothing on stdout.
    static void expect_interrupted(const RunResult& r, int signal, const std::string& needle) {
        expect_failure(r, 128 + signal, needle);
    }
    static void expect_failure(const RunResult& r, int code, const std::string& needle) {
        shprt::test_support::expect_failure(r, code, {needle});
    }
    static std::vector<std::string> with(std::vector<std::string> args,
                                         const std::vector<std::string>& more) {
        args.insert(args.end(), more.begin(), more.end());
        return args;
    }
    // The uninterrupted bake's file, to compare resumed ones with.
    // `args` as one command line, with a space after each.
    static std::string joined(const std::vector<std::string>& args) {
        std::string cmd;
        for (const std::string& a : args) cmd += a + " ";
        return cmd;
    }
    // The bytes of the uninterrupted bake `args`.
    std::string reference(const std::vector<std::string>& args = kBake) const {
        const std::string ref = (m_dir / "reference.shprt").string();
        EXPECT_EQ(shprt(joined(args) + "-o '" + ref + "'").exit_code, 0);
        return slurp(ref);
    }
    // Runs `args --checkpoint ckpt -o output` until it stops after its bake (the test hook),
    // kills it with SIGKILL and returns the checkpoint's bytes; nothing may be left in out/.
    std::string kill_after_bake(const std::vector<std::string>& args, const std::string& ckpt,
                                const std::string& output) {
        const pid_t pid = start(with(args, {"--checkpoint", ckpt, "-o", output}), "write");
        const bool stopped = wait_stopped(pid);
        ::kill(pid, SIGKILL);
        finish(pid);
        EXPECT_TRUE(stopped);
        EXPECT_TRUE(out_dir_empty());
        return slurp(ckpt);
    }
};

// From the first moment of main() on, a signal ends the process with its one line: at timed
// moments from its start (loading, baking) and from every point of a scripted bake.
TEST_F(CliInterrupt, SignalsAtAnyTimeEndWithOneLineAndNothingWritten) {
    const std::string output = out("a.shprt");
    int interrupted = 0;
    for (const int signal : {SIGINT, SIGTERM}) {
        for (const int delay_ms : {0, 1, 3, 10, 30, 100}) {
            SCOPED_TRACE("signal " + std::to_string(signal) + " after " + std::to_string(delay_ms) +
                         " ms");
            const pid_t pid = start(with(kBake, {"--stream", "-o", output}));
            wait_for_main(pid);
            std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
            ::kill(pid, signal);
            const RunResult r = finish(pid);
            if (r.exit_code == 0) {  // it finished first: fine
                fs::remove(output);
                continue;
            }
            ++interrupted;
            expect_interrupted(r, signal, "interrupted by SIG");
            EXPECT_TRUE(out_dir_empty()) << ::testing::PrintToString(out_files());
        }
    }
    EXPECT_GE(interrupted, 6) << "too few runs were interrupted to test anything";
}

// A signal while the command line's libraries load (the launcher's stop point "load": Assimp,
// Embree, TBB, OpenBLAS, GL and MPI are about to be loaded, 20 to 300 ms on a busy machine) is held
// and reported as every other interruption: the one line, 128 + the signal, nothing written.
TEST_F(CliInterrupt, SignalWhileTheLibrariesLoadEndsWithItsLine) {
    const std::string output = out("a.shprt");
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
        SCOPED_TRACE("signal " + std::to_string(signal));
        const pid_t pid = start(with(kBake, {"-o", output}), "load");
        ASSERT_TRUE(wait_stopped(pid));
        signal_stopped(pid, signal);
        expect_interrupted(finish(pid), signal, "interrupted by SIG");
        EXPECT_TRUE(out_dir_empty()) << ::testing::PrintToString(out_files());
    }
}

TEST_F(CliInterrupt, SignalAfterTracingStopsBeforeWriting) {
    const std::string output = out("a.shprt");
    for (const char* point : {"bake", "write", "writing"}) {
        for (const bool stream : {false, true}) {
            for (const int signal : {SIGINT, SIGTERM}) {
                SCOPED_TRACE(std::string("at ") + point + (stream ? " --stream" : "") + " signal " +
                             std::to_string(signal));
                std::vector<std::string> args = with(kBake, {"-o", output});
                if (stream) args.push_back("--stream");
                const pid_t pid = start(args, point);
                ASSERT_TRUE(wait_stopped(pid));
                // With --stream the temporary exists while the bake runs (and nothing else).
                const std::vector<std::string> files = out_files();
                EXPECT_EQ(files.size(), stream ? 1u : 0u);
                signal_stopped(pid, signal);
                expect_interrupted(finish(pid), signal,
                                   std::string("interrupted by ") +
                                       (signal == SIGINT ? "SIGINT" : "SIGTERM") +
                                       "; nothing was written");
                EXPECT_TRUE(out_dir_empty()) << ::testing::PrintToString(out_files());
            }
        }
    }
}

// SIGKILL while the output is written leaves its temporary; the next run to the same output
// removes it and says so in one warning line.
TEST_F(CliInterrupt, TheNextRunRemovesATemporaryThatAKilledRunLeft) {
    const std::string output = out("a.shprt");
    const pid_t pid = start(with(kBake, {"--stream", "-o", output}), "writing");
    ASSERT_TRUE(wait_stopped(pid));
    ::kill(pid, SIGKILL);
    EXPECT_EQ(finish(pid).exit_code, 128 + SIGKILL);
    const std::vector<std::string> left = out_files();
    ASSERT_EQ(left.size(), 1u);
    EXPECT_EQ(left[0].rfind("a.shprt.tmp." + std::to_string(pid) + ".", 0), 0u) << left[0];
    // A temporary of a process that still runs (this test's) is not touched.
    const std::string alive = output + ".tmp." + std::to_string(::getpid()) + ".0";
    std::ofstream(alive) << "x";

    const RunResult r = shprt(joined(kBake) + "-o '" + output + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("shprt: warning: removed " + (m_dir / "out" / left[0]).string() +
                         ", left by a run that was killed"),
              std::string::npos)
        << r.err;
    const std::vector<std::string> files = out_files();
    EXPECT_EQ(files, (std::vector<std::string>{"a.shprt", fs::path(alive).filename().string()}));
}

// A checkpointed bake killed (SIGKILL) at several points resumes to the uninterrupted bake's
// bytes: the points are cuts of a whole checkpoint (after its header, inside a record's head,
// inside its rows, one byte short, whole) and kills at timed moments.
TEST_F(CliInterrupt, KilledCheckpointedBakesResumeToTheSameBytes) {
    const std::string expected = reference();
    const std::string output = out("a.shprt"), ckpt = (m_dir / "a.ckpt").string();
    const std::string whole = kill_after_bake(kBake, ckpt, output);
    ASSERT_GT(whole.size(), 64u + 32u);
    const std::string resume_cmd = joined(kBake) + "--resume '" + ckpt + "' -o '" + output + "'";
    for (const std::size_t cut : {std::size_t(64), std::size_t(64 + 20), std::size_t(64 + 32 + 100),
                                  whole.size() / 2, whole.size() - 1, whole.size()}) {
        SCOPED_TRACE("checkpoint cut at " + std::to_string(cut) + " of " +
                     std::to_string(whole.size()));
        std::ofstream(ckpt, std::ios::binary).write(whole.data(), std::streamsize(cut));
        const RunResult r = shprt(resume_cmd);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(slurp(output) == expected) << "resumed bake differs from the uninterrupted one";
        EXPECT_FALSE(fs::exists(ckpt)) << "the checkpoint outlived its bake";
        fs::remove(output);
    }
    for (const int delay_ms : {20, 80, 200}) {
        SCOPED_TRACE("SIGKILL after " + std::to_string(delay_ms) + " ms");
        const pid_t p = start(with(kBake, {"--checkpoint", ckpt, "-o", output}));
        std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
        ::kill(p, SIGKILL);
        if (finish(p).exit_code == 0) {  // it finished first
            fs::remove(output);
            continue;
        }
        // A SIGKILL cannot be handled: it may leave a temporary (the next run removes it:
        // TheNextRunRemovesATemporaryThatAKilledRunLeft) or, killed after the rename, the complete
        // output — never a partial file under the output's name.
        for (const std::string& file : out_files()) {
            if (file == fs::path(output).filename().string())
                EXPECT_TRUE(slurp(output) == expected) << "a killed bake left a partial output";
            else
                EXPECT_NE(file.find(".tmp."), std::string::npos) << file;
        }
        if (!fs::exists(ckpt)) continue;  // killed before the checkpoint existed, or after the end
        const RunResult r = shprt(resume_cmd);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(slurp(output) == expected) << "resumed bake differs from the uninterrupted one";
        fs::remove(output);
    }
}

// SIGINT and SIGTERM during a checkpointed bake: the checkpoint is kept, the line says how to
// resume, exit 130/143, no output; the resume ends in the uninterrupted bake's bytes.
TEST_F(CliInterrupt, InterruptedCheckpointedBakeSaysHowToResume) {
    const std::string expected = reference();
    const std::string output = out("a.shprt"), ckpt = (m_dir / "a.ckpt").string();
    for (const int signal : {SIGINT, SIGTERM}) {
        const pid_t pid = start(with(kBake, {"--checkpoint", ckpt, "-o", output}), "bake");
        ASSERT_TRUE(wait_stopped(pid));
        signal_stopped(pid, signal);
        expect_interrupted(finish(pid), signal, "--resume " + ckpt);
        EXPECT_TRUE(out_dir_empty());
        ASSERT_TRUE(fs::exists(ckpt));
        const std::string cmd = joined(kBake);
        // A second --checkpoint to the same file would overwrite it: refused.
        expect_one_line_error(shprt(cmd + "--checkpoint '" + ckpt + "' -o '" + output + "'"),
                              "a checkpoint exists; continue its bake with --resume");
        const RunResult r = shprt(cmd + "--resume '" + ckpt + "' -o '" + output + "'");
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(slurp(output) == expected);
        EXPECT_FALSE(fs::exists(ckpt));
        fs::remove(output);
    }
}

// A checkpoint resumes only the bake that made it; bakes that cannot resume refuse a checkpoint.
TEST_F(CliInterrupt, ResumeOfAnotherBakeAndUnresumableBakesAreRefused) {
    const std::string output = out("a.shprt"), ckpt = (m_dir / "a.ckpt").string();
    const pid_t pid = start(with(kBake, {"--checkpoint", ckpt, "-o", output}), "bake");
    ASSERT_TRUE(wait_stopped(pid));
    ::kill(pid, SIGKILL);
    finish(pid);
    ASSERT_TRUE(fs::exists(ckpt));
    const std::string resume = "--resume '" + ckpt + "' -o '" + output + "'";
    for (const char* other :
         {"bake builtin:room --samples 256 --seed 2 ", "bake builtin:room --samples 128 ",
          "bake builtin:room --samples 256 --coeffs 9 ", "bake builtin:plane --samples 256 ",
          "bake builtin:room --samples 256 --transfer unshadowed "}) {
        SCOPED_TRACE(other);
        expect_one_line_error(shprt(other + resume), "the checkpoint is of another bake");
        EXPECT_TRUE(out_dir_empty());
    }
    std::ofstream(m_dir / "junk.ckpt") << "not a checkpoint at all, but long enough for a header "
                                          "of sixty-four bytes to be read from it";
    expect_one_line_error(shprt("bake builtin:room --resume '" + (m_dir / "junk.ckpt").string() +
                                "' -o '" + output + "'"),
                          "not a shprt checkpoint");
    expect_one_line_error(shprt("bake builtin:room --resume '" + (m_dir / "none.ckpt").string() +
                                "' -o '" + output + "'"),
                          "none.ckpt");
    expect_one_line_error(shprt("bake builtin:room --transfer interreflected --checkpoint '" +
                                (m_dir / "b.ckpt").string() + "' -o '" + output + "'"),
                          "interreflected transfer cannot be checkpointed");
    for (const char* receivers : {"--domain texel --resolution 32 ", "--refine 0.01 "})
        expect_one_line_error(
            shprt(std::string("bake builtin:quad_box ") + receivers + "--checkpoint '" +
                  (m_dir / "b.ckpt").string() + "' -o '" + output + "'"),
            "texel and refined bakes cannot be checkpointed");
    EXPECT_FALSE(fs::exists(m_dir / "b.ckpt"));
    EXPECT_TRUE(out_dir_empty());
}

// Glossy matrices resume too: a bake stopped after its first chunks and killed, resumed, gives
// the uninterrupted file's bytes.
TEST_F(CliInterrupt, KilledGlossyBakeResumesToTheSameBytes) {
    const std::vector<std::string> glossy = {
        "bake",      "builtin:room", "--transfer", "glossy", "--bands",       "3",
        "--samples", "256",          "--threads",  "1",      "--reproducible"};
    const std::string expected = reference(glossy);
    const std::string output = out("g.shprt"), ckpt = (m_dir / "g.ckpt").string();
    const std::string whole = kill_after_bake(glossy, ckpt, output);
    ASSERT_GT(whole.size(), 64u + 32u);
    std::ofstream(ckpt, std::ios::binary).write(whole.data(), std::streamsize(whole.size() / 2));
    const RunResult r = shprt(joined(glossy) + "--resume '" + ckpt + "' -o '" + output + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(slurp(output) == expected) << "resumed glossy bake differs";
}

TEST_F(CliInterrupt, BakeThatDoesNotFitInMemoryIsRefusedWithItsEstimate) {
    const std::string output = out("a.shprt");
    expect_one_line_error(
        shprt("bake builtin:room --samples 256 --max-memory 1M -o '" + output + "'"),
        "MiB of memory (estimated");
    expect_one_line_error(shprt("bake builtin:room --max-memory lots -o '" + output + "'"),
                          "--max-memory 'lots'");
    EXPECT_TRUE(out_dir_empty());
    EXPECT_EQ(shprt("bake builtin:room --samples 64 --max-memory 1G -o '" + output + "'").exit_code,
              0);
}

// A write that fails half-way (the file size limit of `ulimit -f`, with SIGXFSZ ignored so that
// write(2) fails with EFBIG, as on a full disk with ENOSPC): one line, nothing left.
TEST_F(CliInterrupt, FailedWritesLeaveNothing) {
    const std::string output = out("a.shprt");
    const shprt::test_support::RunOptions limited{.prefix = "trap '' XFSZ; ulimit -f 200;"};
    for (const char* mode : {"", "--stream ", "--half "}) {
        SCOPED_TRACE(mode);
        expect_failure(
            shprt(std::string("bake builtin:room --samples 16 ") + mode + "-o '" + output + "'",
                  limited),
            1, "cannot write " + output);
        EXPECT_TRUE(out_dir_empty()) << ::testing::PrintToString(out_files());
    }
    // The checkpoint's own writes: what it kept is said to be resumable (issue 41, item 11), and
    // the resume, with the space back, gives the uninterrupted bake's bytes.
    const std::string ckpt = out("a.ckpt");
    const std::string bake = "bake builtin:room --samples 16 --reproducible ";
    const RunResult failed = shprt(bake + "--checkpoint '" + ckpt + "' -o '" + out("b.shprt") + "'",
                                   {.prefix = "trap '' XFSZ; ulimit -f 600;"});
    expect_failure(failed, 1, "cannot write");
    const std::vector<std::string> left = out_files();
    ASSERT_EQ(left, std::vector<std::string>{"a.ckpt"}) << "a 600 KiB limit keeps some rows";
    EXPECT_NE(failed.err.find("receivers are saved in " + ckpt), std::string::npos) << failed.err;
    EXPECT_NE(failed.err.find("--resume " + ckpt), std::string::npos) << failed.err;
    ASSERT_EQ(shprt(bake + "--resume '" + ckpt + "' -o '" + out("b.shprt") + "'").exit_code, 0);
    ASSERT_EQ(shprt(bake + "-o '" + out("c.shprt") + "'").exit_code, 0);
    EXPECT_TRUE(slurp(out("b.shprt")) == slurp(out("c.shprt"))) << "the resume differs";
}

}  // namespace
