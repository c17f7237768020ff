// The receivers of a bake: the points (with normals) where transfer is computed, and the range of
// them this bake computes. Today they are a mesh's vertices; refined vertices, texel centres or a
// shard's range are other Receivers over the same bake (bake.hpp). The occluders (the scene the
// rays hit) are a separate input, so receivers need not lie on the occluding mesh's vertices.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>

namespace shprt {

struct Mesh;

struct Receivers {
    ReceiverDomain domain = ReceiverDomain::vertex;
    // The domain's receivers, all of them (`total` each): rows of the result are indexed in this
    // numbering. Normals are unit length. The arrays are the caller's and must outlive the bake.
    const Vec3f* positions = nullptr;
    const Vec3f* normals = nullptr;
    std::size_t total = 0;
    // The range baked: receivers [first, first + count).
    std::size_t first = 0;
    std::size_t count = 0;

    // All `count` receivers of `domain` at the given arrays (the caller's: they must outlive the
    // bake).
    static Receivers all(ReceiverDomain domain, const Vec3f* positions, const Vec3f* normals,
                         std::size_t count);
    // The same receivers restricted to [first, first + count) of the domain's numbering; throws
    // Error(invalid_argument) when the range is empty or leaves [0, total).
    Receivers range(std::size_t first, std::size_t count) const;
    std::size_t end() const { return first + count; }
};

// Every vertex of `mesh` (positions and normals; the mesh must outlive the bake). Throws
// Error(invalid_argument) when the normal count differs from the vertex count.
Receivers vertex_receivers(const Mesh& mesh);

}  // namespace shprt
