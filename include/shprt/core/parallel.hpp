// shprt's parallel loops: TBB's parallel_for and task arenas behind one door, so that each fork
// and join is marked for ThreadSanitizer in one place (core/tsan.hpp, docs/sanitizers.md). TBB's
// templates are instantiated in src/core/parallel.cpp only; the loop body is called once per
// range through a function pointer.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <memory>
#include <type_traits>
#include <utility>

namespace shprt {

// The most threads an arena may have: TBB's max_allowed_parallelism (the CPUs this process may
// use, or a lower tbb::global_control limit), at least 1.
int max_thread_count();

// The threads a loop of `threads` runs on: `threads` if > 0, clamped to max_thread_count() with
// one log_warn line naming both counts (once per requested count, however often it is asked);
// else TBB's default concurrency (at least 1). Arena, the bakes and their reports ("cpu: N
// threads") all take their count from here, so what is reported is what runs.
int thread_count(int threads);

// How a range is cut: TBB's auto_partitioner (ranges of at least about grain/2, sized by the
// scheduler) or simple_partitioner (split down to ranges of at most `grain`: with grain 1 each
// index is a task, so the partition does not depend on the scheduler).
enum class Split { automatic, fixed };

namespace parallel_detail {
using RangeFn = void (*)(void* body, std::size_t begin, std::size_t end);
using CallFn = void (*)(void* fn);
void run_for(std::size_t begin, std::size_t end, std::size_t grain, Split split, RangeFn call,
             void* body);
template <class F>
void* erase(F& f) {
    return const_cast<void*>(static_cast<const void*>(std::addressof(f)));
}
}  // namespace parallel_detail

// Calls body(first, last) for sub-ranges covering [begin, end), on the current arena's threads
// (the caller's among them); returns when all are done. An exception from a body is rethrown here.
template <class Body>
void parallel_for(std::size_t begin, std::size_t end, std::size_t grain, Split split, Body&& body) {
    using B = std::remove_reference_t<Body>;
    parallel_detail::run_for(
        begin, end, grain, split,
        [](void* b, std::size_t first, std::size_t last) { (*static_cast<B*>(b))(first, last); },
        parallel_detail::erase(body));
}

// A TBB task arena of thread_count(threads) threads: the loops run inside execute() (shprt's
// and Embree's builds) use at most that many.
class Arena {
public:
    explicit Arena(int threads);
    ~Arena();
    Arena(const Arena&) = delete;
    Arena& operator=(const Arena&) = delete;

    // Runs fn() in the arena (on the calling thread when it can join it, else on a worker while
    // the caller waits); an exception from fn is rethrown here.
    template <class Fn>
    void execute(Fn&& fn) {
        using F = std::remove_reference_t<Fn>;
        run([](void* f) { (*static_cast<F*>(f))(); }, parallel_detail::erase(fn));
    }

private:
    void run(parallel_detail::CallFn call, void* fn);
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

// TBB's worker threads, held for a program's run: when it ends, the destructor waits until the
// workers have exited (tbb::finalize). A program that returns from main while TBB's workers are
// still shutting down races LeakSanitizer's scan at exit, which read such a thread's freed
// dynamic TLS and crashed ("Tracer caught signal 11", docs/sanitizers.md). The `shprt` program
// holds one for its whole run. If something still uses the scheduler then (another thread's
// arena), the destructor does not wait.
class WorkerThreads {
public:
    WorkerThreads();
    ~WorkerThreads();
    WorkerThreads(const WorkerThreads&) = delete;
    WorkerThreads& operator=(const WorkerThreads&) = delete;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

// Keeps `signals` off the library's worker threads from now on: each TBB worker blocks them
// (pthread_sigmask) before it runs a task in an Arena or in the calling thread's own arena, and
// keeps them blocked. A signal sent to the process then waits for a thread that takes it — the
// program's main thread — instead of running its handler on whichever worker the kernel picked,
// at a moment the main thread does not know (the `shprt` program: core/interrupt.hpp).
// Call it once, early, from the thread that should take the signals; later calls add signals.
void keep_signals_off_workers(std::initializer_list<int> signals);

// fn() in a new Arena(threads).
template <class Fn>
void in_arena(int threads, Fn&& fn) {
    Arena(threads).execute(std::forward<Fn>(fn));
}

// fn(i) for each i in [0, count), one task per index, in an arena of thread_count(threads).
template <class Fn>
void parallel_each(int threads, std::size_t count, Fn&& fn) {
    in_arena(threads, [&] {
        parallel_for(0, count, 1, Split::fixed, [&](std::size_t first, std::size_t last) {
            for (std::size_t i = first; i != last; ++i) fn(i);
        });
    });
}

}  // namespace shprt
