// The self-shadowing bake of a dynamic object (bake/object_bake.hpp): the paper's shadowed
// transfer (Sloan, Kautz & Snyder 2002, §4) of the object as its own occluder.
#include "shprt/bake/object_bake.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <utility>

namespace shprt {

DynamicObject make_dynamic_object(Mesh mesh, const ObjectBakeOptions& options) {
    SHPRT_CHECK(mesh.vertex_count() > 0 && !mesh.triangles.empty(), invalid_argument,
                "{}: an object needs vertices and triangles", mesh.source);
    DynamicObject object;
    const Bounds b = mesh_bounds(mesh);
    object.pivot = (b.lo + b.hi) * 0.5f;
    if (options.self_shadow) {
        BakeOptions bake_options;
        bake_options.transfer = TransferKind::shadowed;
        bake_options.K = options.K;
        bake_options.samples = options.samples;
        bake_options.seed = options.seed;
        bake_options.threads = options.threads;
        object.self = bake(mesh, bake_options);
    }
    object.mesh = std::move(mesh);
    return object;
}

DynamicObject load_dynamic_object(const std::string& path, const ObjectBakeOptions& options) {
    return make_dynamic_object(load_scene(path), options);
}

}  // namespace shprt
