// Ground-truth stage of the paper study (ground_truth.hpp).
#include "paper/ground_truth.hpp"

#include "shprt/bake/ground_truth.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <span>

namespace shprt::paper {
namespace {

Truth split_truth(const GroundTruth& gt) {
    Truth t;
    const std::size_t V = gt.irradiance.size();
    t.sky = gt.sky_irradiance;
    t.sun.resize(V);
    for (std::size_t v = 0; v < V; ++v)
        t.sun[v] = gt.irradiance[v] - gt.sky_irradiance[v] + gt.sky_irradiance[v] * kSunSkyScale;
    t.sky_y = luminance(std::span<const Vec3d>(t.sky));
    t.sun_y = luminance(std::span<const Vec3d>(t.sun));
    t.sun_visibility = gt.disc_visibility;
    return t;
}

Truth average_truth(const Truth& a, const Truth& b) {
    Truth t = a;
    for (std::size_t v = 0; v < a.sky.size(); ++v) {
        t.sky[v] = (a.sky[v] + b.sky[v]) * 0.5;
        t.sun[v] = (a.sun[v] + b.sun[v]) * 0.5;
        t.sun_visibility[v] = 0.5f * (a.sun_visibility[v] + b.sun_visibility[v]);
    }
    t.sky_y = luminance(std::span<const Vec3d>(t.sky));
    t.sun_y = luminance(std::span<const Vec3d>(t.sun));
    return t;
}

// The ground truth's own error: two independent estimates a, b (different scrambles) have
// RMSE(a − b) = √2·σ, and their mean has σ/√2 = RMSE(a − b)/2.
double truth_noise(const std::vector<double>& a, const std::vector<double>& b) {
    const VertexError e = vertex_error(a, b);
    return 0.5 * e.rmse / e.mean_reference;
}

// FloorSets (ground_truth.hpp): open to the sky means at least kOpenFloor of the floor's largest
// sky irradiance, where nothing is seen.
constexpr double kOpenFloor = 0.25;

FloorSets floor_sets(const Mesh& mesh, const std::vector<float>& visibility,
                     const std::vector<double>& sky_y) {
    FloorSets f;
    const std::size_t V = mesh.vertex_count();
    f.lit.assign(V, 0);
    f.shadow.assign(V, 0);
    const auto is_floor = [&](std::size_t v) {
        return std::fabs(mesh.positions[v].y) < 1e-5f && mesh.normals[v].y > 0.999f;
    };
    double max_sky = 0;
    for (std::size_t v = 0; v < V; ++v)
        if (is_floor(v)) max_sky = std::max(max_sky, sky_y[v]);
    for (std::size_t v = 0; v < V; ++v) {
        if (!is_floor(v) || visibility[v] < 0 || sky_y[v] < kOpenFloor * max_sky) continue;
        if (visibility[v] >= 0.999f) f.lit[v] = 1, ++f.lit_count;
        if (visibility[v] <= 0.001f) f.shadow[v] = 1, ++f.shadow_count;
    }
    return f;
}

}  // namespace

Truth compute_ground_truth(const Mesh& mesh, const Lights& lights, const Options& o, Results& res,
                           const StageLog& stage) {
    res.gt_sky_samples = o.gt_samples;
    res.gt_disc_samples = std::max<std::uint32_t>(1, o.gt_samples / 4);
    Truth passes[2];
    for (int pass = 0; pass < 2; ++pass) {
        stage.say(fmt::format("ground truth pass {}/2: {} sky + {} sun directions per vertex",
                              pass + 1, res.gt_sky_samples, res.gt_disc_samples));
        GroundTruthOptions g;
        g.sky_samples = res.gt_sky_samples;
        g.disc_samples = res.gt_disc_samples;
        g.seed = o.seed + 1000 * std::uint64_t(pass + 1);
        g.threads = o.threads;
        Task task(stage, "ground truth");
        g.progress = task.progress();
        const GroundTruth gt = ground_truth_irradiance(mesh, lights.truth, g);
        task.end();
        res.gt_seconds += gt.seconds;
        res.gt_rays += gt.rays_cast;
        passes[pass] = split_truth(gt);
    }
    res.gt_sky_noise = truth_noise(passes[0].sky_y, passes[1].sky_y);
    res.gt_sun_noise = truth_noise(passes[0].sun_y, passes[1].sun_y);
    Truth truth = average_truth(passes[0], passes[1]);
    truth.floor = floor_sets(mesh, truth.sun_visibility, truth.sky_y);
    const FloorSets& sets = truth.floor;
    res.lit_vertices = sets.lit_count;
    res.shadow_vertices = sets.shadow_count;
    stage.say(
        fmt::format("ground truth: {:.1f} s, {} rays; own error {:.3f} % (sky), {:.3f} % "
                    "(sun); floor: {} lit, {} shadowed vertices",
                    res.gt_seconds, res.gt_rays, 100 * res.gt_sky_noise, 100 * res.gt_sun_noise,
                    sets.lit_count, sets.shadow_count));
    return truth;
}

}  // namespace shprt::paper
