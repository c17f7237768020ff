// Private pieces shared by the bake's translation units.
#pragma once

#include "shprt/bake/bake.hpp"

namespace shprt::detail {

// Throws Error(invalid_argument) for options or a mesh a bake cannot take (see bake.hpp).
void validate_bake_inputs(const Mesh& mesh, const BakeOptions& options);
void validate_direction_set(const DirectionSet& directions);
// `options` with samples set to the size of `directions`, after both checks above: how every
// bake entry point that takes its own direction set starts.
BakeOptions checked_options(const Mesh& mesh, const BakeOptions& options,
                            const DirectionSet& directions);

// A transfer set with the bake's description filled in (kind, K, one channel, sampler, S, seed)
// and no coefficients yet.
TransferSet empty_transfer(const BakeOptions& options, std::size_t samples);

// The CPU bake (bake_cpu.cpp). `tracer` may be null for unshadowed transfer, which casts no rays.
// `seconds_bvh` is recorded in the stats as the tracer's build time.
TransferSet bake_cpu(const Mesh& mesh, const BakeOptions& options, const DirectionSet& directions,
                     const Tracer* tracer, double seconds_bvh);

}  // namespace shprt::detail
