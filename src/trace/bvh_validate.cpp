// Structural checks of a flat BVH, for tests: the invariants the traversal relies on.
#include "shprt/core/error.hpp"
#include "shprt/trace/bvh_build.hpp"
#include "trace/embree_common.hpp"

#include <vector>

namespace shprt {

namespace {

bool contains(const Aabb& outer, const Aabb& inner) {
    return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
           outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

bool overlaps(const Aabb& a, const Aabb& b) {
    return a.lo.x <= b.hi.x && a.lo.y <= b.hi.y && a.lo.z <= b.hi.z && b.lo.x <= a.hi.x &&
           b.lo.y <= a.hi.y && b.lo.z <= a.hi.z;
}

class Validator {
public:
    Validator(const FlatBvh& bvh, const Mesh& mesh)
        : m_bvh(bvh),
          m_mesh(mesh),
          m_node_seen(bvh.nodes.size(), 0),
          m_tri_seen(mesh.triangles.size(), 0) {}

    void run() {
        const auto& nodes = m_bvh.nodes;
        SHPRT_CHECK(!nodes.empty(), format, "flat BVH: no nodes");
        SHPRT_CHECK(m_bvh.tri_ids.size() * kFlatBvhTriStride == m_bvh.tri_verts.size(), format,
                    "flat BVH: {} triangle ids but {} vertex floats", m_bvh.tri_ids.size(),
                    m_bvh.tri_verts.size());
        visit(0, 0);
        for (std::size_t i = 0; i < nodes.size(); ++i)
            SHPRT_CHECK(m_node_seen[i] == 1, format, "flat BVH: node {} reached {} times", i,
                        m_node_seen[i]);
        for (std::size_t t = 0; t < m_mesh.triangles.size(); ++t)
            SHPRT_CHECK(m_tri_seen[t] || trace_detail::is_degenerate(m_mesh, t), format,
                        "flat BVH: triangle {} is in no leaf", t);
    }

private:
    void visit(std::uint32_t index, std::uint32_t depth) {
        SHPRT_CHECK(depth < static_cast<std::uint32_t>(kFlatBvhStackSize), format,
                    "flat BVH: node {} at depth {} is deeper than the traversal stack", index,
                    depth);
        ++m_node_seen[index];
        const FlatBvhNode& node = m_bvh.nodes[index];
        SHPRT_CHECK(node.reserved[0] == 0 && node.reserved[1] == 0, format,
                    "flat BVH: node {} has non-zero reserved words", index);
        for (int i = 0; i < 2; ++i) {
            const std::uint32_t ref = node.child[i];
            const Aabb& box = node.box[i];
            if (flat_bvh_is_leaf(ref)) {
                check_leaf(index, ref, box);
                continue;
            }
            SHPRT_CHECK(ref < m_bvh.nodes.size(), format,
                        "flat BVH: node {} child {} refers to node {} of {}", index, i, ref,
                        m_bvh.nodes.size());
            SHPRT_CHECK(ref > index, format, "flat BVH: node {} child {} points backwards ({})",
                        index, i, ref);
            SHPRT_CHECK(i == 1 || ref == index + 1, format,
                        "flat BVH: node {} is not stored depth first (child 0 is {})", index, ref);
            const FlatBvhNode& child = m_bvh.nodes[ref];
            SHPRT_CHECK(contains(box, child.box[0]) && contains(box, child.box[1]), format,
                        "flat BVH: node {} child {} box does not contain node {}'s boxes", index, i,
                        ref);
            visit(ref, depth + 1);
        }
    }

    void check_leaf(std::uint32_t index, std::uint32_t ref, const Aabb& box) {
        const std::uint32_t first = flat_bvh_leaf_first(ref);
        const std::uint32_t count = flat_bvh_leaf_count(ref);
        SHPRT_CHECK(first + count <= m_bvh.tri_ids.size(), format,
                    "flat BVH: node {} leaf [{}, {}) exceeds {} references", index, first,
                    first + count, m_bvh.tri_ids.size());
        const FlatBvhView view = m_bvh.view();
        for (std::uint32_t r = first; r < first + count; ++r) {
            const std::uint32_t id = m_bvh.tri_ids[r];
            SHPRT_CHECK(id < m_mesh.triangles.size(), format,
                        "flat BVH: reference {} names triangle {} of {}", r, id,
                        m_mesh.triangles.size());
            m_tri_seen[id] = 1;
            Vec3f v[3], n;
            flat_bvh_load_triangle(view, r, v[0], v[1], v[2], n);
            SHPRT_CHECK(n == triangle_normal(v[0], v[1], v[2]), format,
                        "flat BVH: reference {} stores a normal that is not its triangle's", r);
            Aabb tri_box{v[0], v[0]};
            for (int k = 0; k < 3; ++k) {
                SHPRT_CHECK(v[k] == m_mesh.positions[m_mesh.triangles[id][k]], format,
                            "flat BVH: reference {} vertex {} differs from triangle {}'s", r, k,
                            id);
                tri_box = Aabb{vmin(tri_box.lo, v[k]), vmax(tri_box.hi, v[k])};
            }
            SHPRT_CHECK(overlaps(box, tri_box), format,
                        "flat BVH: node {} leaf box misses its triangle {}", index, id);
        }
    }

    const FlatBvh& m_bvh;
    const Mesh& m_mesh;
    std::vector<int> m_node_seen;
    std::vector<char> m_tri_seen;
};

}  // namespace

void validate_flat_bvh(const FlatBvh& bvh, const Mesh& mesh) { Validator(bvh, mesh).run(); }

}  // namespace shprt
