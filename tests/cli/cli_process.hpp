// The `shprt` program started in the background, for tests that signal it at known moments
// (test_cli_interrupt, test_cli_late_signal): start it, wait until its handlers are in place or
// until it stopped itself at a SHPRT_TEST_STOP_AT point, and collect its result.
#pragma once

#include "cli/cli_test.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace shprt::test_support {

struct StartOptions {
    std::string stop_at = "";    // SHPRT_TEST_STOP_AT (empty: none)
    rlim_t file_size_limit = 0;  // RLIMIT_FSIZE in bytes (0: unchanged)
};

// Starts `shprt ARGS` with stdout and stderr into `dir`'s files "stdout" and "stderr", SIGINT,
// SIGTERM, SIGHUP and SIGXFSZ at their default actions and none blocked (whatever the test
// runner set). Returns once the exec is done (the pipe closes on exec); -1 if it cannot start.
inline pid_t start_shprt(const std::filesystem::path& dir, const std::vector<std::string>& args,
                         const StartOptions& how = {}) {
    int ready[2];
    if (::pipe2(ready, O_CLOEXEC) != 0) return -1;
    const std::string out = (dir / "stdout").string(), err = (dir / "stderr").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(ready[0]);
        ::dup2(::open("/dev/null", O_RDONLY), 0);
        ::dup2(::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644), 1);
        ::dup2(::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644), 2);
        for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ}) ::signal(signal, SIG_DFL);
        sigset_t none;
        sigemptyset(&none);
        ::sigprocmask(SIG_SETMASK, &none, nullptr);
        if (!how.stop_at.empty()) ::setenv("SHPRT_TEST_STOP_AT", how.stop_at.c_str(), 1);
        if (how.file_size_limit > 0) {
            const rlimit limit{how.file_size_limit, how.file_size_limit};
            ::setrlimit(RLIMIT_FSIZE, &limit);
        }
        std::vector<char*> argv{const_cast<char*>(SHPRT_CLI_PATH)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(SHPRT_CLI_PATH, argv.data());
        ::_exit(127);
    }
    ::close(ready[1]);
    char c;
    while (::read(ready[0], &c, 1) > 0) {
    }
    ::close(ready[0]);
    return pid;
}

// Waits until the program has its own handler for `signal` (SigCgt in /proc/PID/status): the
// launcher's main() has begun (tools/launcher.cpp, within a millisecond of exec). Before that,
// while the dynamic loader maps the C library, a signal ends it by the default action, before any
// file is opened (README, "What is guaranteed").
inline void wait_for_handlers(pid_t pid, int signal = SIGINT) {
    for (int i = 0; i < 20000; ++i) {
        std::ifstream in("/proc/" + std::to_string(pid) + "/status");
        std::string line;
        while (std::getline(in, line))
            if (line.rfind("SigCgt:", 0) == 0 &&
                (std::stoull(line.substr(7), nullptr, 16) & (1ull << (signal - 1))) != 0)
                return;
        if (!in.eof() && !in.good()) return;
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
}

// Waits until the program stopped itself (SHPRT_TEST_STOP_AT); false if it ended instead.
inline bool wait_stopped(pid_t pid) {
    int status = 0;
    return ::waitpid(pid, &status, WUNTRACED) == pid && WIFSTOPPED(status);
}

// Waits for the end: stdout, stderr (from `dir`, as start_shprt wrote them) and the exit code as
// run_shprt gives them.
inline RunResult finish_shprt(const std::filesystem::path& dir, pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return {code, slurp(dir / "stdout"), slurp(dir / "stderr")};
}

}  // namespace shprt::test_support
