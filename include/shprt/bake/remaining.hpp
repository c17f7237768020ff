// Baking what is left: the rows of a job's receiver range that are not done yet (a resumed bake,
// io/checkpoint.hpp). A sub-range of a bake gives exactly the rows of the whole bake (bake.hpp,
// "Determinism"), so baking the gaps and keeping the rows done before gives the same bits as one
// uninterrupted bake.
#pragma once

#include "shprt/bake/bake.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace shprt {

// Bakes the receivers of job.receivers' range that `done` does not cover: one bake() per gap,
// over one tracer built once (CPU), into job.sink — which sees begin(), write() and finish() once
// per gap, with the gap's range (a sink that keeps the whole range begins it at the first call:
// io/checkpoint.hpp's CheckpointSink). When nothing is left the sink sees begin() and finish()
// for the whole range and no write(). The progress callback sees one bake whose rays run over the
// whole range (the done receivers counted as done). Returns the description with the stats
// summed over the gaps (times, rays; the largest peak). Throws what bake() throws, and
// Error(unsupported) for a job with probes (each gap would bake them).
TransferInfo bake_remaining(const BakeJob& job, const BakeOptions& options,
                            const std::vector<ReceiverSpan>& done);

// Why a bake with `options` cannot be resumed from a checkpoint, or nullopt when it can: the one
// check, on the transfer kind (and, as they come, the domain and device). Interreflected
// transfer cannot (its bounces need every receiver's rows at once).
std::optional<std::string> resume_unsupported(const BakeOptions& options);

}  // namespace shprt
