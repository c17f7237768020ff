// ThreadSanitizer annotations for hand-offs TSan cannot see (docs/sanitizers.md, "The
// ThreadSanitizer stage"). Debian's oneTBB and Embree are not built with -fsanitize=thread: their
// schedulers hand work between threads through atomics and futexes TSan never observes, so work
// that crosses threads through them looks unsynchronised. shprt marks its own fork and join
// points instead. Everything here compiles to nothing unless the translation unit is built with
// ThreadSanitizer (SHPRT_TSAN=ON): the classes are empty and the calls are empty inline functions.
// SHPRT_TSAN_ANNOTATIONS=1 turns them on in a file compiled without it (src/core/parallel.cpp).
#pragma once

#if defined(__SANITIZE_THREAD__) || defined(SHPRT_TSAN_ANNOTATIONS)
#define SHPRT_UNDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SHPRT_UNDER_TSAN 1
#endif
#endif
#ifndef SHPRT_UNDER_TSAN
#define SHPRT_UNDER_TSAN 0
#endif

#if SHPRT_UNDER_TSAN
#include <sanitizer/tsan_interface.h>
// In libtsan (gcc 12, clang 14) but not in their headers.
extern "C" void __tsan_ignore_thread_begin();
extern "C" void __tsan_ignore_thread_end();
#endif

namespace shprt::tsan {

// Everything the calling thread did before release(a) happens before everything a thread does
// after a later acquire(a) (the address is only a key; nothing is read or written there).
inline void release([[maybe_unused]] const void* address) {
#if SHPRT_UNDER_TSAN
    __tsan_release(const_cast<void*>(address));
#endif
}
inline void acquire([[maybe_unused]] const void* address) {
#if SHPRT_UNDER_TSAN
    __tsan_acquire(const_cast<void*>(address));
#endif
}

// One fork-join: a thread forks tasks, other threads run them, the forking thread joins them.
// Tasks see what the forker did before fork(); the forker, after join(), sees what every task did.
// Tasks are not ordered with one another, so TSan still reports two tasks that race.
class ForkJoin {
public:
#if SHPRT_UNDER_TSAN
    void fork() const { release(&m_fork); }
    void task_begin() const { acquire(&m_fork); }
    void task_end() const { release(&m_join); }
    void join() const { acquire(&m_join); }

private:
    char m_fork = 0, m_join = 0;
#else
    void fork() const {}
    void task_begin() const {}
    void task_end() const {}
    void join() const {}
#endif
};

// Callbacks a library makes from its own threads, ordered by that library's synchronisation
// (Embree's builder creates a node on one thread and sets its children on another): each callback
// runs between enter() and leave(), and the thread that started the library call leave()s before
// it and enter()s after it. TSan then orders callbacks that ran one after the other and still
// reports accesses in callbacks that overlapped in time.
class Callbacks {
public:
#if SHPRT_UNDER_TSAN
    void enter() const { acquire(&m_key); }
    void leave() const { release(&m_key); }

private:
    char m_key = 0;
#else
    void enter() const {}
    void leave() const {}
#endif
};

// Calls (object.*Begin)() now and (object.*End)() at the end of the scope, also when an
// exception leaves it.
template <class T, void (T::*Begin)() const, void (T::*End)() const>
class Scope {
public:
    explicit Scope(const T& object) : m_object(object) { (m_object.*Begin)(); }
    ~Scope() { (m_object.*End)(); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

private:
    const T& m_object;
};

// The forker: fork() now, join() at the end of the scope.
using ForkJoinScope = Scope<ForkJoin, &ForkJoin::fork, &ForkJoin::join>;
// A task of a ForkJoin: task_begin() now, task_end() at the end of the scope.
using TaskScope = Scope<ForkJoin, &ForkJoin::task_begin, &ForkJoin::task_end>;
// Inside a callback: enter() now, leave() at the end of the scope.
using CallbackScope = Scope<Callbacks, &Callbacks::enter, &Callbacks::leave>;
// Around a call into the library that may run the callbacks on its own threads: leave() now,
// enter() when the call has returned.
using LibraryCall = Scope<Callbacks, &Callbacks::leave, &Callbacks::enter>;
// A task or a callback must reach its ForkJoin or Callbacks without reading memory the forker or
// caller wrote (an address computed from a callback's user pointer, not a pointer loaded from
// it), since that read would come before the acquire.

// For the scope's lifetime TSan records no memory access of the calling thread: for a call into
// a library that runs none of shprt's code, when the library's own writes would otherwise be
// compared with its reads on the threads it hands work to (EmbreeDevice, embree_common.cpp).
class IgnoreScope {
public:
#if SHPRT_UNDER_TSAN
    IgnoreScope() { __tsan_ignore_thread_begin(); }
    ~IgnoreScope() { __tsan_ignore_thread_end(); }
#else
    IgnoreScope() {}
#endif
    IgnoreScope(const IgnoreScope&) = delete;
    IgnoreScope& operator=(const IgnoreScope&) = delete;
};

}  // namespace shprt::tsan
