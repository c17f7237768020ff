// `shprt compress F.shprt -o G.shprt --cpca CLUSTERS,VECTORS [--probe-cpca C,V] [--half]
// [--light L ...]`: clustered PCA of a file's transfer rows (transfer/cpca.hpp), written as a CPCA
// .shprt file (format version 3), with the error of exit radiance under test lights and views
// (and under the --light given, a --sun kept out of it) and the bytes per vertex; with
// --probe-cpca, the file's transfer probes too (compress_probes). Thin: parses, reads, calls
// compress_transfer and compress_probes, writes atomically, prints (transfer/cpca_summary.hpp).
#include "common/command.hpp"
#include "common/shading_options.hpp"

#include "shprt/bake/bake_option_table.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/transfer/cpca.hpp"
#include "shprt/transfer/cpca_summary.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

struct CompressArgs {
    std::string input, output, cpca, probe_cpca;
    bool half = false, reproducible = false;
    std::uint64_t seed = 1;
    int iterations = 16, threads = 0;
    LightArgs light;  // the error under this light too (common/shading_options.hpp)
};

// "--light a --light b" as given, and the sun kept out of it.
std::string describe_light(const LightArgs& a) {
    std::string out;
    for (const std::string& spec : a.lights) out += (out.empty() ? "--light " : " --light ") + spec;
    if (!a.sun.empty()) out += " (the sun of --sun " + a.sun + " kept out of the SH sum)";
    return out;
}

// CLUSTERS,VECTORS of --cpca or --probe-cpca: two whole numbers ≥ 1.
std::vector<double> parse_cpca(const std::string& option, const std::string& text) {
    const std::vector<double> cv = parse_numbers(text, 2, option + " CLUSTERS,VECTORS");
    SHPRT_CHECK(cv[0] >= 1 && cv[1] >= 1 && cv[0] == std::floor(cv[0]) &&
                    cv[1] == std::floor(cv[1]) && cv[0] < 1e9 && cv[1] < 1e9,
                invalid_argument, "{} {}: CLUSTERS and VECTORS must be whole numbers ≥ 1", option,
                text);
    return cv;
}

// The CPCA options of CLUSTERS,VECTORS `cv` and the shared --seed, --iterations, --threads.
CpcaOptions cpca_options(const CompressArgs& a, const std::vector<double>& cv) {
    CpcaOptions options;
    options.clusters = int(cv[0]);
    options.vectors = int(cv[1]);
    options.seed = a.seed;
    options.iterations = a.iterations;
    options.threads = a.threads;
    return options;
}

// The probes' CPCA (--probe-cpca), printed in two lines; the file's probes replaced by the code.
void compress_file_probes(const CompressArgs& a, const CpcaOptions& options,
                          const LightSetup& setup, TransferSet& out, const ProbeGrid& probes) {
    std::optional<std::vector<float>> light;
    if (!a.light.lights.empty()) light = prepare_light(setup, probes.K).coeffs;
    ProbeCpcaResult r;
    try {
        r = compress_probes(probes, options, light ? &*light : nullptr);
    } catch (const Error& e) {
        fail(e.code(), "{}: --probe-cpca {}: {}", a.input, a.probe_cpca, e.what());
    }
    std::fputs(probe_cpca_summary(r, options, describe_light(a.light)).c_str(), stdout);
    out.probes = std::move(r.compressed);
}

void run(const CompressArgs& a) {
    const std::vector<double> cv = parse_cpca("--cpca", a.cpca);
    const std::vector<double> probe_cv =
        a.probe_cpca.empty() ? std::vector<double>{} : parse_cpca("--probe-cpca", a.probe_cpca);
    SHPRT_CHECK(a.iterations >= 0, invalid_argument, "--iterations {}: must be ≥ 0", a.iterations);
    // As bake's --threads (its row of bake/bake_option_table.hpp).
    check_limits(find_row(bake_option_table(), "threads"), static_cast<long long>(a.threads),
                 Spelling::command_line);
    const bool with_light = !a.light.lights.empty();
    SHPRT_CHECK(with_light || a.light.sun.empty(), invalid_argument,
                "--sun {}: the error is reported under --light SKY; give the sky", a.light.sun);
    const LightSetup setup = light_setup_from(a.light);
    check_output_is_not_input(a.output, input_files(a.input, a.light));
    check_output_writable(a.output);  // a directory, a device: refused before the work
    const ShprtFile file = read_shprt(a.input);
    const TransferSet& t = file.transfer;
    const CpcaOptions options = cpca_options(a, cv);
    check_cpca_fit(t, options, a.input + ": --cpca " + a.cpca);
    // The probes' numbers are checked before the transfer's fit, which may take a while.
    std::optional<CpcaOptions> probe_options;
    if (!probe_cv.empty()) {
        probe_options = cpca_options(a, probe_cv);
        check_probe_cpca_fit(t.probes, *probe_options, a.input + ": --probe-cpca " + a.probe_cpca);
    }
    // The light's SH (never the --sun: prepare_light keeps it out) at the transfer's K.
    std::optional<std::vector<float>> light;
    if (with_light) light = prepare_light(setup, t.layout.K).coeffs;
    CpcaResult r = compress_transfer(t, receiver_normals(file.mesh, t), options, a.half,
                                     light ? &*light : nullptr);
    std::fputs(cpca_summary(t, r, options, a.half, describe_light(a.light)).c_str(), stdout);
    if (probe_options) compress_file_probes(a, *probe_options, setup, r.compressed, t.probes);
    WriteOptions write;
    write.reproducible = a.reproducible;
    write_shprt(a.output, file.mesh, r.compressed, write);
    std::printf("wrote %s\n", a.output.c_str());
}

const bool compress_registered = register_command(
    {"compress", "Compress a .shprt file's transfer with clustered PCA (CPCA)", 36,
     [](CLI::App& app) {
         auto args = std::make_shared<CompressArgs>();
         app.add_option("file", args->input, "Baked .shprt file (glossy matrices or vectors)")
             ->required();
         app.add_option("-o,--output", args->output, "Output .shprt file (CPCA)")->required();
         app.add_option("--cpca", args->cpca,
                        "CLUSTERS,VECTORS: clusters (1 to the vertex count) and PCA vectors "
                        "per cluster (1 to the floats per vertex)")
             ->required();
         app.add_option("--probe-cpca", args->probe_cpca,
                        "CLUSTERS,VECTORS: compress the file's transfer probes too (clusters 1 to "
                        "the valid probes, vectors 1 to channels x K x K); without it they are "
                        "kept as they are");
         app.add_flag("--half", args->half, "Store the code as float16 (not the probes')");
         // --light, --sun, --rotate, --window: the error under that light too.
         add_light_options(app, args->light);
         app.add_option("--seed", args->seed, "Seed of the k-means++ seeding (default 1)");
         app.add_option("--iterations", args->iterations, "Lloyd iterations at most (default 16)");
         app.add_option("--threads", args->threads, "Worker threads (default 0 = all)");
         app.add_flag("--reproducible", args->reproducible,
                      "Leave out what differs between runs (the stats)");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
