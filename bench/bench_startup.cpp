// How long after exec a signal still ends `shprt` by its default action, without its one line:
// the time from exec (a close-on-exec pipe closes) until the program's SIGINT handler is in
// place (the SigCgt mask of /proc/PID/status), over many runs. The launcher (tools/launcher.cpp)
// needs only the C library; the command line's libraries load after its handlers are in place.
//
//     ./build/bench/bench_startup --runs 100 [--program PATH] [-- ARGS]
//
// The default program is the build's shprt, running `bake builtin:room` (killed once measured).
#include "bench_cli.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {

bool has_sigint_handler(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("SigCgt:", 0) == 0)
            return (std::stoull(line.substr(7), nullptr, 16) & (1ull << (SIGINT - 1))) != 0;
    return false;
}

// Milliseconds from exec to the handler, or -1 when the program ended first.
double window_ms(const std::vector<std::string>& command) {
    int ready[2];
    if (::pipe2(ready, O_CLOEXEC) != 0) return -1;
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(ready[0]);
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1);
        ::dup2(null, 2);
        std::vector<char*> argv;
        for (const std::string& a : command) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    ::close(ready[1]);
    char c;
    while (::read(ready[0], &c, 1) > 0) {
    }
    ::close(ready[0]);
    const auto exec_done = std::chrono::steady_clock::now();
    double ms = -1;
    for (;;) {
        if (has_sigint_handler(pid)) {
            ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                           exec_done)
                     .count();
            break;
        }
        if (::waitpid(pid, nullptr, WNOHANG) == pid) return -1;
    }
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    return ms;
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 100;
    std::string program = SHPRT_CLI_PATH;
    std::vector<std::string> args;
    shprt::bench::BenchCli cli("bench_startup", "Time from exec until shprt handles SIGINT");
    cli.option("--runs", runs, "Runs")->check(CLI::Range(1, 100000));
    cli.option("--program", program, "The program (default: the build's shprt)");
    cli.option("args", args,
               "Its arguments (default: bake builtin:room -o /tmp/bench_startup.shprt)");
    cli.parse(argc, argv);
    if (args.empty()) args = {"bake", "builtin:room", "-o", "/tmp/bench_startup.shprt"};

    std::vector<std::string> command{program};
    command.insert(command.end(), args.begin(), args.end());
    std::vector<double> ms;
    for (int i = 0; i < runs; ++i)
        if (const double t = window_ms(command); t >= 0) ms.push_back(t);
    if (ms.empty()) {
        std::fprintf(stderr, "bench_startup: %s ended before it handled SIGINT\n", program.c_str());
        return 1;
    }
    std::sort(ms.begin(), ms.end());
    double sum = 0;
    for (const double t : ms) sum += t;
    std::printf(
        "%s: exec -> SIGINT handler over %zu runs: median %.2f ms, mean %.2f ms, "
        "90th percentile %.2f ms, worst %.2f ms\n",
        program.c_str(), ms.size(), ms[ms.size() / 2], sum / double(ms.size()),
        ms[ms.size() * 9 / 10], ms.back());
    return 0;
}
