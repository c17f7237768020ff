// How the `shprt` program meets SIGINT, SIGTERM and SIGHUP (README, "What is guaranteed"): the
// process's signal handling, which the command line (tools/main.cpp) installs first of all.
//
//   * The `shprt` program (tools/launcher.cpp) holds such a signal while the command line's
//     libraries load; shprt_main() reports it right after install_signal_handlers().
//   * install_signal_handlers(), the first thing shprt_main() does: from then on such a signal
//     ends the process with one line, "shprt: error: interrupted by SIGINT; nothing was written",
//     after removing the temporary files of outputs being written (core/file.hpp) — exit status 128
//     + the signal (130, 143, 129). No moment of the process's life dies silently.
//   * install_interrupt_handler() (a bake or another long computation that polls interrupted()
//     through its progress callback) makes the next signal a request instead: interrupted()
//     turns true, the computation cancels cleanly (Error(cancelled)), and main() reports the
//     signal as above. A second signal ends the process at once, as in the first mode.
//   * end_interruptible() ends the request mode once the computation is over, before its result
//     is written: a signal that arrived meanwhile throws Interrupted (nothing is written), and a
//     later one ends the process with the temporaries removed, so a file is either complete and
//     renamed into place or absent.
//   * Once an output is renamed into place (core/file.hpp: committed_output; the rename holds the
//     signals), the run has succeeded: a first signal lets it finish, exit status 0, and
//     report_late_signal() says so in a warning; a second ends it at once with "interrupted by
//     SIGTERM after OUT was written (it is complete)", 128 + the signal. Never "nothing was
//     written" with the output in place.
//   * Under mpirun only rank 0 (or the lowest rank left, when rank 0 died) prints; every other rank
//     on the machine ends only once the ranks below it are gone (at most 2 s), since mpirun
//     SIGKILLs every rank as soon as the first has ended.
//   * SIGXFSZ is ignored: a write past `ulimit -f` fails with EFBIG, one error line naming the
//     file.
// A signal the process was started with ignored (nohup, a script's background job) stays ignored.
// Every such signal is handled in the main thread. The kernel hands a process's signal to any
// thread that does not block it, so the others block them: TBB's workers from their first task
// (keep_signals_off_workers, core/parallel.hpp) and the threads the libraries start while they
// load (the launcher blocks the signals around dlopen). A signal that another thread still takes
// (one the program did not start through TBB) is passed on to the main thread. So a signal sent
// while the main thread holds them across a rename waits for it, and is handled in its order —
// a worker that handled it raced the summary: the late warning came after it, or never.
#pragma once

#include <signal.h>

namespace shprt {

// The signals above: SIGINT, SIGTERM, SIGHUP.
inline constexpr int kInterruptSignals[] = {SIGINT, SIGTERM, SIGHUP};

// Makes `handler` the action of each of kInterruptSignals, the others blocked while it runs,
// except a signal the process was started with ignored (nohup, a script's background job), which
// stays ignored. Inline: the launcher (tools/launcher.cpp), which links nothing of shprt, uses
// it too.
inline void handle_interrupt_signals(void (*handler)(int)) {
    for (const int signal : kInterruptSignals) {
        struct sigaction current {};
        if (::sigaction(signal, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;
        struct sigaction action {};
        action.sa_handler = handler;
        sigemptyset(&action.sa_mask);
        for (const int other : kInterruptSignals) sigaddset(&action.sa_mask, other);
        ::sigaction(signal, &action, nullptr);
    }
}

// Thrown by end_interruptible(): the process was interrupted; main() reports it.
struct Interrupted {
    int signal = 0;
};

void install_signal_handlers();
// Makes the next SIGINT, SIGTERM or SIGHUP a cancel request (see top); with `terminate_too` false
// only SIGINT — an MPI rank, whose launcher ends a failed job with SIGTERM and may be blocked in
// MPI where no request is polled, dies of SIGTERM at once (temporaries removed). Safe to call more
// than once.
void install_interrupt_handler(bool terminate_too = true);
// True once a signal arrived as a request.
bool interrupted();
// The signal that arrived as a request (SIGINT, SIGTERM, SIGHUP), or 0.
int interrupt_signal();
// Back to the first mode; throws Interrupted if a request arrived.
void end_interruptible();
// After the process printed its one error line (print_error calls it): a later signal (mpirun
// ending the other ranks of a failed job) still removes the temporaries and ends the process, but
// prints nothing, so that the error stays the one and last line.
void quiet_signals();
// The signal that arrived after the output was in place (see top), or 0.
int late_signal();
// Prints "shprt: warning: SIGTERM arrived after OUT was written; the run finished (exit status 0)"
// when late_signal() is not 0 (and this process prints): the end of a successful run.
void report_late_signal();
// "SIGINT", "SIGTERM", "SIGHUP" (else "signal N").
const char* signal_name(int signal);
// The exit status for `signal`: 128 + signal.
inline int interrupted_exit_code(int signal) { return 128 + signal; }

// For the tests: SHPRT_TEST_SIGNAL_LINE_DELAY_MS=N makes the handler wait N ms before the
// line a signal ends the process with, as a rank that the machine does not schedule at once does
// (tests/dist/test_mpi_signals.cpp).

}  // namespace shprt
