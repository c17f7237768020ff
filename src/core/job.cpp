#include "shprt/core/job.hpp"

#include <signal.h>
#include <sys/types.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace shprt {
namespace {

// Filled before g_rank is published; a handler reads g_rank first.
std::array<JobRank, kMaxJobRanks> g_ranks{};
std::atomic<int> g_count{0};
std::atomic<int> g_rank{-1};

// True when rank i's process is known here and no longer exists (a zombie still counts as
// running). Keeps errno.
bool gone(int i) {
    const int pid = g_ranks[std::size_t(i)].pid;
    if (pid <= 0) return false;
    const int saved_errno = errno;
    const bool result = ::kill(pid, 0) != 0 && errno == ESRCH;
    errno = saved_errno;
    return result;
}

}  // namespace

void set_job_ranks(int rank, const std::vector<JobRank>& ranks) {
    g_rank.store(-1);
    if (rank < 0) return;
    const std::size_t n = ranks.size() < std::size_t(kMaxJobRanks) ? ranks.size() : kMaxJobRanks;
    for (std::size_t i = 0; i < n; ++i) g_ranks[i] = ranks[i];
    g_count.store(static_cast<int>(n));
    g_rank.store(rank);
}

bool is_secondary_rank() {
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) {
        const char* value = std::getenv(name);
        if (value != nullptr) return std::strcmp(value, "0") != 0;
    }
    return false;
}

int job_rank() { return g_rank.load(); }

void note_job_rank_ended(int signal) {
    const int rank = g_rank.load();
    if (rank >= 0 && rank < g_count.load() && g_ranks[std::size_t(rank)].ended != nullptr)
        *g_ranks[std::size_t(rank)].ended = signal;
}

int first_lost_rank() {
    const int rank = g_rank.load();
    if (rank < 0) return -1;
    for (int i = 0; i < g_count.load(); ++i) {
        const volatile int* ended = g_ranks[std::size_t(i)].ended;
        if (i != rank && gone(i) && (ended == nullptr || *ended == 0)) return i;
    }
    return -1;
}

int lower_rank_running_here() {
    const int rank = g_rank.load();
    if (rank <= 0 || rank > g_count.load()) return -1;
    for (int i = 0; i < rank; ++i)
        if (g_ranks[std::size_t(i)].pid > 0 && !gone(i)) return i;
    return -1;
}

bool lower_ranks_gone() {
    const int rank = g_rank.load();
    if (rank <= 0 || rank > g_count.load()) return false;
    for (int i = 0; i < rank; ++i)
        if (!gone(i)) return false;
    return true;
}

}  // namespace shprt
