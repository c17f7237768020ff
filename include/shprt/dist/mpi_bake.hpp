// One bake across the ranks of an MPI job (`mpirun -np P shprt bake ...`), with Open MPI or any
// MPI 3 library: built when the build finds MPI (SHPRT_MPI, config.hpp SHPRT_HAS_MPI).
//
// Every rank loads the scene and builds its own BVH; the receivers are cut into work units that
// the ranks claim one at a time from a shared counter on rank 0 (an MPI one-sided fetch-and-add),
// so a rank that finishes early claims more: dynamic load balancing with no coordinator thread.
// The units follow guided self-scheduling (Polychronopoulos & Kuck 1987): each is the remaining
// count over 2·P, but at least `min_unit` receivers, so there are few units while much is left
// and small ones at the end, where imbalance would show. The partition depends only on the
// receiver count, P and the options, never on timing; which rank bakes which unit does. Rows do
// not depend on either: a bake of a sub-range gives exactly the whole bake's rows (bake.hpp), so
// the result is bit-identical to a single-process bake with the same options.
//
// Rows are gathered: each rank bakes a unit into host memory on its threads and sends it to rank
// 0 (non-blocking, a few units in flight), and rank 0 hands every unit to its sink — host memory,
// or the streaming .shprt writer, which puts them straight into the file. Rank 0 bakes too: it
// drains the incoming rows from its own bake's progress callback, ~20 times a second. Only the
// thread that called bake_distributed makes MPI calls (MPI_THREAD_FUNNELED).
//
// Failure: whatever fails on one rank (a bad scene, a device error, a full disk on rank 0)
// becomes one error on every rank — rank 0's names the rank and the problem, the others are
// PeerFailed, which a program reports by exiting quietly with the same status — and no rank waits
// forever. A rank killed by a signal is the launcher's to handle: mpirun then terminates the job,
// and rank 0's temporary output is removed on SIGTERM (core/file.hpp). MpiSession registers the
// ranks on this machine (core/job.hpp), so that the signal handlers of the `shprt` program can say
// which rank ended (rank 0, or the lowest rank left when rank 0 is the one that died).
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/progress.hpp"
#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace shprt::dist {

// True when an MPI launcher started this process (mpirun/mpiexec of Open MPI, MPICH or Intel
// MPI, Slurm's srun with PMI): read from the environment variables they set; no MPI call.
bool launched_by_mpi();

// A failure that another rank reports (rank 0 prints it): carries the error code, so that every
// rank of a failed job exits with the same status.
class PeerFailed : public Error {
public:
    using Error::Error;
};

// The MPI world, initialised for the object's lifetime (MPI_Init_thread with MPI_THREAD_FUNNELED
// in the constructor, MPI_Finalize in the destructor). One per process; not copyable. Throws
// Error(unsupported) when MPI cannot start or gives less than funneled thread support.
class MpiSession {
public:
    MpiSession();
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    int rank() const { return m_rank; }
    int size() const { return m_size; }
    // This rank's index among the ranks on its node (MPI_COMM_TYPE_SHARED), for rank → GPU.
    int local_rank() const { return m_local_rank; }

    // Runs `step` on every rank (collective) and agrees on the outcome: when `step` throws on any
    // rank, every rank throws — the lowest failing rank's error, on rank 0 as that Error (its
    // message prefixed "rank N: " when N ≠ 0), on the others as PeerFailed. std::bad_alloc
    // counts as Error(out_of_memory), another std::exception as Error(invalid_argument).
    void agree(const std::function<void()>& step) const;
    // Waits until every rank is here (MPI_Barrier).
    void barrier() const;

private:
    int m_rank = 0, m_size = 1, m_local_rank = 0;
};

// Checks (collective) that every rank loaded the same scene: the meshes' hashes (io/hash.hpp) are
// equal. Throws as agree() does, naming the first rank whose scene differs from rank 0's.
void check_same_scene(const MpiSession& session, const Mesh& mesh);

struct DistOptions {
    // The smallest work unit, in receivers; 0 = automatic: max(256, auto_chunk_receivers ×
    // max(4, 2 × the rank's threads)), so a unit feeds every thread of a rank. A unit's rows are
    // at most 64 MiB (one MPI message).
    std::size_t min_unit = 0;
    // Units a rank may have sent but rank 0 not yet received (≥ 1): bounds a rank's buffers.
    int units_in_flight = 4;
    // Rank 0: called with ProgressInfo{"bake", receivers done on all ranks, receivers, "receivers"}
    // from the calling thread; returning false cancels the bake on every rank (Error(cancelled)).
    ProgressFn progress;
};

// The work units of a range of `count` receivers for `ranks` ranks (guided self-scheduling, see
// the top of this file): consecutive [first, first + count) ranges, relative to the range's
// start, that tile [0, count); each holds ⌈remaining / (2·ranks)⌉ receivers, at least min_unit
// and at most max_unit (but never more than remain). Depends on its arguments only. Throws
// Error(invalid_argument) when ranks, min_unit or max_unit is < 1. Exposed for tests.
struct WorkUnit {
    std::size_t first = 0, count = 0;
    bool operator==(const WorkUnit&) const = default;
};
std::vector<WorkUnit> plan_units(std::size_t count, int ranks, std::size_t min_unit,
                                 std::size_t max_unit);

// One rank's share of a distributed bake: what it claimed and the seconds its units took.
struct RankLoad {
    std::size_t units = 0, receivers = 0;
    double seconds = 0;
};

struct DistributedBake {
    // The bake's description with the stats of all ranks combined (add_stats: seconds and rays
    // summed, the largest peak, the devices listed as "P ranks: ..."), on every rank.
    TransferInfo info;
    // Rank 0 only (empty elsewhere): each rank's load, by rank — how the balancing went.
    std::vector<RankLoad> ranks;
    // Rank 0 only: the other ranks' rows it received and handed to the sink, and the seconds
    // that took (receive, copy, sink write) — the gather's cost.
    std::uint64_t bytes_gathered = 0;
    double seconds_gathered = 0;
    // Rank 0 only: seconds from the first claim to the last row in the sink.
    double seconds_wall = 0;
};

// Bakes job.receivers' range across the session's ranks (collective: every rank calls it with the
// same scene, receivers and options). Rank 0's job.sink receives every row (begin, the rows in
// any order by units, finish); the other ranks' job.sink is not used (may be null). The GPU, when
// options.device asks for one, is the rank's local rank modulo the node's device count
// (options.device_index is ignored). Throws as MpiSession::agree does; Error(cancelled)
// everywhere when rank 0's progress callback returned false.
DistributedBake bake_distributed(const MpiSession& session, const BakeJob& job,
                                 const BakeOptions& options, const DistOptions& dist = {});

}  // namespace shprt::dist
