// The bake's memory estimate (estimate_bake_peak_bytes) against a peak measured independently of
// the bake's own figures: this test executable replaces the global operator new / delete with
// counting versions (live bytes by malloc_usable_size, and their high-water mark), so the bytes
// every std::vector of the bake holds are seen as they are allocated. The tracer is built before
// the count starts and adds its own measured bytes (Embree's memory monitor: its BVH lives in
// Embree's allocator, not in operator new). Kinds whose rows are not K floats (glossy: a packed
// K×K matrix per receiver) are where an estimate that counted K floats fell short.
#include "shprt/bake/bake.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/tracer.hpp"

#include <gtest/gtest.h>
#include <malloc.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>

namespace {

std::atomic<std::int64_t> g_live{0};
std::atomic<std::int64_t> g_peak{0};

void* counted_alloc(std::size_t size, std::size_t align) {
    void* p = align > alignof(std::max_align_t)
                  ? std::aligned_alloc(align, (size + align - 1) / align * align)
                  : std::malloc(size ? size : 1);
    if (p == nullptr) throw std::bad_alloc();
    const auto now =
        g_live.fetch_add(std::int64_t(malloc_usable_size(p))) + std::int64_t(malloc_usable_size(p));
    auto peak = g_peak.load();
    while (now > peak && !g_peak.compare_exchange_weak(peak, now)) {
    }
    return p;
}

void counted_free(void* p) {
    if (p == nullptr) return;
    g_live.fetch_sub(std::int64_t(malloc_usable_size(p)));
    std::free(p);
}

}  // namespace

void* operator new(std::size_t n) { return counted_alloc(n, 0); }
void* operator new[](std::size_t n) { return counted_alloc(n, 0); }
void* operator new(std::size_t n, std::align_val_t a) {
    return counted_alloc(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
    return counted_alloc(n, static_cast<std::size_t>(a));
}
// The nothrow forms too (std::stable_sort's temporary buffer is one): libstdc++'s call the
// replaced operator new above, but a sanitizer's runtime has its own, whose blocks would reach
// counted_free uncounted.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    try {
        return counted_alloc(n, 0);
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }

namespace shprt {
namespace {

struct Measured {
    std::uint64_t peak = 0;      // heap high-water mark during the bake + the tracer's bytes
    std::uint64_t estimate = 0;  // estimate_bake_peak_bytes, rows in memory
    TransferSet result;
};

// Bakes every vertex of `scene` into host memory with a tracer built beforehand, counting the
// heap's high-water mark above what was live when the bake started.
Measured measure(const char* scene, const BakeOptions& options) {
    const Mesh mesh = make_builtin(scene);
    const DirectionSet dirs = make_direction_set(options.sampler, options.seed, options.samples);
    const auto tracer = make_embree_tracer(mesh);
    const std::int64_t before = g_live.load();
    g_peak.store(before);
    Measured m;
    m.result = bake_with_tracer(mesh, options, dirs, *tracer);
    m.peak = std::uint64_t(g_peak.load() - before) + tracer->memory_bytes();
    m.estimate = estimate_bake_peak_bytes(mesh.triangle_count(), mesh.vertex_count(), options, true,
                                          bake_bounce_source_count(mesh, options));
    EXPECT_EQ(m.result.coeffs.size(), m.result.layout.floats(mesh.vertex_count()));
    return m;
}

// Every kind, and glossy at the K where its matrices dominate: the estimate covers the measured
// peak and is within 1.5× of it (plus 1 MiB for the small scenes' fixed buffers).
TEST(BakeMemoryEstimate, CoversTheCountedPeakOfEveryKind) {
    struct Case {
        const char* scene;
        TransferKind kind;
        int K;
        std::uint32_t samples;
    };
    const Case cases[] = {
        {"room", TransferKind::shadowed, 16, 256},
        {"room", TransferKind::unshadowed, 16, 256},
        {"room", TransferKind::glossy, 16, 256},
        {"room", TransferKind::glossy, 36, 64},
        {"box_on_plane", TransferKind::glossy, 25, 1024},
    };
    for (const Case& c : cases) {
        BakeOptions o;
        o.transfer = c.kind;
        o.K = c.K;
        o.samples = c.samples;
        o.threads = 2;
        SCOPED_TRACE(std::string(c.scene) + " " + to_string(c.kind) + " K=" + std::to_string(c.K) +
                     " S=" + std::to_string(c.samples));
        const Measured m = measure(c.scene, o);
        std::printf("%s %s K=%d S=%u: counted peak %llu bytes, estimate %llu (%.2fx)\n", c.scene,
                    to_string(c.kind), c.K, c.samples, (unsigned long long)m.peak,
                    (unsigned long long)m.estimate, double(m.estimate) / double(m.peak));
        EXPECT_GE(m.estimate, m.peak);
        EXPECT_LE(m.estimate, m.peak + m.peak / 2 + (1u << 20));
    }
}

// The counter itself sees a bake's rows: a glossy bake's peak grows with its K(K+1)/2 floats per
// receiver, not with K.
TEST(BakeMemoryEstimate, CountedPeakGrowsWithTheGlossyMatrices) {
    BakeOptions o;
    o.transfer = TransferKind::glossy;
    o.samples = 64;
    o.threads = 1;
    o.K = 16;
    const Measured small = measure("room", o);
    o.K = 36;
    const Measured large = measure("room", o);
    const std::uint64_t V = make_builtin("room").vertex_count();
    const std::uint64_t extra_rows = V * (36 * 37 / 2 - 16 * 17 / 2) * sizeof(float);
    EXPECT_GE(large.peak, small.peak + extra_rows);
}

// An interreflected bake whose operator A does not fit its memory budget spills A's blocks past it
// to a mapped file: the heap it counts then stays within the budget (give or take the blocks the
// workers are building), well under the same bake with A in memory, and the rows are the same.
TEST(BakeMemoryEstimate, SpillingInterreflectedBakeStaysInItsBudget) {
    BakeOptions o;
    o.transfer = TransferKind::interreflected;
    o.K = 4;
    o.samples = 256;
    o.threads = 2;
    o.bounces = 2;
    o.chunk_receivers = 128;
    const Measured whole = measure("room", o);
    const std::uint64_t A = whole.result.interreflection.operator_bytes;
    BakeOptions tight = o;
    tight.memory_budget = whole.estimate + A / 4;  // the rest's estimate, and a quarter of A
    const Measured spilled = measure("room", tight);
    std::printf("A %llu bytes, budget %llu: counted peak %llu spilled, %llu in memory\n",
                (unsigned long long)A, (unsigned long long)tight.memory_budget,
                (unsigned long long)spilled.peak, (unsigned long long)whole.peak);
    EXPECT_GT(spilled.result.stats.operator_bytes_spilled, A / 2);
    EXPECT_LE(spilled.peak, tight.memory_budget + A / 8);
    EXPECT_LE(spilled.peak + A / 2, whole.peak);
    EXPECT_EQ(spilled.result.coeffs, whole.result.coeffs);
}

}  // namespace
}  // namespace shprt
