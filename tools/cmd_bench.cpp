// `shprt bench paper`: the paper's results table reproduced with measurements. The study is the
// library shprt_paper (bench/paper/paper_study.hpp; definitions in docs/paper_table.md); this
// shell parses the options (paper::options_from checks them), runs it with stage lines and progress
// bars on stderr, prints the table.
//
//   shprt bench paper [--device cpu|cuda|both|auto] [--samples S] [--sampler NAME] [--extended]
//                     [--quick] [--gt-samples N] [--triangles N] [--frames N] [--threads N]
//                     [--seed N] [--no-study] [--no-images] [-o DIR]
#include "common/command.hpp"
#include "common/progress_bar.hpp"
#include "paper/paper_study.hpp"

#include <cstdio>
#include <memory>
#include <string>

namespace shprt::tools {
namespace {

void run_paper(const paper::OptionChoice& choice, const std::string& command_line) {
    const paper::Options o = paper::options_from(choice);
    // Stage lines and warnings on stderr (stdout is the table), one progress bar per long task.
    std::unique_ptr<ProgressBar> bar;
    paper::Reporter reporter;
    reporter.stage = [](double seconds, const std::string& line) {
        std::fprintf(stderr, "[%6.1f s] %s\n", seconds, line.c_str());
        std::fflush(stderr);
    };
    reporter.warning = [](const std::string& line) {
        std::fprintf(stderr, "warning: %s\n", line.c_str());
    };
    reporter.begin_task = [&bar](const std::string& label) {
        bar = std::make_unique<ProgressBar>(label);
        return bar->callback();
    };
    reporter.end_task = [&bar] { bar.reset(); };
    const paper::Results r = paper::run(o, command_line, reporter);
    std::printf("%s\n", paper::markdown_table(r).c_str());
    for (const auto& w : r.warnings) std::printf("warning: %s\n", w.c_str());
    std::printf("wrote %zu files to %s (paper_table.md, paper_table.csv, ...) in %.1f s\n",
                r.files.size(), o.out_dir.c_str(), r.seconds_total);
}

const bool bench_registered = register_command(
    {"bench", "Benchmarks: `bench paper` reproduces the paper's table with measurements", 80,
     [](CLI::App& app) {
         app.require_subcommand(1);
         CLI::App* p = app.add_subcommand(
             "paper",
             "The paper's table on the built-in room: precompute time, display rate and "
             "quality against a ground truth, per basis size (docs/paper_table.md)");
         auto args = std::make_shared<paper::OptionChoice>();
         p->add_option("-o,--output", args->options.out_dir,
                       "Output directory (default out/paper)");
         p->add_option("--device", args->options.device,
                       "cpu, cuda, both, or auto (default: CPU, plus the GPU when present)");
         p->add_option("--samples", args->samples, "Directions S per bake (default 4096)");
         p->add_option("--sampler", args->sampler,
                       "Sampler of the table's bakes (default uniform: the paper's)");
         p->add_flag("--extended", args->options.extended,
                     "Add full bands 16, 25, 36, ... 1024 to the paper's sizes");
         p->add_flag("--quick", args->options.quick,
                     "Tiny run (2000-triangle room, S = 256, ground truth 256): for tests");
         p->add_option("--gt-samples", args->gt_samples,
                       "Ground truth: sky directions per vertex (sun: a quarter; default 16384)");
         p->add_option("--triangles", args->triangles, "Room size in triangles (default 20000)");
         p->add_option("--frames", args->frames, "Display benchmark: frames per K' (default 30)");
         p->add_option("--threads", args->threads, "Worker threads (default 0: all)");
         p->add_option("--seed", args->options.seed, "Seed of the bakes (default 1)");
         p->add_flag("--no-study", args->no_study, "Skip the sampling study");
         p->add_flag("--no-images", args->no_images,
                     "Skip renders, the edge measurement and the display rate (no OpenGL)");
         p->callback([args, p] {
             // CLI11 does not keep the raw command line; rebuild it from the options given.
             std::string line = "shprt bench paper";
             for (const CLI::Option* opt : p->get_options()) {
                 if (opt->count() == 0 || opt->get_name() == "--help") continue;
                 line += " " + opt->get_name();
                 if (opt->get_expected_min() > 0) line += " " + opt->as<std::string>();
             }
             run_paper(*args, line);
         });
     }});

}  // namespace
}  // namespace shprt::tools
