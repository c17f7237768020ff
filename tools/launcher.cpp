// The `shprt` program: a small executable that puts its signal handlers in place before anything
// else loads, then loads the command line (libshprt_cli.so: beside it in the build folder, in
// ../lib/shprt/ when installed, cmake/Install.cmake) and runs it.
//
// The command line links Assimp, Embree, oneTBB, OpenBLAS, OpenGL, GLFW and MPI; the dynamic
// loader's work on them and their initialisers take 20 to 60 ms on a busy machine, and a signal in
// that time used to end the process by its default action, without the one line every other
// moment gets (README, "What is guaranteed"). This program needs only the C library, so its
// handlers are in place within a millisecond of exec. A SIGINT, SIGTERM or SIGHUP that arrives
// while the libraries load is held here, and the command line, once its own handlers are in place,
// reports it like any other interruption: one line, exit status 128 + the signal, nothing written.
#include "shprt/core/interrupt.hpp"

#include <dlfcn.h>
#include <signal.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

volatile sig_atomic_t g_early_signal = 0;  // the first signal that arrived while loading, or 0

extern "C" void hold_signal(int signal) {
    if (g_early_signal == 0) g_early_signal = signal;
}

// Called by the command line once its own handlers are in place (tools/main.cpp).
extern "C" int early_signal() { return g_early_signal; }

// `name` in the folder of this executable (/proc/self/exe), into `path`; `name` alone if unknown.
// Plain C: the program must not need the C++ library, which would cost loading time.
void beside_this_program(const char* name, char (&path)[PATH_MAX]) {
    const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
    path[n > 0 ? n : 0] = '\0';
    char* slash = std::strrchr(path, '/');
    const std::size_t folder = slash != nullptr ? static_cast<std::size_t>(slash - path) + 1 : 0;
    std::snprintf(path + folder, sizeof path - folder, "%s", name);
}

}  // namespace

int main(int argc, char** argv) {
    shprt::handle_interrupt_signals(hold_signal);
    // The tests' stop point "load" (tools/cmd_bake.cpp): the libraries are about to load.
    if (const char* point = std::getenv("SHPRT_TEST_STOP_AT");
        point != nullptr && std::strcmp(point, "load") == 0)
        ::raise(SIGSTOP);

    char library[PATH_MAX], installed[PATH_MAX];
    beside_this_program("libshprt_cli.so", library);
    beside_this_program(SHPRT_CLI_LIBRARY_FROM_BIN "/libshprt_cli.so", installed);
    if (::access(library, F_OK) != 0 && ::access(installed, F_OK) == 0)
        std::memcpy(library, installed, sizeof library);
    // RTLD_GLOBAL: Open MPI's components, which it loads itself, look for libmpi's symbols there.
    // The signals are blocked while the libraries load, so that the threads their constructors
    // start (OpenBLAS's) never take them: a signal sent meanwhile waits, and comes to hold_signal
    // when the mask is restored.
    sigset_t interrupts, previous;
    sigemptyset(&interrupts);
    for (const int signal : shprt::kInterruptSignals) sigaddset(&interrupts, signal);
    ::pthread_sigmask(SIG_BLOCK, &interrupts, &previous);
    void* handle = ::dlopen(library, RTLD_NOW | RTLD_GLOBAL);
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    using Main = int (*)(int, char**, int (*)());
    Main shprt_main =
        handle != nullptr ? reinterpret_cast<Main>(::dlsym(handle, "shprt_main")) : nullptr;
    if (shprt_main == nullptr) {
        // dlerror() names the library: "PATH: cannot open shared object file: ...".
        std::fprintf(stderr, "shprt: error: cannot load the command line: %s\n", ::dlerror());
        return 1;
    }
    return shprt_main(argc, argv, early_signal);
}
