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

namespace shprt {

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

    const BakeOptions& options() const;
    Device backend() const;  // resolved: cpu or cuda
    // Rays cast by every pass so far.
    std::uint64_t rays_cast() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace shprt
