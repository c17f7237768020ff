// Quality stage of the paper study: the SH shading of a bake against the ground truth, per vertex,
// with the measures of paper_metrics.hpp (definitions in docs/paper_table.md).
#pragma once

#include "paper/ground_truth.hpp"
#include "paper/paper_study.hpp"

#include "shprt/light/light.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <vector>

namespace shprt::paper {

// Luminance of the per-vertex irradiance that shade_vertices (shade/shade.hpp) gives for `light`.
std::vector<double> shade_luminance(const Mesh& mesh, const TransferSet& transfer,
                                    const ShLight& light);

// Scores row.K's bakes against the truth: row.sky and row.sun (the paper's bake), row.sky_improved
// and row.sun_improved (the improved bake), row.sun_hann and row.sun_lanczos (the improved bake
// under the sun light with a Hann or a Lanczos window). Each gets the error and the ringing over
// all vertices; the sun lights also the shadow contrast on truth.floor, when both sets exist.
void score_row(KRow& row, const Mesh& mesh, const TransferSet& paper, const TransferSet& improved,
               const ShLight& sky, const ShLight& sun, const Truth& truth);

}  // namespace shprt::paper
