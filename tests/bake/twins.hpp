// Which vertices a fixed-S CPU bake copies from a twin instead of tracing (src/bake/stages.hpp),
// for tests that count the bake's rays. Its tests need the src/ include path.
#pragma once

#include "bake/stages.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/scene/mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace shprt::test {

// Per vertex: whether a fixed-S CPU bake of S directions takes its row from a twin
// (bake/stages.hpp: find_twins in its chunk, CrossTwins across chunks) rather than casting its
// rays, in chunks of auto_chunk_receivers(V, S).
inline std::vector<bool> twin_vertices(const Mesh& mesh, std::size_t S) {
    const std::size_t V = mesh.vertex_count();
    const std::vector<std::uint8_t> traced =
        detail::traced_receivers(mesh.positions.data(), mesh.normals.data(), V,
                                 auto_chunk_receivers(std::max<std::size_t>(V, 1), S), S);
    std::vector<bool> copied(V);
    for (std::size_t v = 0; v < V; ++v) copied[v] = traced[v] == 0;
    return copied;
}

}  // namespace shprt::test
