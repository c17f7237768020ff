// A bake session (issue 39, item 3): what the passes of one bake share, built once and kept —
// the direction set, its direction and basis tables, the open part's control, the error bound's
// parameters and the tracer — so that a bake in several passes builds none of it twice, and an
// error-bounded bake asked for more samples traces only what is new.
//
//   BakeSession session(job, options);        checks like bake(); builds the set, the tables, the
//                                             tracer (Embree, for the whole receiver set)
//   session.bake(part)                        one pass over a range of the receivers: a shard, a
//                                             resumed gap, an MPI unit, a refinement's new vertices
//   session.bake_to(cap, sink)                an error-bounded bake of every receiver to prefixes
//                                             of at most `cap`, going on from the last bake_to: the
//                                             viewer's rounds (background.hpp) trace each ray once
//
// bake(job, options) is a session of one pass. Every pass gives the bits that bake() gives for
// the same receivers and options (bake.hpp, "Determinism"): the tables are the same, the grid of
// chunks is over the whole receiver set, and bake_to(cap) equals bake() with max_samples = cap.
//
// What is kept depends on the backend. The CPU keeps everything above. The GPU bake
// (Device::cuda) and the interreflected bake (a whole-domain stage) keep the direction set only:
// each pass builds its own device copies, BVH or operator (bake_gpu.cpp, interreflect.cpp).
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/core/progress.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace shprt {

// The prefixes an error-bounded bake goes through in rounds (the viewer's progressive bake,
// BakeSession::bake_in_rounds): {256, 1024, …} quadrupling while under the set's max_samples,
// then max_samples; {bake_set_size} without target_error.
std::vector<std::uint32_t> error_bound_rounds(const BakeOptions& options);
// The memory a session's rounds keep for `receivers` receivers (the sums, prefixes, estimates and
// outcomes of every row), beside what bake() itself needs.
std::uint64_t round_rows_bytes(std::size_t receivers, const BakeOptions& options);

class BakeSession {
public:
    // The session of `job` with `options`: job.occluders, job.receivers (the whole receiver set,
    // or a range of it: the passes take ranges of job.receivers' set), job.directions and
    // job.tracer (optional, as for bake()). job.sink, job.direct and job.probes are the passes'.
    // Throws what bake() throws for bad options, occluders or receivers; builds the tracer with
    // options.threads.
    BakeSession(const BakeJob& job, const BakeOptions& options);
    ~BakeSession();
    BakeSession(const BakeSession&) = delete;
    BakeSession& operator=(const BakeSession&) = delete;

    // One pass: bake(part, options) with the session's set, tables and tracer. part.occluders is
    // the session's (or null); part.receivers a range of its receiver set, or another set over
    // the same occluders (a refinement's new vertices); `progress` replaces options.progress for
    // this pass. The first pass's stats count the tracer's build time.
    TransferInfo bake(const BakeJob& part, ProgressFn progress = {});

    // An error-bounded session (options.target_error > 0) on the CPU: every receiver of the set
    // baked to prefixes of at most `cap` (a power of two, kTargetFirstSamples to the set's
    // max_samples) into `sink`, which gets every row and estimate. A receiver already baked by an
    // earlier bake_to with a smaller cap, whose estimate was still over the target, goes on from
    // its sums: only the new segments are traced. The rows are bake()'s with max_samples = cap,
    // bit for bit. Error(invalid_argument) for another cap or a session without a bound.
    TransferInfo bake_to(std::uint32_t cap, TransferSink& sink, ProgressFn progress = {});

    // An error-bounded session's whole bake in the rounds of error_bound_rounds, breadth first:
    // each round takes every receiver still over the target to the round's prefix (bake_to,
    // rows kept in the session), and the last hands every row and estimate to `sink`. The rows
    // are bake()'s bits; what the order buys is the progress: after the first round every
    // receiver has an estimate, and each round reports as its own stage ("bake", then
    // "≤ 1024 samples", …, with the rounds left in ProgressInfo::then) with the estimated error
    // of all receivers falling from round to round. A round with nothing left to trace is not
    // reported. The stats are the rounds' together, the session's rows (round_rows_bytes) in the
    // peak. Error(invalid_argument) where bake_to refuses, or after a bake_to.
    TransferInfo bake_in_rounds(TransferSink& sink, ProgressFn progress = {});

    const BakeOptions& options() const;
    Device backend() const;  // resolved: cpu or cuda
    // Rays cast by every pass so far.
    std::uint64_t rays_cast() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace shprt
