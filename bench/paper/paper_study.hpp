// The paper study: the results table of Parubets & Berestneva 2011 reproduced with measurements
// on the built-in room, beside the paper's own numbers. What it measures and why is in
// docs/paper_table.md.
//
// Why a library in bench/, reached through `shprt bench paper`: this is a study of the product,
// not part of it. It evaluates the bakes, the renderer and the viewer against a ground truth and
// writes a report, so it lives beside the other benchmarks, outside the shprt library (which it
// only uses) and outside tools/ (which stay thin shells). It is still built with every
// configuration, because the `shprt bench paper` command that users and the docs know runs it:
// tools/cmd_bench.cpp parses the options, calls run() and prints.
//
// The stages, in the order run() (run.cpp) calls them, one file each: lights.hpp (the two lights),
// ground_truth.hpp (the reference without SH), bake_sweep.hpp (the bakes per basis size),
// quality.hpp (their errors against the truth), renders.hpp (images, the edge measurement, the
// grids), display_rate.hpp (frames per second), sampling_study.hpp, report.hpp (markdown, CSV,
// gnuplot). paper_metrics.hpp holds the measures, image_grid.hpp the labelled picture grid,
// stage_log.hpp the run's clock and its Reporter.
#pragma once

#include "paper/paper_metrics.hpp"

#include "shprt/core/progress.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace shprt::paper {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Options {
    std::string out_dir = "out/paper";
    std::string device = "auto";   // cpu | cuda | both | auto (cpu, and cuda when present)
    std::uint32_t samples = 4096;  // S of the table's bakes
    SamplerKind sampler = SamplerKind::uniform;  // the paper's sampler
    bool extended = false;                       // add full bands 16 … 1024
    bool quick = false;                          // tiny run for tests: small room, few samples
    std::uint32_t gt_samples = 16384;  // ground truth: sky directions per vertex (sun: a quarter)
    std::size_t triangles = 20000;     // room size
    int threads = 0;
    std::uint64_t seed = 1;
    int frames = 30;     // display benchmark: timed frames per K'
    bool study = true;   // the sampling study
    bool images = true;  // renders, image grid, edge measurement, frames/s
};

// The options as `shprt bench paper` takes them, before they are checked: the numbers as typed
// (wide enough for any), the sampler's name, and what is skipped.
struct OptionChoice {
    Options options;
    std::string sampler = "uniform";
    long long samples = 4096, gt_samples = 16384, triangles = 20000, frames = 30, threads = 0;
    bool no_study = false, no_images = false;
};
// The Options of `choice`, checked (one-line Error(invalid_argument) naming the option, e.g.
// "--samples 0: must be in [1, 2^24]"); with `quick`, the sizes left at their defaults shrink to
// a tiny run (a 2000-triangle room, S = 256, a ground truth of 256, 3 frames).
Options options_from(OptionChoice choice);

// What a run says while it works. The study never prints: `shprt bench paper` passes hooks that
// write to stderr and draw progress bars (tools/cmd_bench.cpp). Any hook may be left empty.
struct Reporter {
    // A stage begins or ends: the seconds since the run began and one line of text.
    std::function<void(double seconds, const std::string& line)> stage;
    // A warning outside the stages (plots skipped); it is in Results::warnings as well.
    std::function<void(const std::string& line)> warning;
    // A long operation begins (a bake, a ground-truth pass; `label` names it): returns the
    // ProgressFn to give it (returning false there cancels the run). end_task() follows when the
    // operation ends, also when it throws.
    std::function<ProgressFn(const std::string& label)> begin_task;
    std::function<void()> end_task;
};

// Everything measured for one light at one K.
struct LightScore {
    VertexError error;  // over all vertices, luminance of E
    VertexRinging ringing;
    bool has_contrast = false;  // lit/shadow floor sets exist (sun light)
    ShadowContrast contrast;
    bool has_edge = false;  // the edge image was rendered
    EdgeMeasure edge;
};

struct BakeRun {
    bool ran = false;
    BakeStats stats;
};

// The improved method the table sets beside the paper's: the same S with a low-discrepancy
// sampler (the sampling study's best at S = 4096).
inline constexpr SamplerKind kImprovedSampler = SamplerKind::sobol;

struct KRow {
    int K = 0;
    bool paper_size = false;                // one of the paper's 32, 48, 64, 128, 256
    BakeRun cpu, gpu;                       // the paper's method (options.sampler)
    BakeRun improved;                       // kImprovedSampler, CPU (or GPU with --device cuda)
    double fps = kNaN, frame_ms = kNaN;     // display rate (NaN: not measured)
    LightScore sky, sun;                    // the paper's method
    LightScore sky_improved, sun_improved;  // the improved bake
    LightScore sun_hann, sun_lanczos;       // the improved bake, the sun light windowed
    Profile sun_profile, improved_profile;  // the edge profiles, for the plot
};

struct StudyRow {
    SamplerKind sampler = SamplerKind::uniform;
    std::uint32_t samples = 0;
    double seconds = 0;
    double sky_error = 0, sun_error = 0;  // relative RMSE against the ground truth
    double sky_noise = 0, sun_noise = 0;  // relative RMSE against the converged K-projection
};

struct Results {
    Options options;
    std::string machine, cpu_threads, gpu, gl_context, command;
    std::size_t vertices = 0, triangles = 0;
    std::string sky_spec, sun_spec;  // the two lights as --light specs
    // Ground truth.
    std::uint32_t gt_sky_samples = 0, gt_disc_samples = 0;
    double gt_seconds = 0;
    std::uint64_t gt_rays = 0;
    double gt_sky_noise = 0, gt_sun_noise = 0;  // relative RMSE of the ground truth itself
    bool gt_has_edge = false;
    EdgeMeasure gt_edge;
    Profile gt_profile;
    std::size_t lit_vertices = 0, shadow_vertices = 0;
    // Rows.
    std::vector<KRow> rows;
    int study_K = 64;
    std::uint32_t study_reference_samples = 0;
    std::vector<StudyRow> study;
    std::vector<std::string> warnings;
    std::vector<std::string> files;  // written, relative to out_dir
    double seconds_total = 0;
};

// The paper's table, as printed (PAPER.md "Results reported").
struct PaperColumn {
    int K;
    const char* fps;
    const char* edge_aliasing;
    const char* shadow_fill;
    const char* artifacts;
    const char* cpu;
    const char* gpu;
    double cpu_seconds, gpu_seconds;
};
inline constexpr PaperColumn kPaperColumns[] = {
    {32, "18.5", "sharp", "uneven", "whole scene", "38 s", "42 s", 38, 42},
    {48, "18.5", "noticeable", "even", "whole scene", "62 s", "55 s", 62, 55},
    {64, "18.5", "noticeable", "even", "only at complex geometry", "5 min 42 s", "2 min 15 s", 342,
     135},
    {128, "18.5", "barely noticeable", "even, unsaturated", "only at complex geometry",
     "35 min 12 s", "15 min 6 s", 2112, 906},
    {256, "18.5", "invisible", "even, unsaturated", "only at complex geometry", "4 h 20 min",
     "2 h 18 min", 15600, 8280},
};
const PaperColumn* paper_column(int K);  // nullptr when K is not one of the paper's sizes

// Runs everything and writes the files (see docs/paper_table.md) into options.out_dir; reports
// its progress through `reporter`. `command_line` is quoted in the report. Throws
// Error(unsupported) when options.device asks for a GPU that is not there, and the errors of the
// library (cancelled when a ProgressFn returns false).
Results run(const Options& options, const std::string& command_line, const Reporter& reporter = {});

// Writes paper_table.md, paper_table.csv, sampling_study.csv, edge_profiles.csv and the
// gnuplot plots (when gnuplot is found) into results.options.out_dir; appends to results.files
// (and to results.warnings when the plots are skipped, also reported to reporter.warning).
void write_reports(Results& results, const Reporter& reporter = {});

// The markdown of the main table (also printed at the end of a run).
std::string markdown_table(const Results& results);

}  // namespace shprt::paper
