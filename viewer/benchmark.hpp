// `shprt view FILE --benchmark FRAMES`: display speed against basis size. For each K' of
// BenchmarkOptions::K_values that the file has (K' ≤ K), renders FRAMES frames offscreen with the
// viewer's own frame (frame.hpp: scene into the MSAA float target, resolve, tone-mapped present
// into an 8-bit framebuffer), the camera orbiting the target by a full turn over the frames so
// that every frame differs, and glFinish after each frame so that the time measured is the time
// the frame took to be drawn. Reports frames/s and the mean, fastest and slowest frame.
//
// The paper claims the display cost does not depend on the basis size; the report's ratio of
// the mean frame time at K' = 256 to that at K' = 32 measures it.
#pragma once

#include "frame.hpp"
#include "light_rig.hpp"
#include "lit_object.hpp"
#include "offscreen_context.hpp"

#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace shprt::viewer {

struct BenchmarkOptions {
    int frames = 100;       // timed frames per K', ≥ 1
    int warmup_frames = 3;  // untimed frames first (shader compilation, first uploads)
    std::vector<int> K_values = {32, 48, 64, 128, 256};
    // Also turn the light a little every frame (an SH rotation on the CPU + upload), as when the
    // user drags it: measures the cost of a light change, not only of a camera change.
    bool rotate_light = false;
    OffscreenBackend backend = OffscreenBackend::automatic;
    // A probe-lit object (docs/probes.md), moved every frame along a line of the grid through its
    // start position (±0.5 m in x) and so shaded on the CPU and uploaded every frame: the cost of
    // dragging it. None: object.object null.
    ViewerObject object;
};

struct BenchmarkRow {
    int K_used = 0;
    bool skipped = false;  // K' > the file's K (or the light's)
    int frames = 0;
    double seconds = 0;  // all timed frames
    double fps = 0;      // frames / seconds
    double mean_ms = 0, min_ms = 0, max_ms = 0;
    // Mean CPU time of the whole process per frame (all threads: llvmpipe's rasteriser threads
    // included), milliseconds. On a loaded machine wall time overstates the cost; this does not.
    double cpu_ms = 0;
};

struct BenchmarkReport {
    std::string context;  // OffscreenContext::description()
    std::string host;     // host_cpu(): the CPU llvmpipe runs on, or the one beside the GPU
    std::size_t vertices = 0, triangles = 0;
    int K = 0;  // the file's (and the light's) K
    int width = 0, height = 0, msaa = 0;
    int shadow_map = 0;                      // texels a side of the sun's map (0: no sun)
    double shadow_texel = 0;                 // its texel, world units
    SunFilter sun_filter = SunFilter::full;  // the map's filter (choose_sun_filter)
    int moving_shadow_map = 0;  // texels a side of the map while moving (0: the same map)
    bool msaa_auto = false;     // msaa chosen by choose_samples, not by --msaa
    // Frames drawn straight into the 8-bit target (Renderer::draw_to_display), not through a
    // float target and the present pass (FrameTarget).
    bool direct = false;
    double k = 1;          // diffuse share drawn
    std::string transfer;  // glossy: describe_gpu_transfer and the BRDF ("" for vectors)
    bool rotate_light = false;
    std::size_t object_vertices = 0;  // the moving object's, 0 = none
    double object_ms = 0;             // its mean CPU shading + upload per frame, milliseconds
    std::vector<BenchmarkRow> rows;
    // Mean frame time at K' = 256 over that at K' = 32; 0 when either was skipped.
    double ratio_256_32 = 0;
};

// Runs the benchmark (see top) with `config`'s size, MSAA, exposure and draw settings (its
// K_used is replaced by each K'); the light comes from `rig` (a source must be set; a copy is
// rotated when options.rotate_light). Throws Error(invalid_argument) for frames < 1 or an empty
// K list, and what OffscreenContext and Renderer throw.
BenchmarkReport run_benchmark(const Mesh& mesh, const TransferSet& transfer, const LightRig& rig,
                              const FrameConfig& config, const BenchmarkOptions& options);

// The report as text: a header line (a second one for glossy transfer), one line per K' ("K'=256
// frames=100  fps=41.2 mean_ms=24.27  min_ms=23.10  max_ms=27.91  cpu_ms=40.12" or "K'=256 skipped:
// ..."), and the ratio line.
std::string format_benchmark(const BenchmarkReport& report);

}  // namespace shprt::viewer
