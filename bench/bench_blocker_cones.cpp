// What blocker cones buy (EmbreeTracerOptions::blocker_cones; trace/tracer.hpp, "Blocker cones";
// bench/RESULTS.md, "Blocker cones"): scenes built like real assets and real models of Assimp's
// test corpus (assimp-testmodels; skipped where it is not installed), each baked with local Sobol
// S = --samples at K = 16 (so that tracing dominates) on an Embree tracer with the cones and one
// without, interleaved, min of --reps runs. Prints the trace seconds (BakeStats, the wall time of
// the parallel phase split by CPU time), the rate, the ratio, and how many receivers' rows are not
// the same bits (a ray whose answer differs changes its row).
//
//     build/bench/bench_blocker_cones [--samples 1024] [--reps 3] [--threads 2]
#include "shprt/bake/bake.hpp"
#include "shprt/core/host.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/trace/tracer.hpp"

#include "bench_cli.hpp"

#include <oneapi/tbb/info.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace shprt {
namespace {

struct Scene {
    std::string name;
    Mesh mesh;
    bool merge = true;  // the tracer's merge_coplanar
};

void row(const Scene& s, const BakeOptions& o, const DirectionSet& set, int reps) {
    double trace[2] = {INFINITY, INFINITY};
    std::vector<float> rows[2];
    std::uint64_t rays = 0;
    for (int rep = 0; rep < reps; ++rep)
        for (int cones = 0; cones < 2; ++cones) {
            EmbreeTracerOptions eo;
            eo.merge_coplanar = s.merge;
            eo.closest_hits = false;
            eo.blocker_cones = cones != 0;
            const auto tracer = make_embree_tracer(s.mesh, eo);
            TransferSet t = bake_with_tracer(s.mesh, o, set, *tracer);
            trace[cones] = std::min(trace[cones], t.stats.seconds_trace);
            rays = t.stats.rays_cast;
            rows[cones] = std::move(t.coeffs);
        }
    std::size_t differ = 0;
    const std::size_t K = std::size_t(o.K), V = rows[0].size() / K;
    for (std::size_t v = 0; v < V; ++v)
        differ +=
            std::memcmp(rows[0].data() + v * K, rows[1].data() + v * K, K * sizeof(float)) ? 1 : 0;
    const double mrays = double(rays) * 1e-6;
    std::printf("| %s | %zu | %s | %.1f | %.3f | %.1f | %.3f | %.1f | %.2fx | %zu of %zu |\n",
                s.name.c_str(), s.mesh.triangles.size(), s.merge ? "merged" : "own", mrays,
                trace[0], mrays / trace[0], trace[1], mrays / trace[1], trace[0] / trace[1], differ,
                V);
    std::fflush(stdout);
}

}  // namespace
}  // namespace shprt

int main(int argc, char** argv) {
    using namespace shprt;
    int samples = 1024, reps = 3, threads = 2;
    bench::BenchCli cli("bench_blocker_cones", "Tracing with blocker cones against without");
    cli.samples(samples).reps(reps).threads(threads);
    cli.parse(argc, argv);
    if (threads <= 0) threads = tbb::info::default_concurrency();

    BakeOptions o;
    o.K = 16;
    o.samples = std::uint32_t(samples);
    o.seed = 1;
    o.threads = threads;
    o.sampler = SamplerKind::sobol;
    o.direction_frame = DirectionFrame::local;
    const DirectionSet set = bake_direction_set(o);
    std::printf(
        "bench_blocker_cones: %s; K = %d, local Sobol S = %u, %d threads, min of %d "
        "interleaved runs\n\n",
        host_cpu().c_str(), o.K, o.samples, threads, reps);
    std::printf(
        "| scene | triangles | traced | Mrays | no cones: trace s | Mrays/s | cones: trace s | "
        "Mrays/s | speed-up | rows not the same bits |\n"
        "|---|---:|---|---:|---:|---:|---:|---:|---:|---|\n");
    std::vector<Scene> scenes;
    for (const char* name : {"room", "leaky_room", "box_on_plane", "corner"})
        scenes.push_back({std::string("builtin:") + name, make_builtin(name), true});
    scenes.push_back({"builtin:room", make_builtin("room"), false});
    const std::string corpus = "/usr/share/assimp/models/";
    for (const char* file : {"IFC/AC14-FZK-Haus.ifc", "Collada/duck.dae", "Collada/teapots.DAE",
                             "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"})
        if (std::filesystem::exists(corpus + file))
            scenes.push_back({file, load_scene(corpus + file), true});
    for (const Scene& s : scenes) row(s, o, set, reps);
    return 0;
}
