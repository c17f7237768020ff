// Ground-truth stage of the paper study: per-vertex irradiance of the two lights computed without
// SH (direct Monte Carlo of L·V·cos, bake/ground_truth.hpp) in two independent passes, averaged;
// their difference estimates the truth's own error. Also the floor vertices that the shadow
// contrast is measured on.
#pragma once

#include "paper/lights.hpp"
#include "paper/paper_study.hpp"
#include "paper/stage_log.hpp"

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt::paper {

// Floor vertices (y = 0, normal +Y) open to the sky (the truth's sky irradiance at least a quarter
// of the floor's largest: not under the sofa, the bookshelf or the rug) and fully in the sun
// (lit: visibility ≥ 0.999) or fully out of it (shadow: ≤ 0.001). Masks of vertex_count().
struct FloorSets {
    std::vector<std::uint8_t> lit, shadow;
    std::size_t lit_count = 0, shadow_count = 0;
};

// Per-vertex RGB irradiance of the two lights: the sky light is the truth's sky part; the sun
// light is the disc part plus kSunSkyScale × the sky part.
struct Truth {
    std::vector<Vec3d> sky, sun;
    std::vector<double> sky_y, sun_y;  // luminance
    std::vector<float> sun_visibility;
    FloorSets floor;
};

// Runs both passes (options.gt_samples sky and a quarter as many sun directions per vertex, seeds
// options.seed + 1000 and + 2000) and returns their mean. Fills results.gt_sky_samples,
// gt_disc_samples, gt_seconds, gt_rays, gt_sky_noise, gt_sun_noise, lit_vertices and
// shadow_vertices.
Truth compute_ground_truth(const Mesh& mesh, const Lights& lights, const Options& options,
                           Results& results, const StageLog& log);

}  // namespace shprt::paper
