// The GPU bake's chunk planner (gpu.hpp): how many vertices go into one chunk so that the bake's
// device memory stays within what the GPU has free. Pure host arithmetic, tested on the CPU.
//
// Chunking is what keeps the bake's memory O(V·K + BVH + chunk·S) (DESIGN.md "Units of work"):
// the S×V matrix of transfer samples never exists, only `slots` chunks of it at a time.
#include "shprt/bake/gpu.hpp"
#include "shprt/bake/transfer_sample.hpp"

#include "shprt/core/error.hpp"

#include <algorithm>
#include <limits>

namespace shprt {
namespace {

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
constexpr std::size_t kGemmTile = 128;  // cuBLAS SGEMM tiles are multiples of this
constexpr std::uint64_t kCounterBytes = sizeof(std::uint64_t);  // a slot's ray counter
constexpr std::uint64_t kMaxThreadIndex = 0x7FFFFFFFull;  // the kernels index threads in int32

}  // namespace

std::uint64_t gpu_bake_fixed_bytes(std::size_t vertices, std::size_t samples, int K,
                                   std::uint64_t bvh_bytes) {
    const std::uint64_t v = vertices, s = samples, k = K > 0 ? std::uint64_t(K) : 0;
    return bvh_bytes + v * 2 * 3 * sizeof(float) + s * 4 * sizeof(float) + s * k * sizeof(float);
}

std::uint64_t gpu_bake_bytes_per_vertex(std::size_t samples, int K, bool device_output,
                                        bool closest_hits) {
    const std::uint64_t k = K > 0 ? std::uint64_t(K) : 0;
    return (std::uint64_t(samples) + (device_output ? 0 : k)) * sizeof(float) +
           (closest_hits ? std::uint64_t(samples) * kClosestHitBytesPerSample + sizeof(std::int32_t)
                         : 0);
}

ChunkPlan plan_chunks(const ChunkPlanRequest& r) {
    SHPRT_CHECK(r.vertices >= 1, invalid_argument, "chunk plan: no vertices");
    SHPRT_CHECK(r.samples >= 1, invalid_argument, "chunk plan: no samples");
    SHPRT_CHECK(r.K >= 1 && r.K <= kMaxBakeCoeffs, invalid_argument,
                "chunk plan: K = {} is out of range (1 to {})", r.K, kMaxBakeCoeffs);
    SHPRT_CHECK(r.slots >= 1, invalid_argument, "chunk plan: slots = {} must be ≥ 1", r.slots);
    SHPRT_CHECK(r.usable_fraction > 0.0 && r.usable_fraction <= 1.0, invalid_argument,
                "chunk plan: usable fraction {} is outside (0, 1]", r.usable_fraction);

    const std::uint64_t per_vertex =
        gpu_bake_bytes_per_vertex(r.samples, r.K, r.device_output, r.closest_hits);
    const std::uint64_t slots = std::uint64_t(r.slots);
    const auto usable =
        static_cast<std::uint64_t>(static_cast<double>(r.free_device_bytes) * r.usable_fraction);
    const std::uint64_t need_min = r.fixed_device_bytes + slots * (per_vertex + kCounterBytes);
    if (usable < need_min) {
        fail(ErrorCode::out_of_memory,
             "the GPU bake needs at least {:.1f} MiB of device memory ({:.1f} MiB for the BVH, "
             "mesh, directions and basis table, plus one vertex per buffer) but {:.1f} MiB are "
             "free (of which {:.0f}% are used)",
             double(need_min) / double(kMiB), double(r.fixed_device_bytes) / double(kMiB),
             double(r.free_device_bytes) / double(kMiB), 100.0 * r.usable_fraction);
    }
    const std::uint64_t fit = (usable - r.fixed_device_bytes - slots * kCounterBytes) /
                              (slots * per_vertex);  // ≥ 1 by the check above
    // Interreflected: three entries of A per (vertex, sample), each indexed in int32.
    const std::uint64_t by_index =
        std::max<std::uint64_t>(1, kMaxThreadIndex / (r.samples * (r.closest_hits ? 3 : 1)));

    std::uint64_t chunk = std::min<std::uint64_t>(r.vertices, std::min(fit, by_index));
    if (r.requested_chunk > 0) {
        chunk = std::min<std::uint64_t>(chunk, r.requested_chunk);
    } else {
        const std::uint64_t by_slot = std::max<std::uint64_t>(1, r.max_slot_bytes / per_vertex);
        chunk = std::min(chunk, by_slot);
        if (chunk < r.vertices && chunk >= kGemmTile) chunk = chunk / kGemmTile * kGemmTile;
    }

    ChunkPlan plan;
    plan.chunk_vertices = static_cast<std::size_t>(chunk);
    plan.chunk_count = static_cast<std::size_t>((r.vertices + chunk - 1) / chunk);
    plan.slots = static_cast<int>(std::min<std::uint64_t>(slots, plan.chunk_count));
    plan.slot_bytes = chunk * per_vertex + kCounterBytes;
    plan.peak_bytes = r.fixed_device_bytes + std::uint64_t(plan.slots) * plan.slot_bytes;
    return plan;
}

TransportResidency plan_transport_residency(const std::vector<std::uint64_t>& block_bytes,
                                            std::uint64_t dense_bytes,
                                            std::uint64_t free_device_bytes,
                                            double usable_fraction) {
    SHPRT_CHECK(usable_fraction > 0.0 && usable_fraction <= 1.0, invalid_argument,
                "transport residency: usable fraction {} is outside (0, 1]", usable_fraction);
    const auto usable =
        static_cast<std::uint64_t>(static_cast<double>(free_device_bytes) * usable_fraction);
    std::uint64_t total = 0, largest = 0;
    for (const std::uint64_t b : block_bytes) {
        total += b;
        largest = std::max(largest, b);
    }
    TransportResidency r;
    if (dense_bytes <= usable && total <= usable - dense_bytes) {
        r.resident_blocks = block_bytes.size();
        r.peak_bytes = dense_bytes + total;
        return r;
    }
    if (usable < dense_bytes || usable - dense_bytes < largest) {
        fail(ErrorCode::out_of_memory,
             "the GPU bounces need at least {:.1f} MiB of device memory (the transfer in and out, "
             "{:.1f} MiB, and the largest block of the transport operator, {:.1f} MiB) but {:.1f} "
             "MiB are free (of which {:.0f}% are used)",
             double(dense_bytes + largest) / double(kMiB), double(dense_bytes) / double(kMiB),
             double(largest) / double(kMiB), double(free_device_bytes) / double(kMiB),
             100.0 * usable_fraction);
    }
    r.staging_bytes = largest;
    std::uint64_t room = usable - dense_bytes - largest, resident = 0;
    while (r.resident_blocks < block_bytes.size() && block_bytes[r.resident_blocks] <= room) {
        room -= block_bytes[r.resident_blocks];
        resident += block_bytes[r.resident_blocks];
        ++r.resident_blocks;
    }
    r.streamed_bytes = total - resident;
    r.peak_bytes = dense_bytes + resident + largest;
    return r;
}

}  // namespace shprt
