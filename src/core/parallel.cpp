// TBB behind shprt/core/parallel.hpp. Under SHPRT_TSAN this file is compiled without
// -fsanitize=thread (CMakeLists.txt): TBB's task objects are built on one thread and run on
// another through libtbb's scheduler, which TSan cannot see, so instrumenting the templates
// instantiated here would report every task. The fork and join are marked instead (core/tsan.hpp).
#include "shprt/core/parallel.hpp"

#include "shprt/core/log.hpp"
#include "shprt/core/tsan.hpp"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <signal.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <new>

namespace shprt {

int max_thread_count() {
    const auto allowed =
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    return static_cast<int>(std::clamp<std::size_t>(allowed, 1, 1 << 20));
}

int thread_count(int threads) {
    if (threads <= 0) return std::max(1, tbb::info::default_concurrency());
    const int allowed = max_thread_count();
    if (threads <= allowed) return threads;
    // Beyond the limit TBB would print its own warning (and an empty line) on stderr and run
    // with fewer workers than the arena claims; clamping here keeps the count that is reported
    // the count that runs. One warning per requested count, not one per call.
    static std::atomic<int> warned{0};
    if (warned.exchange(threads) != threads)
        log_warn("{} threads requested, but TBB allows at most {} on this machine: using {}",
                 threads, allowed, allowed);
    return allowed;
}

struct WorkerThreads::Impl {
    tbb::task_scheduler_handle handle{tbb::attach{}};
};

WorkerThreads::WorkerThreads() : m_impl(std::make_unique<Impl>()) {}

WorkerThreads::~WorkerThreads() {
    // false (the scheduler still in use elsewhere) leaves the workers as they are: nothing to do.
    (void)tbb::finalize(m_impl->handle, std::nothrow);
}

namespace parallel_detail {

void run_for(std::size_t begin, std::size_t end, std::size_t grain, Split split, RangeFn call,
             void* body) {
    const tsan::ForkJoin fj;
    const tsan::ForkJoinScope scope(fj);
    const tbb::blocked_range<std::size_t> range(begin, end, std::max<std::size_t>(grain, 1));
    const auto task = [&](const tbb::blocked_range<std::size_t>& r) {
        const tsan::TaskScope task_scope(fj);
        call(body, r.begin(), r.end());
    };
    if (split == Split::fixed)
        tbb::parallel_for(range, task, tbb::simple_partitioner());
    else
        tbb::parallel_for(range, task, tbb::auto_partitioner());
}

}  // namespace parallel_detail

namespace {

// The signals keep_signals_off_workers() keeps off the workers (none until it is called).
std::mutex g_worker_signals_mutex;
sigset_t g_worker_signals;
std::atomic<bool> g_block_in_workers{false};

// Blocks the signals in each worker that enters the observed arena, before its first task there.
class BlockSignalsInWorkers final : public tbb::task_scheduler_observer {
public:
    BlockSignalsInWorkers() { observe(true); }
    explicit BlockSignalsInWorkers(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) {
        observe(true);
    }
    ~BlockSignalsInWorkers() override { observe(false); }
    void on_scheduler_entry(bool is_worker) override {
        if (!is_worker) return;
        sigset_t set;
        {
            const std::lock_guard lock(g_worker_signals_mutex);
            set = g_worker_signals;
        }
        ::pthread_sigmask(SIG_BLOCK, &set, nullptr);
    }
};

}  // namespace

void keep_signals_off_workers(std::initializer_list<int> signals) {
    {
        const std::lock_guard lock(g_worker_signals_mutex);
        if (!g_block_in_workers) sigemptyset(&g_worker_signals);
        for (const int signal : signals) sigaddset(&g_worker_signals, signal);
    }
    // The calling thread's own arena (parallel_for outside any Arena runs there), observed for the
    // rest of the program (never destroyed: it must outlive the scheduler, which ends at exit).
    static const auto* calling_threads_arena = new BlockSignalsInWorkers();
    (void)calling_threads_arena;
    g_block_in_workers = true;
}

struct Arena::Impl {
    tbb::task_arena arena;
    std::unique_ptr<BlockSignalsInWorkers> observer;  // when keep_signals_off_workers was called
};

Arena::Arena(int threads) : m_impl(new Impl{tbb::task_arena(thread_count(threads)), nullptr}) {
    if (g_block_in_workers) {
        m_impl->arena.initialize();
        m_impl->observer = std::make_unique<BlockSignalsInWorkers>(m_impl->arena);
    }
}

Arena::~Arena() = default;

void Arena::run(parallel_detail::CallFn call, void* fn) {
    // TBB may run fn on a worker when the caller cannot take a slot in the arena.
    const tsan::ForkJoin fj;
    const tsan::ForkJoinScope scope(fj);
    m_impl->arena.execute([&] {
        const tsan::TaskScope task_scope(fj);
        call(fn);
    });
}

}  // namespace shprt
