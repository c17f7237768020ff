// Which vertices a CPU bake copies from a twin instead of tracing (src/bake/stages.hpp,
// find_twins), for tests that count the bake's rays. Its tests need the src/ include path.
#pragma once

#include "bake/stages.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/scene/mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace shprt::test {

// Per vertex: whether a CPU bake of S directions copies its row from a twin (bake/stages.hpp,
// find_twins) rather than casting its rays: the twins of each chunk of auto_chunk_receivers(V, S).
inline std::vector<bool> twin_vertices(const Mesh& mesh, std::size_t S) {
    const std::size_t V = mesh.vertex_count(),
                      chunk = auto_chunk_receivers(std::max<std::size_t>(V, 1), S);
    std::vector<bool> copied(V, false);
    std::vector<std::uint32_t> twin;
    for (std::size_t first = 0; first < V; first += chunk) {
        const std::size_t count = std::min(chunk, V - first);
        detail::find_twins(mesh.positions.data() + first, mesh.normals.data() + first, count, twin);
        for (std::size_t j = 0; j < count; ++j) copied[first + j] = twin[j] != j;
    }
    return copied;
}

}  // namespace shprt::test
