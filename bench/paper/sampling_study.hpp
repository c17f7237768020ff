// Sampling-study stage of the paper study: at one K, for each sampler and S, the error of the bake
// against the ground truth and its noise against the converged projection (a Sobol bake with 4×
// the largest S, independently scrambled).
#pragma once

#include "paper/ground_truth.hpp"
#include "paper/lights.hpp"
#include "paper/paper_study.hpp"
#include "paper/stage_log.hpp"

#include "shprt/scene/mesh.hpp"

namespace shprt::paper {

// K = 64 and S = 64, 256, 1024, 4096 (with options.quick: K = 16, S = 64, 256), every sampler;
// CPU bakes through one Embree tracer. Fills results.study_K, study_reference_samples and study.
void run_sampling_study(const Mesh& mesh, const Lights& lights, const Truth& truth,
                        const Options& options, Results& results, const StageLog& log);

}  // namespace shprt::paper
