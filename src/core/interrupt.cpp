// The process's signal handling (interrupt.hpp).
#include "shprt/core/interrupt.hpp"

#include "shprt/core/file.hpp"
#include "shprt/core/job.hpp"
#include "shprt/core/parallel.hpp"

#include <signal.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <string>

namespace shprt {
namespace {

volatile std::sig_atomic_t g_request = 0;   // the signal that arrived as a request, or 0
volatile std::sig_atomic_t g_requests = 0;  // which signals are requests: 1 SIGINT, 2 all
pid_t g_main_pid = 0;                       // a forked child (the importer) dies quietly
pid_t g_main_tid = 0;                       // the thread that installed the handlers (main's)
volatile std::sig_atomic_t g_quiet = 0;     // no line: after the error
volatile std::sig_atomic_t g_secondary =
    0;                                  // an MPI rank other than 0: a line only for a lost rank
volatile std::sig_atomic_t g_late = 0;  // a signal that arrived after the output was in place
std::atomic<bool> g_installed{false};
long g_test_line_delay_ms = 0;  // SHPRT_TEST_SIGNAL_LINE_DELAY_MS (interrupt.hpp)

void write_all(const char* text);

// Writes a non-negative number (async-signal-safe).
void write_number(int value) {
    char digits[12];
    int n = 0;
    do {
        digits[n++] = static_cast<char>('0' + value % 10);
        value /= 10;
    } while (value > 0 && n < 11);
    char text[13];
    for (int i = 0; i < n; ++i) text[i] = digits[n - 1 - i];
    text[n] = '\0';
    write_all(text);
}

void write_all(const char* text) {
    std::size_t size = std::strlen(text);
    while (size > 0) {
        const ssize_t n = ::write(STDERR_FILENO, text, size);
        if (n <= 0) return;
        text += n;
        size -= static_cast<std::size_t>(n);
    }
}

// Sleeps `ms` milliseconds (async-signal-safe).
void sleep_ms(long ms) {
    timespec t{ms / 1000, (ms % 1000) * 1'000'000};
    while (::nanosleep(&t, &t) != 0 && errno == EINTR) {
    }
}

// The line a signal ends the process with is about to be written (the test hook's delay).
void before_line() {
    if (g_test_line_delay_ms > 0) sleep_ms(g_test_line_delay_ms);
}

// A rank that does not speak for the job ends only once the ranks below it on this machine are
// gone (at most kQuietRankWaitMs): mpirun (Open MPI 4.1) ends a job with SIGTERM to every rank and
// then SIGKILL to all of them as soon as the first has ended (the SIGCHLD cuts its one-second wait
// short), so a quiet rank that ended first killed the rank that speaks before its line, whenever
// the machine ran that rank's handler later than the quiet one's (about 1 run in 20). Rank 0, or
// the lowest rank left, now ends first.
constexpr long kQuietRankWaitMs = 2000;
[[noreturn]] void end_quiet_rank(int signal) {
    for (long waited = 0; waited < kQuietRankWaitMs && lower_rank_running_here() >= 0; waited += 2)
        sleep_ms(2);
    ::_exit(128 + signal);
}

// The calling thread's id (async-signal-safe: a bare system call).
pid_t current_tid() { return static_cast<pid_t>(::syscall(SYS_gettid)); }

// Async-signal-safe: write, unlink (remove_live_temporaries), kill(pid, 0), tgkill, nanosleep and
// _exit only.
extern "C" void on_signal(int signal) {
    if (::getpid() != g_main_pid) ::_exit(128 + signal);
    // A signal sent to the process is taken by any thread that does not hold it: a worker of the
    // bake's pools, or of Embree's or OpenBLAS's, whenever the main thread holds it (AtomicFile::
    // commit, across the rename). Handled there, it raced the main thread: a late signal's
    // warning could come after the summary, or never. So every signal is handed to the main
    // thread, where it waits until commit lets it go and is then handled in the main thread's
    // order of events (the test: CliLateSignal.SignalRightAfterTheRenameLetsTheRunFinish). Only if
    // the main thread cannot take it (it is gone) is it handled here.
    if (g_main_tid != 0 && current_tid() != g_main_tid &&
        ::syscall(SYS_tgkill, g_main_pid, g_main_tid, signal) == 0)
        return;
    if ((g_requests == 2 || (g_requests == 1 && signal == SIGINT)) && g_request == 0) {
        g_request = signal;
        return;
    }
    // The output is in place (AtomicFile::commit holds the signals across its rename): the run has
    // succeeded, and only its summary is left. The first signal lets it finish (exit 0,
    // report_late_signal); a second ends it at once, saying what was written.
    if (const char* written = committed_output()) {
        if (g_late == 0) {
            g_late = signal;
            return;
        }
        remove_live_temporaries();
        if (g_quiet || g_secondary) ::_exit(128 + signal);
        write_all("shprt: error: interrupted by ");
        write_all(signal_name(signal));
        write_all(" after ");
        write_all(written);
        write_all(" was written (it is complete)\n");
        ::_exit(128 + signal);
    }
    remove_live_temporaries();
    note_job_rank_ended(signal);
    if (g_quiet) ::_exit(128 + signal);
    // An MPI job that mpirun ends because one of its ranks died (core/job.hpp): rank 0, or the
    // lowest rank left when rank 0 is the one that died, says so instead of naming the signal.
    const int lost = first_lost_rank();
    if (g_secondary && !(lost >= 0 && lower_ranks_gone())) end_quiet_rank(signal);
    before_line();
    if (lost >= 0) {
        write_all("shprt: error: rank ");
        write_number(lost);
        write_all(" of the MPI job ended (killed or crashed), so the job was stopped (");
        write_all(signal_name(signal));
        write_all("); nothing was written\n");
        ::_exit(128 + signal);
    }
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
    g_main_tid = current_tid();
    if (is_secondary_rank()) g_secondary = 1;
    if (const char* delay = std::getenv("SHPRT_TEST_SIGNAL_LINE_DELAY_MS"))
        g_test_line_delay_ms = std::strtol(delay, nullptr, 10);
    handle_interrupt_signals(on_signal);
    // Only the main thread takes them (the hand-over in on_signal is for threads outside TBB's
    // pools, such as a viewer's background bake).
    keep_signals_off_workers({SIGINT, SIGTERM, SIGHUP});
    // A write past the file size limit (ulimit -f) fails with EFBIG, which the writer reports in
    // its one line and after which it removes its temporary, instead of killing the process.
    ::signal(SIGXFSZ, SIG_IGN);
}

int late_signal() { return g_late; }

void report_late_signal() {
    const char* written = committed_output();
    if (g_late == 0 || g_quiet || g_secondary || written == nullptr) return;
    const std::string line = std::string("shprt: warning: ") + signal_name(g_late) +
                             " arrived after " + written +
                             " was written; the run finished (exit status 0)\n";
    write_all(line.c_str());
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

}  // namespace shprt
