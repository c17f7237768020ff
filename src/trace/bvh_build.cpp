// Host construction of the flat BVH (flat_bvh.hpp).
//
// The tree is built by Embree's generic BVH builder (rtcBuildBVH) with our own node callbacks:
// a binned surface-area-heuristic build (Goldsmith & Salmon 1987; MacDonald & Booth 1990;
// Wald 2007 for binning) and, at HIGH quality, spatial splits of triangles that straddle a split
// plane (M. Stich, H. Friedrich, A. Dietrich, "Spatial Splits in Bounding Volume Hierarchies",
// HPG 2009). Our split callback clips the triangle against the plane and returns the bounds of
// each part, so split references are tight. The tree is then flattened depth first into the
// 64-byte two-child-box nodes of Aila & Laine (HPG 2009).
#include "shprt/trace/bvh_build.hpp"

#include "shprt/core/error.hpp"
#include "trace/embree_common.hpp"

#include <embree3/rtcore_builder.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>

namespace shprt {

namespace {

using trace_detail::EmbreeDevice;

// Nodes of the intermediate tree, allocated by Embree's thread-local allocator inside the
// RTCBVH and freed with it.
struct BuildNode {
    bool leaf;
};
struct BuildInner : BuildNode {
    BuildNode* child[2];
    Aabb box[2];
};
struct BuildLeaf : BuildNode {
    std::uint32_t count;
    std::uint32_t prims[1];  // `count` entries (over-allocated)
};

// What the node callbacks get as their user pointer.
struct BuildContext {
    tsan::Callbacks callbacks;  // Embree runs the callbacks on its build threads
    const Mesh& mesh;
};

BuildContext& context(void* user) { return *static_cast<BuildContext*>(user); }

// Embree's builder keeps this depth with margin under the traversal stack (depth ≤ stack size).
constexpr unsigned kBuildMaxDepth = kFlatBvhStackSize - 8;

void* create_node(RTCThreadLocalAllocator alloc, unsigned int /*child_count*/, void* user) {
    const tsan::CallbackScope scope(context(user).callbacks);
    void* mem = rtcThreadLocalAlloc(alloc, sizeof(BuildInner), 16);
    auto* node = new (mem) BuildInner;
    node->leaf = false;
    node->child[0] = node->child[1] = nullptr;
    return node;
}

void set_children(void* node_ptr, void** children, unsigned int count, void* user) {
    const tsan::CallbackScope scope(context(user).callbacks);
    auto* node = static_cast<BuildInner*>(node_ptr);
    for (unsigned i = 0; i < count && i < 2; ++i)
        node->child[i] = static_cast<BuildNode*>(children[i]);
}

void set_bounds(void* node_ptr, const RTCBounds** bounds, unsigned int count, void* user) {
    const tsan::CallbackScope scope(context(user).callbacks);
    auto* node = static_cast<BuildInner*>(node_ptr);
    for (unsigned i = 0; i < count && i < 2; ++i)
        node->box[i] = Aabb{{bounds[i]->lower_x, bounds[i]->lower_y, bounds[i]->lower_z},
                            {bounds[i]->upper_x, bounds[i]->upper_y, bounds[i]->upper_z}};
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count,
                  void* user) {
    const tsan::CallbackScope scope(context(user).callbacks);
    void* mem = rtcThreadLocalAlloc(
        alloc, sizeof(BuildLeaf) + (count > 0 ? count - 1 : 0) * sizeof(std::uint32_t), 16);
    auto* leaf = new (mem) BuildLeaf;
    leaf->leaf = true;
    leaf->count = static_cast<std::uint32_t>(count);
    for (size_t i = 0; i < count; ++i) leaf->prims[i] = prims[i].primID;
    return leaf;
}

// Spatial split of a (possibly already split) triangle reference at `position` on axis `dim`:
// clip the triangle's edges against the plane; each side's bounds are the vertices on that side
// plus the edge/plane crossings, intersected with the reference's current bounds.
void split_primitive(const RTCBuildPrimitive* prim, unsigned int dim, float position,
                     RTCBounds* left, RTCBounds* right, void* user) {
    const tsan::CallbackScope scope(context(user).callbacks);
    const Mesh& mesh = context(user).mesh;
    const auto& tri = mesh.triangles[prim->primID];
    const float inf = std::numeric_limits<float>::infinity();
    Vec3f llo{inf, inf, inf}, lhi{-inf, -inf, -inf}, rlo = llo, rhi = lhi;
    auto grow = [](Vec3f& lo, Vec3f& hi, Vec3f p) {
        lo = vmin(lo, p);
        hi = vmax(hi, p);
    };
    for (int k = 0; k < 3; ++k) {
        const Vec3f a = mesh.positions[tri[k]];
        const Vec3f b = mesh.positions[tri[(k + 1) % 3]];
        const float da = a[dim], db = b[dim];
        if (da <= position) grow(llo, lhi, a);
        if (da >= position) grow(rlo, rhi, a);
        if ((da < position && db > position) || (da > position && db < position)) {
            const float s = (position - da) / (db - da);
            Vec3f c = a + (b - a) * s;
            c[dim] = position;
            // The interpolated crossing is rounded; widen it by a few ulps so that each side's
            // box still contains its exact part of the triangle.
            Vec3f lo = c, hi = c;
            for (int i = 0; i < 3; ++i) {
                if (i == static_cast<int>(dim)) continue;
                const float slack = 4.0f * std::numeric_limits<float>::epsilon() *
                                    std::max(std::fabs(a[i]), std::fabs(b[i]));
                lo[i] -= slack;
                hi[i] += slack;
            }
            grow(llo, lhi, lo);
            grow(llo, lhi, hi);
            grow(rlo, rhi, lo);
            grow(rlo, rhi, hi);
        }
    }
    const Vec3f plo{prim->lower_x, prim->lower_y, prim->lower_z};
    const Vec3f phi{prim->upper_x, prim->upper_y, prim->upper_z};
    llo = vmax(llo, plo);
    lhi = vmin(lhi, phi);
    rlo = vmax(rlo, plo);
    rhi = vmin(rhi, phi);
    lhi[dim] = std::min(lhi[dim], position);
    rlo[dim] = std::max(rlo[dim], position);
    *left = RTCBounds{llo.x, llo.y, llo.z, 0.0f, lhi.x, lhi.y, lhi.z, 0.0f};
    *right = RTCBounds{rlo.x, rlo.y, rlo.z, 0.0f, rhi.x, rhi.y, rhi.z, 0.0f};
}

float half_area(const Aabb& b) {
    const Vec3f e = vmax(b.hi - b.lo, Vec3f{0, 0, 0});
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

Aabb merge(const Aabb& a, const Aabb& b) { return Aabb{vmin(a.lo, b.lo), vmax(a.hi, b.hi)}; }

class Flattener {
public:
    Flattener(const Mesh& mesh, const FlatBvhBuildOptions& options, FlatBvh& out)
        : m_mesh(mesh), m_options(options), m_out(out) {}

    void run(const BuildNode* root, const Aabb& root_box) {
        m_root_area = std::max(static_cast<double>(half_area(root_box)), 1e-30);
        m_out.nodes.emplace_back();
        if (root->leaf) {
            // A one-leaf tree: the root's two children are that leaf (see FlatBvhNode).
            const std::uint32_t ref = emit(root, root_box, 1);
            FlatBvhNode& node = m_out.nodes[0];
            node.box[0] = node.box[1] = root_box;
            node.child[0] = node.child[1] = ref;
        } else {
            const auto* inner = static_cast<const BuildInner*>(root);
            m_out.stats.sah_cost += m_options.traversal_cost;
            for (int i = 0; i < 2; ++i) {
                m_out.nodes[0].box[i] = inner->box[i];
                const std::uint32_t ref = emit(inner->child[i], inner->box[i], 1);
                m_out.nodes[0].child[i] = ref;
            }
        }
        m_out.nodes[0].reserved[0] = m_out.nodes[0].reserved[1] = 0;
    }

private:
    // Appends the subtree at `node` (whose bounds are `box`, at depth `depth`) and returns its
    // child reference.
    std::uint32_t emit(const BuildNode* node, const Aabb& box, std::uint32_t depth) {
        const double area = half_area(box) / m_root_area;
        if (node->leaf) {
            const auto* leaf = static_cast<const BuildLeaf*>(node);
            SHPRT_CHECK(leaf->count >= 1 && leaf->count <= kFlatBvhMaxLeafSize, unsupported,
                        "{}: BVH builder produced a leaf of {} triangles (limit {})", m_mesh.source,
                        leaf->count, kFlatBvhMaxLeafSize);
            const std::size_t first = m_out.tri_ids.size();
            SHPRT_CHECK(first + leaf->count <= kFlatBvhMaxPrimRefs, unsupported,
                        "{}: more than {} triangle references do not fit the flat BVH layout",
                        m_mesh.source, kFlatBvhMaxPrimRefs);
            for (std::uint32_t i = 0; i < leaf->count; ++i) {
                const std::uint32_t id = leaf->prims[i];
                m_out.tri_ids.push_back(id);
                const auto& tri = m_mesh.triangles[id];
                const Vec3f v[3] = {m_mesh.positions[tri[0]], m_mesh.positions[tri[1]],
                                    m_mesh.positions[tri[2]]};
                const Vec3f n = triangle_normal(v[0], v[1], v[2]);
                for (int k = 0; k < 3; ++k)
                    m_out.tri_verts.insert(m_out.tri_verts.end(), {v[k].x, v[k].y, v[k].z, n[k]});
            }
            ++m_out.stats.leaves;
            m_out.stats.max_depth = std::max(m_out.stats.max_depth, depth);
            m_out.stats.sah_cost +=
                static_cast<double>(m_options.intersection_cost) * leaf->count * area;
            return flat_bvh_make_leaf(static_cast<std::uint32_t>(first), leaf->count);
        }
        const auto* inner = static_cast<const BuildInner*>(node);
        SHPRT_CHECK(m_out.nodes.size() < kFlatBvhLeafBit, unsupported,
                    "{}: too many BVH nodes for the flat layout", m_mesh.source);
        const auto index = static_cast<std::uint32_t>(m_out.nodes.size());
        m_out.nodes.emplace_back();
        m_out.stats.sah_cost += m_options.traversal_cost * area;
        for (int i = 0; i < 2; ++i) {
            const std::uint32_t ref = emit(inner->child[i], inner->box[i], depth + 1);
            FlatBvhNode& out = m_out.nodes[index];  // re-fetched: emit() grows the vector
            out.box[i] = inner->box[i];
            out.child[i] = ref;
        }
        m_out.nodes[index].reserved[0] = m_out.nodes[index].reserved[1] = 0;
        return index;
    }

    const Mesh& m_mesh;
    const FlatBvhBuildOptions& m_options;
    FlatBvh& m_out;
    double m_root_area = 1.0;
};

struct BvhRelease {
    void operator()(RTCBVH bvh) const { rtcReleaseBVH(bvh); }
};

}  // namespace

FlatBvh build_flat_bvh(const Mesh& mesh, const FlatBvhBuildOptions& options) {
    SHPRT_CHECK(options.max_leaf_size >= 1 && options.max_leaf_size <= kFlatBvhMaxLeafSize,
                invalid_argument, "flat BVH: max_leaf_size {} is outside 1..{}",
                options.max_leaf_size, kFlatBvhMaxLeafSize);
    SHPRT_CHECK(options.spatial_split_budget >= 1.0f && options.spatial_split_budget <= 4.0f,
                invalid_argument, "flat BVH: spatial_split_budget {} is outside [1, 4]",
                options.spatial_split_budget);
    SHPRT_CHECK(options.traversal_cost > 0.0f && options.intersection_cost > 0.0f, invalid_argument,
                "flat BVH: SAH costs must be positive (got {} and {})", options.traversal_cost,
                options.intersection_cost);
    const std::size_t good = trace_detail::validate_mesh(mesh);

    // Build primitives: the bounds of every triangle that can be hit.
    const double budget = options.high_quality ? options.spatial_split_budget : 1.0;
    const auto capacity = static_cast<std::size_t>(std::ceil(budget * static_cast<double>(good)));
    std::vector<RTCBuildPrimitive> prims;
    prims.reserve(capacity);
    Aabb scene_box{
        {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
         std::numeric_limits<float>::infinity()},
        {-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
         -std::numeric_limits<float>::infinity()}};
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (trace_detail::is_degenerate(mesh, t)) continue;
        const auto& tri = mesh.triangles[t];
        const Vec3f a = mesh.positions[tri[0]], b = mesh.positions[tri[1]],
                    c = mesh.positions[tri[2]];
        const Vec3f lo = vmin(vmin(a, b), c), hi = vmax(vmax(a, b), c);
        scene_box = merge(scene_box, Aabb{lo, hi});
        RTCBuildPrimitive p;
        p.lower_x = lo.x;
        p.lower_y = lo.y;
        p.lower_z = lo.z;
        p.geomID = 0;
        p.upper_x = hi.x;
        p.upper_y = hi.y;
        p.upper_z = hi.z;
        p.primID = static_cast<unsigned>(t);
        prims.push_back(p);
    }
    const std::size_t count = prims.size();
    prims.resize(capacity);  // room for the references spatial splits add

    EmbreeDevice device;
    const std::unique_ptr<RTCBVHTy, BvhRelease> bvh(rtcNewBVH(device.get()));
    device.check("flat BVH: creating the Embree builder");
    SHPRT_CHECK(bvh != nullptr, out_of_memory, "flat BVH: rtcNewBVH failed");

    RTCBuildArguments args = rtcDefaultBuildArguments();
    args.byteSize = sizeof(args);
    args.buildQuality = options.high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
    args.buildFlags = RTC_BUILD_FLAG_NONE;
    args.maxBranchingFactor = 2;
    args.maxDepth = kBuildMaxDepth;
    args.sahBlockSize = 1;
    args.minLeafSize = 1;
    args.maxLeafSize = static_cast<unsigned>(options.max_leaf_size);
    args.traversalCost = options.traversal_cost;
    args.intersectionCost = options.intersection_cost;
    args.bvh = bvh.get();
    args.primitives = prims.data();
    args.primitiveCount = count;
    args.primitiveArrayCapacity = capacity;
    args.createNode = create_node;
    args.setNodeChildren = set_children;
    args.setNodeBounds = set_bounds;
    args.createLeaf = create_leaf;
    args.splitPrimitive = options.high_quality ? split_primitive : nullptr;
    args.buildProgress = nullptr;
    BuildContext build_context{{}, mesh};
    args.userPtr = &build_context;

    const BuildNode* root;
    {
        trace_detail::FtzDazScope ftz;
        const tsan::ForkJoinScope monitor(device.monitor());
        const tsan::LibraryCall call(build_context.callbacks);
        root = static_cast<const BuildNode*>(rtcBuildBVH(&args));
    }
    device.check("flat BVH: Embree's rtcBuildBVH");
    SHPRT_CHECK(root != nullptr, unsupported, "flat BVH: rtcBuildBVH returned no tree for {}",
                mesh.source);

    FlatBvh out;
    out.stats.triangles = static_cast<std::uint32_t>(count);
    out.nodes.reserve(2 * count / std::max(1, options.max_leaf_size / 2) + 1);
    out.tri_ids.reserve(count);
    out.tri_verts.reserve(count * kFlatBvhTriStride);
    Flattener(mesh, options, out).run(root, scene_box);
    out.stats.references = static_cast<std::uint32_t>(out.tri_ids.size());
    SHPRT_CHECK(out.stats.max_depth <= static_cast<std::uint32_t>(kFlatBvhStackSize), unsupported,
                "{}: BVH depth {} exceeds the traversal stack ({})", mesh.source,
                out.stats.max_depth, kFlatBvhStackSize);
    return out;
}

FlatBvh build_flat_bvh(const Mesh& mesh) { return build_flat_bvh(mesh, FlatBvhBuildOptions{}); }

}  // namespace shprt
