// A bake request (bake/request.hpp) run across the ranks of an MPI job: the request's vertex
// receivers (every vertex; a request cannot be both a shard and distributed) shared by the ranks
// (bake_distributed, mpi_bake.hpp), rank 0's output written by rank 0. What the request cannot
// combine with MPI (texels, refinement, interreflected transfer, a checkpoint) is refused by
// request_refusal on every rank.
#pragma once

#include "shprt/bake/request.hpp"
#include "shprt/dist/mpi_bake.hpp"

#include <cstddef>
#include <string>

namespace shprt::dist {

struct DistributedResult {
    BakeResult result;      // on rank 0: the output's summary (or the rows, without a file)
    DistributedBake ranks;  // how the ranks shared it (rank 0's view)
};

// Runs `request` (its `distributed` set) on `mesh` across the session's ranks (collective: every
// rank calls it with the same scene and request; only rank 0's output, progress callback and
// before_write are used). `min_unit`: DistOptions::min_unit. Throws as MpiSession::agree does:
// the same error on every rank.
DistributedResult run(const MpiSession& session, const BakeRequest& request, const Mesh& mesh,
                      std::size_t min_unit = 0);

// "ranks: receivers 4096 3968 ... (units 3 3 ...), busy 1.201 s to 1.310 s of 1.402 s; gathered
// 0.05 GiB in 0.081 s\n": how the balancing and the gather went (`shprt bake` under MPI prints it).
std::string rank_loads_summary(const DistributedBake& result);

}  // namespace shprt::dist
