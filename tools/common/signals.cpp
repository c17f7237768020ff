#include "common/signals.hpp"

#include "common/command.hpp"

#include "shprt/core/file.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace shprt::tools {
namespace {

volatile std::sig_atomic_t g_request = 0;   // the signal that arrived as a request, or 0
volatile std::sig_atomic_t g_requests = 0;  // which signals are requests: 1 SIGINT, 2 all
pid_t g_main_pid = 0;                       // a forked child (the importer) dies quietly
volatile std::sig_atomic_t g_quiet = 0;     // no line: an MPI rank other than 0, or after the error
std::atomic<bool> g_installed{false};

void write_all(const char* text) {
    std::size_t size = std::strlen(text);
    while (size > 0) {
        const ssize_t n = ::write(STDERR_FILENO, text, size);
        if (n <= 0) return;
        text += n;
        size -= static_cast<std::size_t>(n);
    }
}

// Async-signal-safe: write, unlink (remove_live_temporaries) and _exit only.
extern "C" void on_signal(int signal) {
    if (::getpid() != g_main_pid) ::_exit(128 + signal);
    if ((g_requests == 2 || (g_requests == 1 && signal == SIGINT)) && g_request == 0) {
        g_request = signal;
        return;
    }
    remove_live_temporaries();
    if (g_quiet) ::_exit(128 + signal);
    write_all("shprt: error: interrupted by ");
    write_all(signal_name(signal));
    write_all("; nothing was written\n");
    ::_exit(128 + signal);
}

}  // namespace

const char* signal_name(int signal) {
    switch (signal) {
        case SIGINT:
            return "SIGINT";
        case SIGTERM:
            return "SIGTERM";
        case SIGHUP:
            return "SIGHUP";
        default:
            return "a signal";
    }
}

void install_signal_handlers() {
    if (g_installed.exchange(true)) return;
    g_main_pid = ::getpid();
    if (is_secondary_rank()) g_quiet = 1;
    handle_interrupt_signals(on_signal);
}

void quiet_signals() { g_quiet = 1; }

void install_interrupt_handler(bool terminate_too) {
    install_signal_handlers();
    g_requests = terminate_too ? 2 : 1;
}

bool interrupted() { return g_request != 0; }

int interrupt_signal() { return g_request; }

void end_interruptible() {
    g_requests = 0;
    if (g_request != 0) throw Interrupted{g_request};
}

void test_stop_point(const char* point) {
    const char* wanted = std::getenv("SHPRT_TEST_STOP_AT");
    if (wanted != nullptr && std::strcmp(wanted, point) == 0) ::raise(SIGSTOP);
}

}  // namespace shprt::tools
