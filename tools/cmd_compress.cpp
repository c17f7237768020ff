// `shprt compress F.shprt -o G.shprt --cpca CLUSTERS,VECTORS [--half] [--light L ...]`:
// clustered PCA of a file's transfer rows (transfer/cpca.hpp), written as a CPCA .shprt file
// (format version 3), with the error of exit radiance under test lights and views (and under
// the --light given, a --sun kept out of it) and the bytes per vertex. Thin:
// parses, reads, calls compress_transfer, writes atomically, prints.
#include "common/command.hpp"
#include "common/shading_options.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/transfer/cpca.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

struct CompressArgs {
    std::string input, output, cpca;
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

void run(const CompressArgs& a) {
    const std::vector<double> cv = parse_numbers(a.cpca, 2, "--cpca CLUSTERS,VECTORS");
    SHPRT_CHECK(cv[0] >= 1 && cv[1] >= 1 && cv[0] == std::floor(cv[0]) &&
                    cv[1] == std::floor(cv[1]) && cv[0] < 1e9 && cv[1] < 1e9,
                invalid_argument, "--cpca {}: CLUSTERS and VECTORS must be whole numbers ≥ 1",
                a.cpca);
    SHPRT_CHECK(a.iterations >= 0, invalid_argument, "--iterations {}: must be ≥ 0", a.iterations);
    // As bake's --threads (common/bake_options.cpp).
    SHPRT_CHECK(a.threads >= 0 && a.threads <= kMaxBakeThreads, invalid_argument,
                "--threads {}: must be 0 (all) to {}", a.threads, kMaxBakeThreads);
    const bool with_light = !a.light.lights.empty();
    SHPRT_CHECK(with_light || a.light.sun.empty(), invalid_argument,
                "--sun {}: the error is reported under --light SKY; give the sky", a.light.sun);
    const LightSetup setup = light_setup_from(a.light);
    check_output_is_not_input(a.output, input_files(a.input, a.light));
    check_output_writable(a.output);  // a directory, a device: refused before the work
    const ShprtFile file = read_shprt(a.input);
    const TransferSet& t = file.transfer;
    const std::size_t V = t.receiver_count();
    const std::size_t D = t.layout.floats_per_receiver();
    // The receivers, named in what is printed: vertices, or texels.
    const char* unit = to_string(t.layout.domain);
    const char* units = t.layout.domain == ReceiverDomain::texel ? "texels" : "vertices";
    SHPRT_CHECK(cv[0] <= double(V), invalid_argument,
                "{}: --cpca {}: {} clusters for {} {} (at most one per {})", a.input, a.cpca, cv[0],
                V, units, unit);
    SHPRT_CHECK(cv[1] <= double(D), invalid_argument,
                "{}: --cpca {}: {} vectors, more than the {} floats of a {} ({} transfer, "
                "K = {}; a symmetric K×K matrix stores K(K+1)/2 ≤ K²)",
                a.input, a.cpca, cv[1], D, unit, to_string(t.layout.shape), t.layout.K);
    CpcaOptions options;
    options.clusters = int(cv[0]);
    options.vectors = int(cv[1]);
    options.seed = a.seed;
    options.iterations = a.iterations;
    options.threads = a.threads;
    // The light's SH (never the --sun: prepare_light keeps it out) at the transfer's K.
    std::optional<std::vector<float>> light;
    if (with_light) light = prepare_light(setup, t.layout.K).coeffs;
    const CpcaResult r = compress_transfer(t, receiver_normals(file.mesh, t), options, a.half,
                                           light ? &*light : nullptr);
    WriteOptions write;
    write.reproducible = a.reproducible;
    write_shprt(a.output, file.mesh, r.compressed, write);

    const TransferError& e = r.error;
    std::vector<float> sorted = e.receiver_rmse;
    std::sort(sorted.begin(), sorted.end());
    const auto pct = [&](double q) {
        return 100.0 * sorted[std::min(sorted.size() - 1, std::size_t(q * double(sorted.size())))];
    };
    std::printf(
        "cpca: %d clusters x %d vectors (k-means++ seed %llu, at most %d Lloyd iterations), "
        "%s, fit %.3f s\n",
        options.clusters, options.vectors, static_cast<unsigned long long>(a.seed), a.iterations,
        a.half ? "float16" : "float32", r.seconds_fit);
    std::printf(
        "size: %.1f B/%s (raw float32: %.0f B/%s as stored, %.0f B/%s as full matrices) = "
        "%.1fx / %.1fx smaller\n",
        r.bytes_per_receiver, unit, r.raw_bytes_per_receiver, unit, r.raw_full_bytes_per_receiver,
        unit, r.raw_bytes_per_receiver / r.bytes_per_receiver,
        r.raw_full_bytes_per_receiver / r.bytes_per_receiver);
    if (r.direct_bytes_per_receiver > 0)
        std::printf("direct part: kept beside the code (--direct), %.0f B/%s\n",
                    r.direct_bytes_per_receiver, unit);
    std::printf(
        "error: exit radiance relative RMSE %.3f%% (8 test lights x %s); per %s (RMSE / "
        "scene RMS): median %.3f%%, p99 %.3f%%, max %.3f%%\n",
        100.0 * e.relative_rmse, t.layout.shape == TransferShape::vector ? "diffuse" : "5 views",
        unit, pct(0.5), pct(0.99), pct(1.0));
    if (r.light_error)
        std::printf("error under %s: exit radiance relative RMSE %.3f%% (%s)\n",
                    describe_light(a.light).c_str(), 100.0 * r.light_error->relative_rmse,
                    t.layout.shape == TransferShape::vector ? "diffuse" : "5 views");
    std::string worst;
    for (std::size_t i = 0; i < std::min<std::size_t>(5, e.worst.size()); ++i)
        worst += fmt::format("{}{} ({:.2f}%)", i ? ", " : "", e.worst[i],
                             100.0 * e.receiver_rmse[e.worst[i]]);
    std::printf("worst %s: %s\n", units, worst.c_str());
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
         app.add_flag("--half", args->half, "Store the code as float16");
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
