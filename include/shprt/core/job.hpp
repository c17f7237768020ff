// The processes of this process's job (the ranks of an MPI job), for a program's signal handlers:
// when a job is ended because one of its ranks died (mpirun then sends SIGTERM to the others), a
// surviving rank can say which one, instead of "interrupted by SIGTERM". dist::MpiSession
// registers the ranks that share this machine, each with a word in memory shared by them where a
// rank that ends by a signal it handles records it (note_job_rank_ended): a rank whose process is
// gone without that record was killed outright or crashed. The queries only read that memory and
// call kill(pid, 0), so they are async-signal-safe.
#pragma once

#include <vector>

namespace shprt {

// One rank of the job, as this process sees it.
struct JobRank {
    int pid = 0;                    // its process on this machine; 0: on another one, or unknown
    volatile int* ended = nullptr;  // shared word: the signal it ended by (0: none), or nullptr
};

// Registers this process as rank `rank` of a job whose rank i is `ranks[i]`. rank < 0 forgets the
// job (before the ranks part in MPI_Finalize, where a rank that finished may end first, and the
// shared words are freed). At most kMaxJobRanks ranks are kept.
inline constexpr int kMaxJobRanks = 4096;
void set_job_ranks(int rank, const std::vector<JobRank>& ranks);

// True in a process that an MPI launcher started as a rank other than 0 (Open MPI's, PMI's or
// PMIx's rank variable is set and not 0), before any MPI call. Such a process prints no error:
// every rank of an `mpirun shprt ...` meets the same bad argument, and rank 0 reports it once.
bool is_secondary_rank();

// This process's rank in its job, or -1 outside a job.
int job_rank();

// Records, in this rank's shared word, that it is ending by `signal` (a handled SIGTERM from
// mpirun, which ends every rank): the others then do not take its end for the cause.
// Async-signal-safe.
void note_job_rank_ended(int signal);

// The lowest rank of the job, other than this one, whose process (on this machine) no longer
// exists and recorded no signal: killed outright (SIGKILL) or crashed. -1 when there is none.
// Async-signal-safe.
int first_lost_rank();

// The lowest rank below this one whose process runs on this machine (not yet reaped), or -1: none,
// outside a job, or rank 0. Async-signal-safe.
int lower_rank_running_here();

// True when every rank below this one is known to have ended (their processes are gone from this
// machine): this rank is the lowest one left, which speaks for the job. False for rank 0 and
// outside a job, and when a lower rank runs on another machine (unknown). Async-signal-safe.
bool lower_ranks_gone();

}  // namespace shprt
