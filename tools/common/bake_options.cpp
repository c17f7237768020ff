// Bake options shared by `shprt bake` and `shprt view --bake` (bake_options.hpp).
#include "common/bake_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/sh/basis.hpp"

#include <limits>

namespace shprt::tools {

void add_bake_options(CLI::App& app, BakeOptionArgs& args) {
    app.add_option("--transfer", args.transfer, "unshadowed or shadowed (default)");
    app.add_option("--bands", args.bands,
                   fmt::format("SH bands n (K = n², 1 to {}); default 4", kMaxComputeBands));
    app.add_option(
        "--coeffs", args.coeffs,
        fmt::format("Basis size K, 1 to {} (need not be a square); default 16", kMaxBakeCoeffs));
    app.add_option("--samples", args.samples, "Directions per vertex S (default 1024)");
    app.add_option("--sampler", args.sampler,
                   "sobol (default: 7x lower error than the paper's set at the same cost), "
                   "uniform (the paper's), stratified or fibonacci");
    app.add_option("--seed", args.seed, "Seed of the direction set (default 1)");
    app.add_option("--threads", args.threads, "Worker threads (default 0 = all)");
    app.add_option("--device", args.device, "cpu (default), cuda or auto");
    app.add_option("--device-index", args.device_index,
                   "CUDA device for --device cuda|auto (default 0)");
}

// The CLI turns its text and wide integers into BakeOptions, naming the option it cannot convert;
// the ranges are the library's (bake.hpp), and bake() checks them again at its boundary.
BakeOptions bake_options_from(const BakeOptionArgs& a) {
    BakeOptions o;
    o.transfer = parse_transfer_kind(a.transfer);
    o.sampler = parse_sampler_kind(a.sampler);
    o.device = parse_device(a.device);
    SHPRT_CHECK(!(a.bands && a.coeffs), invalid_argument,
                "--bands and --coeffs both given; use one (K = bands²)");
    if (a.bands) {
        const int max_bands = kMaxComputeBands;
        SHPRT_CHECK(*a.bands >= 1 && *a.bands <= max_bands, invalid_argument,
                    "--bands {}: must be 1 to {} (K = bands², at most {})", *a.bands, max_bands,
                    kMaxBakeCoeffs);
        o.K = sh_count(static_cast<int>(*a.bands));
    } else if (a.coeffs) {
        SHPRT_CHECK(*a.coeffs >= 1 && *a.coeffs <= kMaxBakeCoeffs, invalid_argument,
                    "--coeffs {}: must be 1 to {}", *a.coeffs, kMaxBakeCoeffs);
        o.K = static_cast<int>(*a.coeffs);
    }
    SHPRT_CHECK(a.samples >= 1 && a.samples <= kMaxBakeSamples, invalid_argument,
                "--samples {}: must be 1 to {}", a.samples, kMaxBakeSamples);
    o.samples = static_cast<std::uint32_t>(a.samples);
    o.seed = a.seed;
    SHPRT_CHECK(a.threads >= 0 && a.threads <= kMaxBakeThreads, invalid_argument,
                "--threads {}: must be 0 (all) to {}", a.threads, kMaxBakeThreads);
    o.threads = static_cast<int>(a.threads);
    SHPRT_CHECK(a.device_index >= 0 && a.device_index <= std::numeric_limits<int>::max(),
                invalid_argument, "--device-index {}: must be 0 or more", a.device_index);
    o.device_index = static_cast<int>(a.device_index);
    validate(o);
    return o;
}

}  // namespace shprt::tools
