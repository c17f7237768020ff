// `shprt compress F.shprt -o G.shprt --cpca CLUSTERS,VECTORS [--probe-cpca C,V] [--half]
// [--light L ...]`: clustered PCA of a file's transfer rows (transfer/cpca.hpp), written as a CPCA
// .shprt file (format version 3), with the error of exit radiance under test lights and views
// (and under the --light given, a --sun kept out of it) and the bytes per vertex; with
// --probe-cpca, the file's transfer probes too (compress_probes). Thin: parses, reads, calls
// compress_transfer and compress_probes, writes atomically, prints (transfer/cpca_summary.hpp).
#include "common/command.hpp"
#include "common/option_table.hpp"

#include "shprt/bake/bake_option_table.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
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
    std::string input, output;
    CpcaChoice cpca;  // transfer/cpca_summary.hpp
    bool reproducible = false;
    LightChoice light;  // the error under this light too (light/light_setup.hpp)
};

void run(const CompressArgs& a) {
    const CpcaFits fits = cpca_options_from(a.cpca);
    // As bake's --threads (its row of bake/bake_option_table.hpp).
    check_limits(find_row(bake_option_table(), "threads"), static_cast<long long>(a.cpca.threads),
                 Spelling::command_line);
    const bool with_light = !a.light.light.empty();
    SHPRT_CHECK(with_light || a.light.sun.empty(), invalid_argument,
                "--sun {}: the error is reported under --light SKY; give the sky", a.light.sun);
    const LightSetup setup = light_setup_from(a.light);
    check_output_is_not_input(a.output, input_files(a.input, a.light));
    check_output_writable(a.output);  // a directory, a device: refused before the work
    const ShprtFile file = read_shprt(a.input);
    const TransferSet& t = file.transfer;
    check_cpca_fit(t, fits.transfer, a.input + ": --cpca " + a.cpca.cpca);
    // The probes' numbers are checked before the transfer's fit, which may take a while.
    if (fits.probes)
        check_probe_cpca_fit(t.probes, *fits.probes,
                             a.input + ": --probe-cpca " + a.cpca.probe_cpca);
    // The light's SH (never the --sun: prepare_light keeps it out) at the transfer's K, and at
    // the probes' for theirs.
    std::optional<std::vector<float>> light, probe_light;
    if (with_light) light = prepare_light(setup, t.layout.K).coeffs;
    if (with_light && fits.probes) probe_light = prepare_light(setup, t.probes.K).coeffs;
    SetCompression r = compress_set(t, receiver_normals(file.mesh, t), fits, a.cpca.half, light,
                                    probe_light, a.input + ": --probe-cpca " + a.cpca.probe_cpca);
    std::fputs(compress_summary(t, r, fits, a.cpca.half, describe_light_choice(a.light)).c_str(),
               stdout);
    WriteOptions write;
    write.reproducible = a.reproducible;
    write_shprt(a.output, file.mesh, r.rows.compressed, write);
    std::printf("wrote %s\n", a.output.c_str());
}

const bool compress_registered = register_command(
    {"compress", "Compress a .shprt file's transfer with clustered PCA (CPCA)", 36,
     [](CLI::App& app) {
         auto args = std::make_shared<CompressArgs>();
         app.add_option("file", args->input, "Baked .shprt file (glossy matrices or vectors)")
             ->required();
         app.add_option("-o,--output", args->output, "Output .shprt file (CPCA)")->required();
         const auto& table = cpca_option_table();
         add_table_options(app, table, args->cpca, {}, {"cpca", "probe_cpca", "half"});
         app.get_option("--cpca")->required();
         // --light, --sun, --rotate, --window: the error under that light too.
         add_table_options(app, light_option_table(), args->light);
         add_table_options(app, table, args->cpca, {"cpca", "probe_cpca", "half"});
         app.add_flag("--reproducible", args->reproducible,
                      "Leave out what differs between runs (the stats)");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
