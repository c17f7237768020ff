// The GPU bake's chunk planner (gpu.hpp) on the CPU: every plan fits the memory it was given,
// covers the mesh, honours requests and the kernel's index limit, does not depend on the free
// memory when memory is ample, and fails with out_of_memory when nothing fits.
#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace shprt {
namespace {

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
constexpr std::uint64_t kGiB = std::uint64_t(1) << 30;
constexpr std::uint64_t kCounterBytes = 8;  // one ray counter per slot

ChunkPlanRequest request(std::size_t V, std::size_t S, int K, std::uint64_t free_bytes) {
    ChunkPlanRequest r;
    r.vertices = V;
    r.samples = S;
    r.K = K;
    r.free_device_bytes = free_bytes;
    r.fixed_device_bytes = gpu_bake_fixed_bytes(V, S, K, 1 * kMiB);
    return r;
}

std::uint64_t usable(const ChunkPlanRequest& r) {
    return static_cast<std::uint64_t>(static_cast<double>(r.free_device_bytes) * r.usable_fraction);
}

// The invariants every plan must satisfy.
void expect_valid(const ChunkPlanRequest& r, const ChunkPlan& p) {
    SCOPED_TRACE(testing::Message()
                 << "V=" << r.vertices << " S=" << r.samples << " K=" << r.K
                 << " free=" << r.free_device_bytes << " chunk=" << p.chunk_vertices);
    ASSERT_GE(p.chunk_vertices, 1u);
    EXPECT_LE(p.chunk_vertices, r.vertices);
    EXPECT_EQ(p.chunk_count, (r.vertices + p.chunk_vertices - 1) / p.chunk_vertices);
    EXPECT_EQ(p.slots, std::min<std::size_t>(std::size_t(r.slots), p.chunk_count));
    const std::uint64_t b =
        gpu_bake_bytes_per_vertex(r.samples, r.K, r.device_output, r.closest_hits);
    EXPECT_EQ(p.slot_bytes, p.chunk_vertices * b + kCounterBytes);
    EXPECT_EQ(p.peak_bytes, r.fixed_device_bytes + std::uint64_t(p.slots) * p.slot_bytes);
    EXPECT_LE(p.peak_bytes, usable(r)) << "the plan must fit the usable free memory";
    EXPECT_LE(std::uint64_t(p.chunk_vertices) * r.samples * (r.closest_hits ? 3 : 1), 0x7FFFFFFFull)
        << "the kernels index threads (and A's entries) with 32-bit signed integers";
    if (r.requested_chunk > 0) {
        EXPECT_LE(p.chunk_vertices, r.requested_chunk);
    }
}

TEST(ChunkPlan, ByteCountsFollowTheDocumentedFormulas) {
    // 1000 vertices × 24 B + 512 samples × 16 B + 512·16 floats + the BVH.
    EXPECT_EQ(gpu_bake_fixed_bytes(1000, 512, 16, 12345),
              12345u + 1000u * 24u + 512u * 16u + 512u * 16u * 4u);
    EXPECT_EQ(gpu_bake_bytes_per_vertex(4096, 256, false), (4096u + 256u) * 4u);
    EXPECT_EQ(gpu_bake_bytes_per_vertex(4096, 256, true), 4096u * 4u);
    // Interreflected: a 12-byte hit record per sample, and A's block built from them: three
    // entries of 80 bytes and 8 of cub's per sample, a 4-byte row start per vertex.
    EXPECT_EQ(gpu_bake_bytes_per_vertex(4096, 256, false, true),
              (4096u + 256u) * 4u + 4096u * (12u + 3u * 88u) + 4u);
}

TEST(ChunkPlan, RoomSweepOnAnAmpleDevice) {
    // The paper's sweep on a 80 GB device: chunks are capped by the slot size (64 MiB), whole
    // GEMM tiles, and the plan does not depend on how much memory is free.
    for (int K : {32, 48, 64, 128, 256}) {
        for (std::size_t S : {1024u, 4096u}) {
            const ChunkPlanRequest a = request(20000, S, K, 80 * kGiB);
            const ChunkPlan p = plan_chunks(a);
            expect_valid(a, p);
            EXPECT_LE(p.slot_bytes, a.max_slot_bytes + kCounterBytes);
            if (p.chunk_vertices < a.vertices) {
                EXPECT_EQ(p.chunk_vertices % 128, 0u);
                EXPECT_GE(p.chunk_count, 2u);
                EXPECT_EQ(p.slots, 2);
                // Maximal: one more tile would exceed the slot cap.
                EXPECT_GT((p.chunk_vertices + 128) * gpu_bake_bytes_per_vertex(S, K, false),
                          a.max_slot_bytes);
            }
            const ChunkPlanRequest b = request(20000, S, K, 20 * kGiB);
            const ChunkPlan q = plan_chunks(b);
            EXPECT_EQ(q.chunk_vertices, p.chunk_vertices) << "ample memory: same chunks";
            EXPECT_EQ(q.peak_bytes, p.peak_bytes);
        }
    }
    // K = 256, S = 4096: (4096 + 256)·4 = 17 408 bytes a vertex, 64 MiB / 17 408 = 3855 → 3840.
    const ChunkPlan p = plan_chunks(request(20000, 4096, 256, 80 * kGiB));
    EXPECT_EQ(p.chunk_vertices, 3840u);
    EXPECT_EQ(p.chunk_count, 6u);
}

TEST(ChunkPlan, SmallMeshIsOneChunkInOneSlot) {
    const ChunkPlanRequest r = request(289, 1024, 16, 8 * kGiB);
    const ChunkPlan p = plan_chunks(r);
    expect_valid(r, p);
    EXPECT_EQ(p.chunk_vertices, 289u);
    EXPECT_EQ(p.chunk_count, 1u);
    EXPECT_EQ(p.slots, 1);
}

TEST(ChunkPlan, ScarceMemoryShrinksChunksToTheLargestThatFits) {
    // Explicit chunk request of the whole mesh: memory is the only limit, so the chunk is the
    // largest that fits, exactly.
    ChunkPlanRequest r = request(1'000'000, 4096, 256, 0);
    r.requested_chunk = r.vertices;
    const std::uint64_t b = gpu_bake_bytes_per_vertex(4096, 256, false);
    for (std::uint64_t free_bytes : {300 * kMiB, 1 * kGiB, 3 * kGiB + 12345}) {
        r.free_device_bytes = free_bytes;
        const ChunkPlan p = plan_chunks(r);
        expect_valid(r, p);
        ASSERT_LT(p.chunk_vertices, r.vertices);
        const std::uint64_t one_more =
            r.fixed_device_bytes + 2 * ((p.chunk_vertices + 1) * b + kCounterBytes);
        EXPECT_GT(one_more, usable(r)) << "one more vertex per slot would not fit";
    }
    // Automatic chunks under scarce memory: within the budget, whole tiles.
    ChunkPlanRequest a = request(1'000'000, 4096, 256, 200 * kMiB);
    const ChunkPlan q = plan_chunks(a);
    expect_valid(a, q);
    EXPECT_EQ(q.chunk_vertices % 128, 0u);
}

TEST(ChunkPlan, RequestedChunkIsHonouredWhenItFits) {
    ChunkPlanRequest r = request(5000, 1024, 64, 16 * kGiB);
    r.requested_chunk = 1000;
    ChunkPlan p = plan_chunks(r);
    expect_valid(r, p);
    EXPECT_EQ(p.chunk_vertices, 1000u);
    EXPECT_EQ(p.chunk_count, 5u);
    r.requested_chunk = 333;  // requests are not rounded to tiles
    p = plan_chunks(r);
    EXPECT_EQ(p.chunk_vertices, 333u);
    EXPECT_EQ(p.chunk_count, 16u);
    r.requested_chunk = 1'000'000;  // larger than the mesh
    p = plan_chunks(r);
    EXPECT_EQ(p.chunk_vertices, 5000u);
    EXPECT_EQ(p.chunk_count, 1u);
}

TEST(ChunkPlan, ThreadIndexLimitCapsHugeSampleCounts) {
    ChunkPlanRequest r = request(100'000, std::size_t(1) << 24, 16, 1024 * kGiB);
    r.requested_chunk = r.vertices;
    const ChunkPlan p = plan_chunks(r);
    expect_valid(r, p);
    EXPECT_EQ(p.chunk_vertices, 0x7FFFFFFFull / (1u << 24));  // 127
    r.closest_hits = true;  // three entries of A per (vertex, sample), indexed in int32 too
    const ChunkPlan q = plan_chunks(r);
    expect_valid(r, q);
    EXPECT_EQ(q.chunk_vertices, 0x7FFFFFFFull / (3u << 24));  // 42
}

TEST(ChunkPlan, DeviceOutputNeedsNoCoefficientBuffers) {
    ChunkPlanRequest r = request(1'000'000, 256, 1024, 2 * kGiB);
    r.requested_chunk = r.vertices;
    const ChunkPlan with_c = plan_chunks(r);
    r.device_output = true;
    const ChunkPlan without_c = plan_chunks(r);
    expect_valid(r, without_c);
    // W + C is 5× W here, so about 5× as many vertices fit without C.
    EXPECT_GT(without_c.chunk_vertices, 4 * with_c.chunk_vertices);
}

TEST(ChunkPlan, InvariantsHoldAcrossAGrid) {
    for (std::size_t V : {1u, 7u, 128u, 129u, 20000u, 3'000'000u})
        for (std::size_t S : {1u, 100u, 1024u, 65536u})
            for (int K : {1, 16, 256, 1024})
                for (std::uint64_t free_bytes : {256 * kMiB, 4 * kGiB, 80 * kGiB})
                    for (int slots : {1, 2}) {
                        ChunkPlanRequest r = request(V, S, K, free_bytes);
                        r.slots = slots;
                        const std::uint64_t least =
                            r.fixed_device_bytes +
                            std::uint64_t(slots) *
                                (gpu_bake_bytes_per_vertex(S, K, false) + kCounterBytes);
                        if (least > usable(r)) {
                            EXPECT_THROW(plan_chunks(r), Error);
                            continue;
                        }
                        expect_valid(r, plan_chunks(r));
                    }
}

TEST(ChunkPlan, NothingFitsIsOutOfMemory) {
    ChunkPlanRequest r = request(1000, 1024, 16, 10 * kMiB);
    r.fixed_device_bytes = 20 * kMiB;
    try {
        plan_chunks(r);
        FAIL() << "expected Error(out_of_memory)";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::out_of_memory);
        EXPECT_NE(std::string(e.what()).find("MiB"), std::string::npos) << e.what();
    }
    // Exactly enough for one vertex per slot (2 slots) is enough.
    r.usable_fraction = 1.0;
    r.fixed_device_bytes = 1000;
    r.free_device_bytes = 1000 + 2 * (gpu_bake_bytes_per_vertex(1024, 16, false) + kCounterBytes);
    const ChunkPlan p = plan_chunks(r);
    EXPECT_EQ(p.chunk_vertices, 1u);
    --r.free_device_bytes;
    EXPECT_THROW(plan_chunks(r), Error);
}

TEST(ChunkPlan, BadRequestsAreInvalidArguments) {
    const auto code_of = [](ChunkPlanRequest r) {
        try {
            plan_chunks(r);
        } catch (const Error& e) {
            return e.code();
        }
        return ErrorCode::io;  // no throw: a value no check uses
    };
    const ChunkPlanRequest ok = request(100, 64, 16, kGiB);
    ChunkPlanRequest r = ok;
    r.vertices = 0;
    EXPECT_EQ(code_of(r), ErrorCode::invalid_argument);
    r = ok;
    r.samples = 0;
    EXPECT_EQ(code_of(r), ErrorCode::invalid_argument);
    r = ok;
    r.K = 0;
    EXPECT_EQ(code_of(r), ErrorCode::invalid_argument);
    r = ok;
    r.K = kMaxBakeCoeffs + 1;
    EXPECT_EQ(code_of(r), ErrorCode::invalid_argument);
    r = ok;
    r.slots = 0;
    EXPECT_EQ(code_of(r), ErrorCode::invalid_argument);
    r = ok;
    r.usable_fraction = 0.0;
    EXPECT_EQ(code_of(r), ErrorCode::invalid_argument);
    r = ok;
    r.usable_fraction = 1.5;
    EXPECT_EQ(code_of(r), ErrorCode::invalid_argument);
    EXPECT_EQ(code_of(ok), ErrorCode::io) << "the valid request must not throw";
}

// The bounces' A on the device: whole when it fits, else its first blocks resident and the rest
// streamed through staging buffers as large as the largest block.
TEST(TransportResidency, KeepsWhatFitsAndStreamsTheRest) {
    const std::vector<std::uint64_t> blocks = {10, 20, 30, 40};
    const TransportResidency all = plan_transport_residency(blocks, 5, 105, 1.0);
    EXPECT_EQ(all.resident_blocks, 4u);
    EXPECT_EQ(all.staging_bytes, 0u);
    EXPECT_EQ(all.streamed_bytes, 0u);
    EXPECT_EQ(all.peak_bytes, 105u);

    // 80 bytes: the dense 5 and the staging 40 leave 35 for 10 + 20; 30 and 40 are streamed.
    const TransportResidency some = plan_transport_residency(blocks, 5, 80, 1.0);
    EXPECT_EQ(some.resident_blocks, 2u);
    EXPECT_EQ(some.staging_bytes, 40u);
    EXPECT_EQ(some.streamed_bytes, 70u);
    EXPECT_EQ(some.peak_bytes, 75u);

    // Only the staging fits: every block streamed.
    const TransportResidency none = plan_transport_residency(blocks, 5, 45, 1.0);
    EXPECT_EQ(none.resident_blocks, 0u);
    EXPECT_EQ(none.streamed_bytes, 100u);
    EXPECT_EQ(none.peak_bytes, 45u);

    // The usable fraction applies to the free bytes: 0.9 · 100 = 90 does not hold all 105.
    EXPECT_LT(plan_transport_residency(blocks, 5, 100).resident_blocks, 4u);

    std::string message;
    const auto failure = [&](std::uint64_t free_bytes, double fraction) {
        try {
            plan_transport_residency(blocks, 5, free_bytes, fraction);
        } catch (const Error& e) {
            message = e.what();
            return e.code();
        }
        return ErrorCode::io;  // no throw: a value no check uses
    };
    EXPECT_EQ(failure(44, 1.0), ErrorCode::out_of_memory);
    EXPECT_NE(message.find("largest block of the transport operator"), std::string::npos)
        << message;
    EXPECT_EQ(failure(100, 0.0), ErrorCode::invalid_argument);
}

TEST(TransportResidency, NeverPlansMoreThanIsUsable) {
    const std::vector<std::uint64_t> blocks = {7, 1, 13, 2, 9, 9, 0, 30, 4};
    for (std::uint64_t free_bytes = 40; free_bytes <= 120; ++free_bytes) {
        const TransportResidency r = plan_transport_residency(blocks, 3, free_bytes, 0.9);
        const auto usable = std::uint64_t(double(free_bytes) * 0.9);
        EXPECT_LE(r.peak_bytes, usable) << free_bytes;
        std::uint64_t resident = 0;
        for (std::size_t i = 0; i < r.resident_blocks; ++i) resident += blocks[i];
        EXPECT_EQ(r.peak_bytes, 3 + resident + r.staging_bytes) << free_bytes;
        EXPECT_EQ(r.streamed_bytes, 75 - resident) << free_bytes;
    }
}

}  // namespace
}  // namespace shprt
