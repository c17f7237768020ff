// Adaptive refinement and per-texel transfer on the coarse room (docs/refinement.md,
// docs/texels.md; results in bench/RESULTS.md):
//
//  1. error vs vertex count: the room generated coarse (--triangles 2000) baked on uniformly
//     subdivided meshes (every edge split, levels 0..3) and on adaptively refined meshes
//     (bake --refine) with budgets of a quarter of each uniform level's vertices; the irradiance
//     interpolated over each mesh's triangles is compared, at fixed probe points spread over the
//     surfaces by area, with the no-SH ground truth of `shprt bench paper` (its two lights:
//     bench/paper/lights.hpp; its integrator: bake/ground_truth.hpp): relative RMSE of luminance.
//     The target: refinement reaches the uniform mesh's error with ≤ 1/4 of its vertices.
//     With each: the shadow-edge width of the paper table (`shprt bench paper`'s crop and
//     measure, bench/paper/renders.hpp), also for the texel bake of the coarse room and for the
//     dense room (the paper's 20 000 triangles): the coarse room's should approach the dense's.
//  2. per-receiver cost: a texel bake of the same room (its own UV atlas, scene/uv_atlas.hpp)
//     against the vertex bake of a mesh with about as many vertices, in the same run: the limit
//     is 10 % per receiver.
//
// Usage: bench_refine [--quick] (quick: fewer probes and samples, levels 0..2).
#include "paper/lights.hpp"
#include "paper/renders.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/ground_truth.hpp"
#include "shprt/bake/refine.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/scene/texel_raster.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

using namespace shprt;

namespace {

struct Probe {
    std::uint32_t triangle;  // input triangle
    Vec3f position, normal;
};

double luminance(Vec3d c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Area-weighted random points on the input triangles (fixed seed).
std::vector<Probe> make_probes(const Mesh& mesh, std::size_t count) {
    std::vector<double> cdf;
    double total = 0;
    for (const auto& t : mesh.triangles) {
        const Vec3d a = cast<double>(mesh.positions[t[0]]), b = cast<double>(mesh.positions[t[1]]),
                    c = cast<double>(mesh.positions[t[2]]);
        total += 0.5 * length(cross(b - a, c - a));
        cdf.push_back(total);
    }
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<Probe> probes;
    for (std::size_t i = 0; i < count; ++i) {
        const auto t =
            std::uint32_t(std::lower_bound(cdf.begin(), cdf.end(), u01(rng) * total) - cdf.begin());
        double s = u01(rng), r = u01(rng);
        if (s + r > 1) s = 1 - s, r = 1 - r;
        const auto& tri = mesh.triangles[std::min<std::size_t>(t, mesh.triangle_count() - 1)];
        const double w[3] = {1 - s - r, s, r};
        Vec3d p{0, 0, 0}, n{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            p = p + cast<double>(mesh.positions[tri[k]]) * w[k];
            n = n + cast<double>(mesh.normals[tri[k]]) * w[k];
        }
        probes.push_back({t, cast<float>(p), cast<float>(normalize(n))});
    }
    return probes;
}

// Per-vertex luminance of the irradiance under `light`.
std::vector<double> vertex_luminance(const TransferSet& t, const ShLight& light) {
    std::vector<double> e(t.receiver_count());
    const int K = std::min(t.layout.K, light.K);
    for (std::size_t v = 0; v < e.size(); ++v) {
        Vec3d rgb{0, 0, 0};
        for (int c = 0; c < 3; ++c) {
            double s = 0;
            for (int i = 0; i < K; ++i) s += double(t.receiver(v)[i]) * double(light.channel(c)[i]);
            rgb[c] = s;
        }
        e[v] = luminance(rgb);
    }
    return e;
}

// The value interpolated over `mesh` at each probe: the triangle (among those that came from the
// probe's input triangle) whose barycentrics at the probe are the least negative.
std::vector<double> interpolate(const Mesh& mesh, const std::vector<std::uint32_t>& origin,
                                const std::vector<double>& value, const std::vector<Probe>& probes,
                                std::size_t input_triangles) {
    std::vector<std::vector<std::uint32_t>> bucket(input_triangles);
    for (std::size_t t = 0; t < origin.size(); ++t) bucket[origin[t]].push_back(std::uint32_t(t));
    std::vector<double> out;
    for (const Probe& p : probes) {
        double best = -1e30, v = 0;
        for (std::uint32_t t : bucket[p.triangle]) {
            const auto& tri = mesh.triangles[t];
            const Vec3d a = cast<double>(mesh.positions[tri[0]]),
                        b = cast<double>(mesh.positions[tri[1]]),
                        c = cast<double>(mesh.positions[tri[2]]), q = cast<double>(p.position);
            const Vec3d n = cross(b - a, c - a);
            const double area = dot(n, n);
            if (!(area > 0)) continue;
            const double la = dot(cross(c - b, q - b), n) / area;
            const double lb = dot(cross(a - c, q - c), n) / area;
            const double lc = 1 - la - lb;
            const double least = std::min({la, lb, lc});
            if (least > best) {
                best = least;
                v = la * value[tri[0]] + lb * value[tri[1]] + lc * value[tri[2]];
            }
        }
        out.push_back(v);
    }
    return out;
}

double relative_rmse(const std::vector<double>& a, const std::vector<double>& truth) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        num += (a[i] - truth[i]) * (a[i] - truth[i]);
        den += truth[i] * truth[i];
    }
    return std::sqrt(num / den);
}

}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const int levels = quick ? 2 : 3;
    const std::size_t probe_count = quick ? 4000 : 20000;
    BakeOptions options;
    options.K = 36;                                    // 6 bands
    options.direction_frame = DirectionFrame::sphere;  // as in the recorded tables (RESULTS.md)
    options.samples = quick ? 256 : 1024;
    options.threads = 0;

    Mesh room = generate_room(RoomOptions{2000, false});
    room.source = "builtin:room --triangles 2000";
    const std::size_t T0 = room.triangle_count();
    std::printf("scene: %s, %zu vertices, %zu triangles; K=%d, S=%u (%s)\n", room.source.c_str(),
                room.vertex_count(), T0, options.K, options.samples, to_string(options.sampler));

    const paper::Lights lights = paper::make_lights();
    const ShLight sky = make_light(lights.sky_specs, options.K);
    const ShLight sun = make_light(lights.sun_specs, options.K);
    // The paper table's shadow-edge width (10-90 %, cm) under the sun, when OpenGL works here.
    paper::Results gl_results;
    std::optional<paper::Renders> renders;
    try {
        renders.emplace(room, lights.sun_dir, quick, gl_results);
    } catch (const Error& e) {
        std::printf("shadow-edge widths not measured: %s\n", e.what());
    }
    const auto edge_cm = [&](const Mesh& mesh, const TransferSet& t) {
        if (!renders) return std::numeric_limits<double>::quiet_NaN();
        const paper::EdgeMeasure edge = renders->sun_edge(mesh, t, sun);
        return edge.valid ? 100 * edge.width : std::numeric_limits<double>::quiet_NaN();
    };

    // Ground truth at the probes: the probes as unconnected extra vertices of the room.
    const std::vector<Probe> probes = make_probes(room, probe_count);
    Mesh with_probes = room;
    for (const Probe& p : probes) {
        with_probes.positions.push_back(p.position);
        with_probes.normals.push_back(p.normal);
        with_probes.albedo.push_back({0.8f, 0.8f, 0.8f});
    }
    GroundTruthOptions gt;
    gt.sky_samples = quick ? 1024 : 4096;
    gt.disc_samples = quick ? 256 : 1024;
    const auto gt_start = Clock::now();
    const GroundTruth truth = ground_truth_irradiance(with_probes, lights.truth, gt);
    std::vector<double> truth_sky, truth_sun;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const Vec3d all = truth.irradiance[room.vertex_count() + i];
        const Vec3d s = truth.sky_irradiance[room.vertex_count() + i];
        truth_sky.push_back(luminance(s));
        truth_sun.push_back(luminance(all - s + s * paper::kSunSkyScale));
    }
    // The edge the mesh itself allows: the ground truth at its receivers (vertices, or extra
    // points appended after them), shown through the same renderer (no SH; irradiance_as_transfer
    // under a white light of K = 1).
    const ShLight white = constant_light({1, 1, 1}, 1);
    const auto truth_edge_cm = [&](const Mesh& mesh, const Mesh& receivers, std::size_t first,
                                   TransferSet as) {
        if (!renders) return std::numeric_limits<double>::quiet_NaN();
        const GroundTruth g = ground_truth_irradiance(receivers, lights.truth, gt);
        std::vector<Vec3d> e;
        for (std::size_t v = first; v < g.irradiance.size(); ++v)
            e.push_back(g.irradiance[v] - g.sky_irradiance[v] +
                        g.sky_irradiance[v] * paper::kSunSkyScale);
        const TransferSet t = paper::irradiance_as_transfer(e);
        as.coeffs = t.coeffs;
        as.layout.K = t.layout.K;
        as.layout.channels = t.layout.channels;
        const paper::EdgeMeasure edge = renders->sun_edge(mesh, as, white);
        return edge.valid ? 100 * edge.width : std::numeric_limits<double>::quiet_NaN();
    };
    const auto vertex_truth_edge_cm = [&](const Mesh& mesh) {
        return truth_edge_cm(mesh, mesh, 0, TransferSet{});
    };
    std::printf("ground truth: %zu probes, %u sky + %u sun directions each, %.1f s\n\n",
                probes.size(), gt.sky_samples, gt.disc_samples, seconds_since(gt_start));

    const auto score = [&](const Mesh& mesh, const std::vector<std::uint32_t>& origin,
                           const TransferSet& t, double& sky_err, double& sun_err) {
        sky_err = relative_rmse(interpolate(mesh, origin, vertex_luminance(t, sky), probes, T0),
                                truth_sky);
        sun_err = relative_rmse(interpolate(mesh, origin, vertex_luminance(t, sun), probes, T0),
                                truth_sun);
    };

    std::printf(
        "| mesh | vertices | sky error | sun error | sun edge, cm | truth's edge on it, cm | bake "
        "s "
        "|\n|---|---:|---:|---:|---:|---:|---:|\n");
    struct Row {
        std::size_t vertices;
        double sky, sun;
    };
    std::vector<Row> uniform;
    Mesh mesh = room;
    std::vector<std::uint32_t> origin(T0);
    for (std::size_t t = 0; t < T0; ++t) origin[t] = std::uint32_t(t);
    double uniform_seconds_per_vertex = 0;
    for (int level = 0; level <= levels; ++level) {
        if (level > 0) {
            std::vector<std::array<std::uint32_t, 2>> all;
            for (const auto& t : mesh.triangles)
                for (int k = 0; k < 3; ++k) all.push_back({t[k], t[(k + 1) % 3]});
            split_edges(mesh, all, &origin);
        }
        const auto start = Clock::now();
        const TransferSet t = bake(mesh, options);
        const double seconds = seconds_since(start);
        uniform_seconds_per_vertex = seconds / double(mesh.vertex_count());
        Row row{mesh.vertex_count(), 0, 0};
        score(mesh, origin, t, row.sky, row.sun);
        uniform.push_back(row);
        std::printf("| uniform level %d | %zu | %.4f | %.4f | %.1f | %.1f | %.2f |\n", level,
                    row.vertices, row.sky, row.sun, edge_cm(mesh, t), vertex_truth_edge_cm(mesh),
                    seconds);
    }
    // A quarter of level 1 is fewer vertices than the room has: budgets from level 2 on.
    for (int level = 2; level <= levels; ++level) {
        RefineOptions refine;
        refine.tolerance = 0.005;
        refine.max_vertices = uniform[std::size_t(level)].vertices / 4;
        refine.max_depth = 2 * levels;
        const auto start = Clock::now();
        const RefineResult r = bake_refined(room, options, refine);
        const double seconds = seconds_since(start);
        double sky_err = 0, sun_err = 0;
        score(r.mesh, r.triangle_origin, r.transfer, sky_err, sun_err);
        const Row& u = uniform[std::size_t(level)];
        std::printf(
            "| refined, budget 1/4 of level %d | %zu | %.4f (%.2fx uniform's) | %.4f (%.2fx) | "
            "%.1f | %.1f | %.2f |\n",
            level, r.mesh.vertex_count(), sky_err, sky_err / u.sky, sun_err, sun_err / u.sun,
            edge_cm(r.mesh, r.transfer), vertex_truth_edge_cm(r.mesh), seconds);
    }
    // The same room per texel, and the dense room per vertex: their edges only.
    {
        const int side = quick ? 512 : 1024;
        const TexelSamples texels = rasterize_texels(room, side, side);
        HostSink sink;
        const auto start = Clock::now();
        TransferSet t;
        static_cast<TransferInfo&>(t) = bake(
            BakeJob{&room, texel_receivers(texels), &sink, nullptr, nullptr, nullptr}, options);
        t.texels = texel_atlas(texels, 0);
        t.coeffs = sink.take_rows();
        const double texel_seconds = seconds_since(start);
        Mesh with_texels = room;  // the texel centres as extra, unconnected vertices
        with_texels.positions.insert(with_texels.positions.end(), texels.positions.begin(),
                                     texels.positions.end());
        with_texels.normals.insert(with_texels.normals.end(), texels.normals.begin(),
                                   texels.normals.end());
        with_texels.albedo.insert(with_texels.albedo.end(), texels.albedo.begin(),
                                  texels.albedo.end());
        with_texels.uvs.clear();
        std::printf("| texels %dx%d | %zu texels | | | %.1f | %.1f | %.2f |\n", side, side,
                    texels.count(), edge_cm(room, t),
                    truth_edge_cm(room, with_texels, room.vertex_count(), t), texel_seconds);
        const Mesh dense = generate_room(RoomOptions{});
        const auto dense_start = Clock::now();
        const TransferSet d = bake(dense, options);
        const double dense_seconds = seconds_since(dense_start);
        std::printf("| the dense room (%zu triangles) | %zu | | | %.1f | %.1f | %.2f |\n",
                    dense.triangle_count(), dense.vertex_count(), edge_cm(dense, d),
                    vertex_truth_edge_cm(dense), dense_seconds);
    }

    // Per-receiver cost: texels of the room against vertices of a mesh with about as many.
    const int side = quick ? 128 : 256;
    const TexelSamples texels = rasterize_texels(room, side, side);
    HostSink sink;
    const auto t0 = Clock::now();
    const TransferInfo info =
        bake(BakeJob{&room, texel_receivers(texels), &sink, nullptr, nullptr, nullptr}, options);
    const double texel_seconds = seconds_since(t0);
    // The vertex bake with about as many receivers: uniform subdivision of the room.
    Mesh dense = room;
    while (dense.vertex_count() < texels.count()) {
        std::vector<std::array<std::uint32_t, 2>> all;
        for (const auto& t : dense.triangles)
            for (int k = 0; k < 3; ++k) all.push_back({t[k], t[(k + 1) % 3]});
        split_edges(dense, all);
    }
    const auto t1 = Clock::now();
    const TransferSet vertex_bake = bake(dense, options);
    const double vertex_seconds = seconds_since(t1);
    const double texel_us = 1e6 * texel_seconds / double(texels.count());
    const double vertex_us = 1e6 * vertex_seconds / double(dense.vertex_count());
    const double texel_rays = double(info.stats.rays_cast) / double(texels.count());
    const double vertex_rays = double(vertex_bake.stats.rays_cast) / double(dense.vertex_count());
    std::printf(
        "\ntexels: %dx%d, %zu covered: %.3f s, %.1f us/receiver, %.0f texels/s, %.1f rays each\n"
        "vertices: %zu: %.3f s, %.1f us/receiver, %.0f vertices/s, %.1f rays each\n"
        "texel / vertex cost per receiver: %.3f (limit 1.10); per ray: %.3f\n",
        side, side, texels.count(), texel_seconds, texel_us, 1e6 / texel_us, texel_rays,
        dense.vertex_count(), vertex_seconds, vertex_us, 1e6 / vertex_us, vertex_rays,
        texel_us / vertex_us, (texel_us / texel_rays) / (vertex_us / vertex_rays));
    (void)uniform_seconds_per_vertex;
    return 0;
}
