// Receivers of a bake (receivers.hpp).
#include "shprt/bake/receivers.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/mesh.hpp"

namespace shprt {

Receivers Receivers::range(std::size_t range_first, std::size_t range_count) const {
    SHPRT_CHECK(range_count >= 1 && range_first <= total && range_count <= total - range_first,
                invalid_argument, "receiver range [{}, {}) is empty or outside the {} receivers",
                range_first, range_first + range_count, total);
    Receivers out = *this;
    out.first = range_first;
    out.count = range_count;
    return out;
}

Receivers vertex_receivers(const Mesh& mesh) {
    const std::string name = mesh.source.empty() ? std::string("mesh") : mesh.source;
    SHPRT_CHECK(mesh.normals.size() == mesh.vertex_count(), invalid_argument,
                "{} has {} normals for {} vertices", name, mesh.normals.size(),
                mesh.vertex_count());
    return Receivers::all(ReceiverDomain::vertex, mesh.positions.data(), mesh.normals.data(),
                          mesh.vertex_count());
}

Receivers Receivers::all(ReceiverDomain domain, const Vec3f* positions, const Vec3f* normals,
                         std::size_t count) {
    Receivers r;
    r.domain = domain;
    r.positions = positions;
    r.normals = normals;
    r.total = count;
    r.first = 0;
    r.count = count;
    return r;
}

}  // namespace shprt
