// A dynamic object made ready to be lit from transfer probes (transfer/object.hpp,
// shade/object_shade.hpp): its mesh, its pivot and its self-shadowing transfer, baked once when
// the object is loaded — a shadowed diffuse bake of the object alone, in its own frame, with few
// directions (an object is small and its self-shadowing smooth at the probes' 3 bands).
#pragma once

#include "shprt/transfer/object.hpp"

#include <cstdint>
#include <string>

namespace shprt {

// Directions of the self-shadowing bake by default: 256 Sobol directions of the sphere (about
// 128 above each vertex's horizon). ~3 ms per 1000 vertices on one core of the dev machine.
inline constexpr std::uint32_t kDefaultObjectSamples = 256;

struct ObjectBakeOptions {
    int K = 9;  // basis size of the self-transfer: the probes' K (3 bands by default)
    std::uint32_t samples = kDefaultObjectSamples;
    bool self_shadow = true;  // false: no bake (DynamicObject::self empty: the cosine lobe)
    std::uint64_t seed = 1;
    int threads = 0;  // as BakeOptions::threads
};

// `mesh` (any mesh load_scene reads; it needs normals and triangles) with its pivot (the centre of
// its bounding box) and, with self_shadow, its shadowed transfer (bake(), one channel, K
// coefficients). Throws Error(invalid_argument) for a mesh without vertices or triangles and what
// bake() throws.
DynamicObject make_dynamic_object(Mesh mesh, const ObjectBakeOptions& options);
// load_scene(path), then make_dynamic_object. A file that does not load is load_scene's one-line
// Error naming `path`.
DynamicObject load_dynamic_object(const std::string& path, const ObjectBakeOptions& options);

}  // namespace shprt
