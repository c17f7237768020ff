// The device side of the GPU bake, as seen from the host orchestration in src/bake/bake_gpu.cpp.
// CUDA-free (it is included by shprt_bake's .cpp files); implemented in src/bake/cuda/ and built
// only when SHPRT_HAS_CUDA. All pointers here are host pointers unless named device_*.
#pragma once

#include "shprt/bake/gpu.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/bake/transfer_sample.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/trace/flat_bvh.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace shprt::cuda {

struct DeviceState {
    std::string name;              // the GPU's name
    std::uint64_t free_bytes = 0;  // cudaMemGetInfo after the context exists
    std::uint64_t total_bytes = 0;
    std::uint64_t workspace_bytes = 0;  // cuBLAS workspaces of the context (all handles)
};

// Creates the process's GPU context for CUDA device `device` if needed and reports the device's
// memory. Takes the GPU lock for the duration of the call. Throws Error(unsupported) without
// that device, Error(cuda).
DeviceState prepare_device(int device);

// The scene and sampling of one bake, in host memory.
struct DeviceScene {
    FlatBvhView bvh{};  // node_count 0 when !shadowed
    const Vec3f* positions = nullptr;
    const Vec3f* normals = nullptr;
    std::size_t vertex_count = 0;
    const float* dirs = nullptr;     // 3·S
    const float* weights = nullptr;  // S
    std::size_t samples = 0;
    bool shadowed = true;
    bool hemisphere = false;  // glossy transfer matrices: W without the cosine
    bool local = false;       // a local set: dirs in each receiver's tangent frame
};

// The occluders' flat BVH on the device, uploaded once and kept by its owners across bakes (the
// error-bounded bake's segments and a bake session's passes, bake_gpu.cpp):
// DeviceBakeInput::occluders. Freed under the GPU
// lock when the last owner lets it go. Takes the GPU lock; throws as prepare_device, and
// Error(out_of_memory).
class DeviceOccluders;
std::shared_ptr<const DeviceOccluders> upload_occluders(int device, const FlatBvhView& bvh);

struct DeviceBakeInput {
    int device = 0;  // the CUDA device
    DeviceScene scene;
    // Set: scene.bvh is already on the device (upload_occluders of the same BVH on this device),
    // and the bake uses it instead of uploading its own copy.
    std::shared_ptr<const DeviceOccluders> occluders;
    // The projection table, S × K row-major: the basis Y, or for glossy transfer the pair
    // products (pair_product_table), K then being the packed matrix's K(K+1)/2 columns.
    const float* basis = nullptr;
    int K = 0;
    // The receivers baked: [first, first + count) of the scene's vertices, in the plan's chunks.
    std::size_t first = 0, count = 0;
    ChunkPlan plan;
    // Device pointer to the range's rows (count × K floats), or null: the rows are then
    // copied back to pinned host memory and handed to on_chunk_done.
    float* device_output = nullptr;
    // Called on the calling thread after each chunk, in vertex order, with the chunk's first
    // vertex and count, its rows (pinned host memory valid during the call, or null with
    // device_output) and the rays it cast. Returning false cancels: no further chunk is started.
    std::function<bool(std::size_t first, std::size_t count, const float* coeffs,
                       std::uint64_t rays)>
        on_chunk_done;
    // Interreflected transfer: W from the closest hits (closest_hit_sample), and from the hit
    // records, on the device, each chunk's block of the transport operator A (transport_build.hpp:
    // the CPU builder's bits from the same hits), handed to on_transport_block before
    // on_chunk_done. The receivers must be the mesh's vertices.
    bool closest_hits = false;
    TransportMeshView mesh{};  // host arrays of the occluder mesh
    std::size_t mesh_vertices = 0, mesh_triangles = 0;
    bool two_sided = false;
    std::function<void(TransportOperator::Block&& block)> on_transport_block;
};

struct DeviceBakeResult {
    double seconds_trace = 0;     // Σ GPU time of the transfer kernels
    double seconds_project = 0;   // Σ GPU time of the SGEMMs
    double seconds_operator = 0;  // Σ GPU time of the builds of A's blocks (closest_hits)
    std::uint64_t rays = 0;
    std::uint64_t peak_device_bytes = 0;  // the bake's allocations + the cuBLAS workspaces
    std::uint64_t pinned_bytes = 0;       // page-locked host staging
    bool cancelled = false;
};

// Runs the chunk pipeline of gpu.hpp's bake_gpu. Holds the GPU lock throughout.
DeviceBakeResult run_device_bake(const DeviceBakeInput& input);

// The bounces of an interreflected bake on the device: A (interreflect.hpp), its first
// `resident_blocks` blocks uploaded once (plan_transport_residency), then each apply() is
// out = A·in per channel by cuSPARSE SpMM (CSR, one call per block of A and channel,
// CUSPARSE_SPMM_ALG_DEFAULT without transposing A: deterministic run to run), `in` and `out`
// V × 3K floats in host memory (the transfer layout). The other blocks are copied in per apply,
// one at a time, through staging buffers as large as the largest of them; A must outlive this
// object. Holds the GPU lock while it uploads and while it applies.
class DeviceTransport {
public:
    DeviceTransport(int device, const TransportOperator& A, int K, std::size_t resident_blocks);
    ~DeviceTransport();
    DeviceTransport(const DeviceTransport&) = delete;
    DeviceTransport& operator=(const DeviceTransport&) = delete;

    void apply(const float* in, float* out);
    std::uint64_t device_bytes() const;    // A, the two dense buffers and SpMM's workspace
    double seconds() const;                // Σ GPU time of the products (and staging) so far
    std::uint64_t streamed_bytes() const;  // bytes of the blocks copied in per apply

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

// W rows of vertices [first, first + count): count × S floats, vertex-major (gpu.hpp).
std::vector<float> device_transfer_samples(int device, const DeviceScene& scene, std::size_t first,
                                           std::size_t count);

// The trace-only kernel over every (vertex, direction) of the scene (gpu.hpp).
GpuTraversalResult device_traversal_rate(int device, const DeviceScene& scene, int repeats);

}  // namespace shprt::cuda
