// The lines a finished bake request is told in: what `shprt bake` prints on stdout (under MPI,
// rank 0), and what a refinement that stopped at one of its limits warns (core/log.hpp). The
// library says them, the shell prints them.
#pragma once

#include "shprt/bake/request.hpp"
#include "shprt/scene/mesh.hpp"

#include <string>

namespace shprt {

// The summary of `result`, the outcome of `request` on `mesh`, written to `output`, with the
// scene's load time, each line ending in '\n':
//   probes: ...                          (a bake with probes: describe_probes)
//   unwrap: ... / texels: WxH, ...       (texels)
//   refined: V -> V' vertices, ...       (refinement; a warning when a limit stopped it)
//   interreflection: N bounces (...), operator ..., albedo: ...   (interreflected)
//   baked N vertices|texels, K=.., S=.. (kind, sampler): ... -> OUTPUT
//   error bound: receivers per prefix ...; estimated error ...   (an error-bounded bake)
std::string bake_summary(const BakeRequest& request, const Mesh& mesh, const BakeResult& result,
                         const std::string& output, double seconds_load);

}  // namespace shprt
