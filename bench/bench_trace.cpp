// Tracing rates on the paper's room (builtin:room, ~20k triangles), the workload of a bake: for
// every vertex, the directions of one fixed 1024-direction sphere set that lie above the vertex's
// horizon (~512), cast from offset_ray_origin(position, normal) with tnear = 0, tfar = inf, in one
// call per vertex. Threads: a tbb::task_arena of T threads over vertices.
//
//   BM_EmbreeRaw/threads/chunk/high/config  plain Embree, rtcOccluded1M (incoherent) in chunks of
//                          `chunk` rays, no shprt code in the loop: the reference rate. high: scene
//                          build quality HIGH (1) or MEDIUM (0); config: the device string, 0 =
//                          Embree's default, 1 = "threads=1", 2 = "threads=2".
//   BM_EmbreeRawSingle     plain Embree, single-ray rtcOccluded1 (for comparison).
//   BM_TracerEmbree / BM_TracerFlatBvh   the same work through Tracer::occluded.
//   BM_FlatBvhOptions      the flat BVH traversal (bvh_occluded) for build options, 2 threads.
//   BM_ValidateAgreement   Embree vs flat BVH on every ray of the workload (fails above 0.1 %).
//   BM_BuildEmbree / BM_BuildFlatBvh     build times.
//
// Results and the command: bench/RESULTS.md, section "Tracing".
#include "shprt/scene/mesh.hpp"
#include "shprt/trace/bvh_build.hpp"
#include "shprt/trace/tracer.hpp"

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#if __has_include("shprt/scene/room.hpp")
#include "shprt/scene/room.hpp"
#define SHPRT_BENCH_HAS_ROOM 1
#else
#define SHPRT_BENCH_HAS_ROOM 0
#endif

namespace {

using namespace shprt;

constexpr int kSamples = 1024;  // S: directions per vertex before the horizon test

#if !SHPRT_BENCH_HAS_ROOM
// Fallback scene: a floor with tessellated random boxes, about 20k triangles.
void add_quad(Mesh& m, Vec3f o, Vec3f eu, Vec3f ev, Vec3f n, int cells) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) {
            m.positions.push_back(o + eu * (float(i) / cells) + ev * (float(j) / cells));
            m.normals.push_back(n);
            m.albedo.push_back({0.8f, 0.8f, 0.8f});
        }
    const auto row = static_cast<std::uint32_t>(cells + 1);
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const std::uint32_t a = base + j * row + i;
            m.triangles.push_back({a, a + 1, a + row + 1});
            m.triangles.push_back({a, a + row + 1, a + row});
        }
}
#endif

const Mesh& scene() {
    static const Mesh mesh = [] {
#if SHPRT_BENCH_HAS_ROOM
        return generate_room(RoomOptions{});
#else
        Mesh m;
        m.source = "random boxes";
        add_quad(m, {-3, 0, 3}, {6, 0, 0}, {0, 0, -6}, {0, 1, 0}, 40);
        std::srand(1);
        auto r = [] { return float(std::rand()) / RAND_MAX; };
        for (int b = 0; b < 60; ++b) {
            const Vec3f lo{-3 + 5.5f * r(), 0, -3 + 5.5f * r()};
            const Vec3f e{0.2f + 0.4f * r(), 0.2f + 1.5f * r(), 0.2f + 0.4f * r()};
            const Vec3f hi = lo + e;
            add_quad(m, {lo.x, lo.y, hi.z}, {e.x, 0, 0}, {0, e.y, 0}, {0, 0, 1}, 4);
            add_quad(m, {hi.x, lo.y, lo.z}, {-e.x, 0, 0}, {0, e.y, 0}, {0, 0, -1}, 4);
            add_quad(m, {hi.x, lo.y, hi.z}, {0, 0, -e.z}, {0, e.y, 0}, {1, 0, 0}, 4);
            add_quad(m, {lo.x, lo.y, lo.z}, {0, 0, e.z}, {0, e.y, 0}, {-1, 0, 0}, 4);
            add_quad(m, {lo.x, hi.y, hi.z}, {e.x, 0, 0}, {0, 0, -e.z}, {0, 1, 0}, 4);
        }
        return m;
#endif
    }();
    return mesh;
}

// One fixed direction set (spherical Fibonacci), shared by all vertices as in the bake.
const std::vector<Vec3f>& directions() {
    static const std::vector<Vec3f> dirs = [] {
        std::vector<Vec3f> d(kSamples);
        const double golden = 2.399963229728653;  // π(3 − √5)
        for (int i = 0; i < kSamples; ++i) {
            const double z = 1.0 - (2.0 * i + 1.0) / kSamples;
            const double r = std::sqrt(1.0 - z * z), phi = golden * i;
            d[i] = {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
        }
        return d;
    }();
    return dirs;
}

// The rays a bake casts from vertex v: directions above the horizon, into `out`; returns count.
int vertex_rays(const Mesh& m, std::size_t v, Vec3f& origin, Vec3f* out) {
    const Vec3f n = m.normals[v];
    origin = offset_ray_origin(m.positions[v], n);
    int count = 0;
    for (const Vec3f& d : directions())
        if (dot(d, n) > 0.0f) out[count++] = d;
    return count;
}

std::uint64_t rays_per_pass() {
    static const std::uint64_t rays = [] {
        std::uint64_t total = 0;
        std::vector<Vec3f> buf(kSamples);
        Vec3f o;
        for (std::size_t v = 0; v < scene().positions.size(); ++v)
            total += vertex_rays(scene(), v, o, buf.data());
        return total;
    }();
    return rays;
}

// CPU time the tracing threads spent (summed over threads) and which arena slots took part:
// wall-clock rates on a shared machine mean little, rays per thread-CPU-second still do.
struct Usage {
    std::atomic<std::uint64_t> cpu_ns{0};
    std::atomic<std::uint32_t> slots{0};
};
Usage g_usage;

std::uint64_t thread_cpu_ns() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return std::uint64_t(t.tv_sec) * 1000000000ull + std::uint64_t(t.tv_nsec);
}

// Runs body(origin, dirs, count, occluded) for every vertex's rays with `threads` threads.
template <class Body>
void for_all_vertices(int threads, Body&& body) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, scene().positions.size(), 64),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              const std::uint64_t start = thread_cpu_ns();
                              _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
                              _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
                              std::vector<Vec3f> dirs(kSamples);
                              std::vector<std::uint8_t> occ(kSamples);
                              for (std::size_t v = range.begin(); v < range.end(); ++v) {
                                  Vec3f o;
                                  const int n = vertex_rays(scene(), v, o, dirs.data());
                                  body(o, dirs.data(), n, occ.data());
                              }
                              g_usage.cpu_ns += thread_cpu_ns() - start;
                              g_usage.slots |=
                                  1u << (tbb::this_task_arena::current_thread_index() & 31);
                          });
    });
}

void reset_usage() {
    g_usage.cpu_ns = 0;
    g_usage.slots = 0;
}

// Counters: rays/s (wall clock), rays/cpu-s (per thread-CPU-second, summed over threads),
// threads_used (arena slots that did work), occluded fraction.
void set_rate(benchmark::State& state, std::uint64_t occluded) {
    const double rays = double(rays_per_pass()) * double(state.iterations());
    state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
    state.counters["rays/cpu-s"] = rays / (double(g_usage.cpu_ns.load()) * 1e-9);
    state.counters["threads_used"] = double(__builtin_popcount(g_usage.slots.load()));
    state.counters["occluded"] = double(occluded) / double(rays_per_pass());
    state.SetLabel(scene().source + ", " + std::to_string(scene().triangle_count()) + " tris");
}

// Plain Embree: its own device and scene, rtcOccluded1M per vertex in chunks of `chunk` rays.
struct RawEmbree {
    RTCDevice device;
    RTCScene scene_;
    explicit RawEmbree(RTCBuildQuality quality, const char* config = nullptr) {
        device = rtcNewDevice(config);
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        const Mesh& m = scene();
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, m.positions.size()));
        auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, m.triangles.size()));
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            vb[3 * i] = m.positions[i].x;
            vb[3 * i + 1] = m.positions[i].y;
            vb[3 * i + 2] = m.positions[i].z;
        }
        for (std::size_t t = 0; t < m.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) ib[3 * t + k] = m.triangles[t][k];
        rtcSetGeometryBuildQuality(g, quality);
        rtcCommitGeometry(g);
        scene_ = rtcNewScene(device);
        rtcSetSceneBuildQuality(scene_, quality);
        rtcAttachGeometry(scene_, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene_);
    }
    ~RawEmbree() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device);
    }
};

// Device configurations compared: Embree's default, and explicit thread counts (which, with
// TBB tasking, install a process-wide tbb::global_control).
const char* const kDeviceConfigs[] = {nullptr, "threads=1", "threads=2"};

void BM_EmbreeRaw(benchmark::State& state) {
    const int threads = int(state.range(0));
    const int chunk = int(state.range(1));
    const RawEmbree embree(state.range(2) ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM,
                           kDeviceConfigs[state.range(3)]);
    std::atomic<std::uint64_t> occluded{0};
    reset_usage();
    for (auto _ : state) {
        occluded = 0;
        for_all_vertices(threads, [&](Vec3f o, const Vec3f* dirs, int n, std::uint8_t*) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            RTCRay rays[1024];  // chunk ≤ 1024
            std::uint64_t local = 0;
            for (int base = 0; base < n; base += chunk) {
                const int c = std::min(chunk, n - base);
                for (int i = 0; i < c; ++i) {
                    RTCRay& r = rays[i];
                    r.org_x = o.x, r.org_y = o.y, r.org_z = o.z, r.tnear = 0.0f;
                    r.dir_x = dirs[base + i].x, r.dir_y = dirs[base + i].y;
                    r.dir_z = dirs[base + i].z, r.time = 0.0f;
                    r.tfar = INFINITY, r.mask = ~0u, r.id = unsigned(i), r.flags = 0;
                }
                rtcOccluded1M(embree.scene_, &ctx, rays, unsigned(c), sizeof(RTCRay));
                for (int i = 0; i < c; ++i) local += rays[i].tfar < 0.0f;
            }
            occluded += local;
        });
    }
    set_rate(state, occluded);
}
BENCHMARK(BM_EmbreeRaw)
    ->ArgNames({"threads", "chunk", "high", "config"})
    ->Args({1, 256, 0, 0})
    ->Args({2, 256, 0, 0})
    ->Args({2, 64, 0, 0})
    ->Args({2, 1024, 0, 0})
    ->Args({2, 256, 1, 0})
    ->Args({2, 256, 0, 1})
    ->Args({2, 256, 0, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_EmbreeRawSingle(benchmark::State& state) {
    const int threads = int(state.range(0));
    const RawEmbree embree(RTC_BUILD_QUALITY_MEDIUM);
    std::atomic<std::uint64_t> occluded{0};
    reset_usage();
    for (auto _ : state) {
        occluded = 0;
        for_all_vertices(threads, [&](Vec3f o, const Vec3f* dirs, int n, std::uint8_t*) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            std::uint64_t local = 0;
            for (int i = 0; i < n; ++i) {
                RTCRay r;
                r.org_x = o.x, r.org_y = o.y, r.org_z = o.z, r.tnear = 0.0f;
                r.dir_x = dirs[i].x, r.dir_y = dirs[i].y, r.dir_z = dirs[i].z, r.time = 0.0f;
                r.tfar = INFINITY, r.mask = ~0u, r.id = 0, r.flags = 0;
                rtcOccluded1(embree.scene_, &ctx, &r);
                local += r.tfar < 0.0f;
            }
            occluded += local;
        });
    }
    set_rate(state, occluded);
}
BENCHMARK(BM_EmbreeRawSingle)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

template <bool kEmbree>
void BM_Tracer(benchmark::State& state) {
    const int threads = int(state.range(0));
    const auto tracer = kEmbree ? make_embree_tracer(scene()) : make_flat_bvh_tracer(scene());
    std::atomic<std::uint64_t> occluded{0};
    reset_usage();
    for (auto _ : state) {
        occluded = 0;
        for_all_vertices(threads, [&](Vec3f o, const Vec3f* dirs, int n, std::uint8_t* occ) {
            tracer->occluded(o, dirs, n, 0.0f, INFINITY, occ);
            std::uint64_t local = 0;
            for (int i = 0; i < n; ++i) local += occ[i];
            occluded += local;
        });
    }
    set_rate(state, occluded);
}
BENCHMARK(BM_Tracer<true>)
    ->Name("BM_TracerEmbree")
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Tracer<false>)
    ->Name("BM_TracerFlatBvh")
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The flat BVH traversal with build options varied (leaf size, HIGH/MEDIUM), 2 threads.
void BM_FlatBvhOptions(benchmark::State& state) {
    FlatBvhBuildOptions options;
    options.max_leaf_size = int(state.range(0));
    options.high_quality = state.range(1) != 0;
    options.spatial_split_budget = state.range(2) ? 1.5f : 1.0f;
    const FlatBvh bvh = build_flat_bvh(scene(), options);
    const FlatBvhView view = bvh.view();
    std::atomic<std::uint64_t> occluded{0};
    reset_usage();
    for (auto _ : state) {
        occluded = 0;
        for_all_vertices(2, [&](Vec3f o, const Vec3f* dirs, int n, std::uint8_t*) {
            std::uint64_t local = 0;
            for (int i = 0; i < n; ++i) local += bvh_occluded(view, o, dirs[i], 0.0f, INFINITY);
            occluded += local;
        });
    }
    set_rate(state, occluded);
    state.counters["nodes"] = double(bvh.nodes.size());
    state.counters["refs"] = double(bvh.stats.references);
    state.counters["depth"] = double(bvh.stats.max_depth);
    state.counters["sah"] = bvh.stats.sah_cost;
}
BENCHMARK(BM_FlatBvhOptions)
    ->ArgNames({"leaf", "high", "split"})
    ->Args({1, 1, 0})
    ->Args({2, 1, 0})
    ->Args({4, 1, 0})
    ->Args({8, 1, 0})
    ->Args({4, 0, 0})
    ->Args({4, 1, 1})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Validates what the others time: Embree (through Tracer) and the flat BVH give the same
// visibility on every ray of the workload; reports the disagreement rate and fails above 0.1 %.
void BM_ValidateAgreement(benchmark::State& state) {
    const auto embree = make_embree_tracer(scene());
    const auto flat = make_flat_bvh_tracer(scene());
    std::atomic<std::uint64_t> diff{0}, occluded{0};
    for (auto _ : state) {
        diff = 0;
        occluded = 0;
        for_all_vertices(2, [&](Vec3f o, const Vec3f* dirs, int n, std::uint8_t* occ) {
            embree->occluded(o, dirs, n, 0.0f, INFINITY, occ);
            std::uint64_t d = 0, k = 0;
            for (int i = 0; i < n; ++i) {
                std::uint8_t f = 0;
                flat->occluded(o, dirs + i, 1, 0.0f, INFINITY, &f);
                d += f != occ[i];
                k += occ[i];
            }
            diff += d;
            occluded += k;
        });
    }
    const double rate = double(diff) / double(rays_per_pass());
    state.counters["disagree"] = rate;
    state.counters["rays"] = double(rays_per_pass());
    state.counters["occluded"] = double(occluded) / double(rays_per_pass());
    if (rate > 1e-3) state.SkipWithError("Embree and the flat BVH disagree on > 0.1 % of rays");
}
BENCHMARK(BM_ValidateAgreement)->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_BuildEmbree(benchmark::State& state) {
    EmbreeTracerOptions options;
    options.high_quality = state.range(0) != 0;
    for (auto _ : state) benchmark::DoNotOptimize(make_embree_tracer(scene(), options));
    state.SetLabel(scene().source);
}
BENCHMARK(BM_BuildEmbree)
    ->ArgName("high")
    ->Arg(1)
    ->Arg(0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_BuildFlatBvh(benchmark::State& state) {
    FlatBvhBuildOptions options;
    options.high_quality = state.range(0) != 0;
    options.spatial_split_budget = state.range(1) ? 1.5f : 1.0f;
    for (auto _ : state) benchmark::DoNotOptimize(build_flat_bvh(scene(), options));
    state.SetLabel(scene().source);
}
BENCHMARK(BM_BuildFlatBvh)
    ->ArgNames({"high", "split"})
    ->Args({1, 0})
    ->Args({0, 0})
    ->Args({1, 1})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
