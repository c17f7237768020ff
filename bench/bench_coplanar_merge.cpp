// What tracing merged coplanar triangles buys (trace/coplanar_merge.hpp; bench/RESULTS.md,
// "Tracing merged coplanar triangles"):
//  1. merge_coplanar on the room at 20k, 200k and 2M triangles and on real models of Assimp's own
//     test corpus (assimp-testmodels; skipped where it is not installed): triangles before and
//     after, and the merge's time (one thread);
//  2. the room baked with its tracer on the mesh's own triangles and on the merged ones
//     (EmbreeTracerOptions::merge_coplanar), each with a MEDIUM and a HIGH Embree build (merged
//     triangles build MEDIUM whatever is asked since HIGH measured slower on them here, so their
//     two rows now time the same scene), local Sobol at --samples S, interleaved, min of
//     --reps runs: the bake's trace and projection seconds (BakeStats), and whether the rows are
//     the same bits (the program fails where they are not).
//
//     build/bench/bench_coplanar_merge [--samples 2048] [--reps 3] [--threads 2]
#include "shprt/bake/bake.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/trace/coplanar_merge.hpp"
#include "shprt/trace/tracer.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace shprt {
namespace {

using Clock = std::chrono::steady_clock;

void merge_row(const std::string& name, const Mesh& mesh) {
    const auto start = Clock::now();
    const MergedTriangles m = merge_coplanar(mesh);
    const double ms = 1e3 * std::chrono::duration<double>(Clock::now() - start).count();
    std::printf("| %s | %zu | %zu | %.2fx | %.1f | %s |\n", name.c_str(), mesh.triangles.size(),
                m.triangles.size(), double(mesh.triangles.size()) / double(m.triangles.size()), ms,
                m.area_check_failed ? "failed: the mesh's own kept" : "ok");
    std::fflush(stdout);
}

}  // namespace
}  // namespace shprt

int main(int argc, char** argv) {
    using namespace shprt;
    std::uint32_t samples = 2048;
    int reps = 3, threads = 2;
    CLI::App app("Tracing merged coplanar triangles against the mesh's own");
    app.add_option("--samples", samples, "local Sobol samples per receiver");
    app.add_option("--reps", reps, "runs of each tracer (interleaved; the minimum is kept)");
    app.add_option("--threads", threads, "bake threads");
    CLI11_PARSE(app, argc, argv);

    std::printf(
        "\n1. merge_coplanar (one thread)\n\n"
        "| mesh | triangles | merged | fewer | ms | area check |\n"
        "|---|---:|---:|---:|---:|---|\n");
    for (const std::size_t t : {std::size_t(20000), std::size_t(200000), std::size_t(2000000)})
        merge_row("builtin:room, " + std::to_string(t / 1000) + "k requested",
                  generate_room(RoomOptions{t}));
    const std::string corpus = "/usr/share/assimp/models/";
    for (const char* file : {"Collada/duck.dae", "Collada/teapots.DAE", "IFC/AC14-FZK-Haus.ifc",
                             "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"})
        if (std::filesystem::exists(corpus + file)) merge_row(file, load_scene(corpus + file));

    const Mesh room = generate_room(RoomOptions{});
    BakeOptions o;
    o.K = 256;
    o.samples = samples;
    o.seed = 1;
    o.threads = threads;
    o.sampler = SamplerKind::sobol;
    o.direction_frame = DirectionFrame::local;
    const DirectionSet set = bake_direction_set(o);
    std::printf(
        "\n2. builtin:room (%zu vertices), K = %d, local Sobol S = %u, %d threads, "
        "min of %d interleaved runs\n\n"
        "| traced triangles | Embree build | trace s | project s | Mrays | Mrays/s (trace) |\n"
        "|---|---|---:|---:|---:|---:|\n",
        room.vertex_count(), o.K, samples, threads, reps);
    // [merged][high]
    double trace[2][2], project[2][2];
    std::uint64_t rays = 0;
    std::vector<float> rows[2][2];
    for (auto& t : trace) t[0] = t[1] = INFINITY;
    for (auto& p : project) p[0] = p[1] = INFINITY;
    for (int rep = 0; rep < reps; ++rep)
        for (int high = 0; high < 2; ++high)
            for (int merged = 0; merged < 2; ++merged) {
                EmbreeTracerOptions eo;
                eo.high_quality = high != 0;
                eo.merge_coplanar = merged != 0;
                eo.closest_hits = merged == 0;
                const auto tracer = make_embree_tracer(room, eo);
                TransferSet t = bake_with_tracer(room, o, set, *tracer);
                trace[merged][high] = std::min(trace[merged][high], t.stats.seconds_trace);
                project[merged][high] = std::min(project[merged][high], t.stats.seconds_project);
                rays = t.stats.rays_cast;
                rows[merged][high] = std::move(t.coeffs);
            }
    const char* names[2] = {"the mesh's own", "merged"};
    const char* builds[2] = {"MEDIUM", "HIGH"};
    for (int m = 0; m < 2; ++m)
        for (int h = 0; h < 2; ++h)
            std::printf("| %s | %s | %.3f | %.3f | %.1f | %.1f |\n", names[m], builds[h],
                        trace[m][h], project[m][h], double(rays) * 1e-6,
                        double(rays) * 1e-6 / trace[m][h]);
    const bool same =
        rows[0][0] == rows[1][0] && rows[0][0] == rows[0][1] && rows[0][0] == rows[1][1];
    const auto best = [&](int m) { return std::min(trace[m][0], trace[m][1]); };
    std::printf(
        "\ntracing merged: %.2fx the rate (MEDIUM), %.2fx (HIGH), %.2fx (the best of each); "
        "the rows are %s\n",
        trace[0][0] / trace[1][0], trace[0][1] / trace[1][1], best(0) / best(1),
        same ? "the same bits" : "DIFFERENT");
    return same ? 0 : 1;
}
