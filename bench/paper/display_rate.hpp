// Display-rate stage of the paper study: frames per second at each K of the table, measured by the
// viewer's benchmark (viewer/benchmark.hpp, the code behind `shprt view --benchmark`) on the
// largest bake, truncated to each K, under the sun light with 4× MSAA and an orbiting camera.
#pragma once

#include "paper/lights.hpp"
#include "paper/paper_study.hpp"
#include "paper/stage_log.hpp"

#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

namespace shprt::paper {

// Fills fps and frame_ms of results.rows, and results.gl_context with the benchmark's context,
// size and MSAA; a failure becomes a warning. Does nothing when `opengl` is false (OpenGL did not
// work for the renders). A build without the viewer only adds a warning.
void measure_display_rate(const Mesh& mesh, const TransferSet& largest, const Lights& lights,
                          const Options& options, bool opengl, Results& results,
                          const StageLog& log);

}  // namespace shprt::paper
