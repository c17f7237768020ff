// `shprt bench paper`: the paper's results table (Parubets & Berestneva 2011) reproduced with
// measurements on the built-in room, beside the paper's own numbers. What it measures and why is
// in docs/paper_table.md; this header is the data model shared by the run (bench_paper_run.cpp),
// the reports (bench_paper_report.cpp) and the subcommand (cmd_bench.cpp).
#pragma once

#include "paper/paper_metrics.hpp"

#include "shprt/bake/transfer.hpp"
#include "shprt/sh/sampler.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace shprt::tools::paper {

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

// Runs everything and writes the files (see docs/paper_table.md). Prints progress to stderr.
Results run(const Options& options, const std::string& command_line);

// Writes paper_table.md, paper_table.csv, sampling_study.csv, edge_profiles.csv and the
// gnuplot plots (when gnuplot is found) into options.out_dir; appends to results.files.
void write_reports(Results& results);

// The markdown of the main table (also printed at the end of a run).
std::string markdown_table(const Results& results);

}  // namespace shprt::tools::paper
