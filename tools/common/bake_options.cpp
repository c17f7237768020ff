// Bake options shared by `shprt bake` and `shprt view --bake` (bake_options.hpp).
#include "common/bake_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/sh/basis.hpp"

#include <cmath>
#include <limits>

namespace shprt::tools {

void add_bake_options(CLI::App& app, BakeOptionArgs& args) {
    app.add_option("--transfer", args.transfer,
                   "unshadowed, shadowed (default), interreflected (RGB, with bounces) or glossy "
                   "(K×K matrices, at most 8 bands)");
    app.add_option("--bands", args.bands,
                   fmt::format("SH bands n (K = n², 1 to {}); default 4 (glossy: 5, at most 8)",
                               kMaxComputeBands));
    app.add_option(
        "--coeffs", args.coeffs,
        fmt::format("Basis size K, 1 to {} (need not be a square); default 16 (4 bands: smooth "
                    "skies; a sun projected into SH wants more, e.g. the paper's 256)",
                    kMaxBakeCoeffs));
    app.add_option("--samples", args.samples,
                   "Directions per vertex S (default 1024; not used with --target-error)");
    app.add_option("--target-error", args.target_error,
                   fmt::format("Error-bounded bake: each receiver gets the smallest prefix {}, "
                               "{}, ... of the nested set whose estimated relative error is at "
                               "most E (e.g. 0.01; above 0, at most 1; default 0 = off: every "
                               "receiver gets --samples). Shadowed or unshadowed, sobol or "
                               "uniform, CPU; docs/sampling.md",
                               kTargetFirstSamples, 2 * kTargetFirstSamples));
    app.add_option("--max-samples", args.max_samples,
                   fmt::format("--target-error: the most directions a receiver gets, a power of "
                               "two {} to {} (default 0 = {})",
                               kTargetFirstSamples, kMaxBakeSamples, kDefaultMaxSamples));
    app.add_option("--sampler", args.sampler,
                   "sobol (default: 7x lower error than the paper's set at the same cost), "
                   "uniform (the paper's), stratified or fibonacci");
    app.add_option("--directions", args.directions,
                   "sphere (default: one set on the sphere, the paper's) or local (one "
                   "cosine-weighted set in each receiver's tangent frame: every ray above the "
                   "horizon; docs/sampling.md)");
    app.add_option("--seed", args.seed, "Seed of the direction set (default 1)");
    app.add_option("--threads", args.threads, "Worker threads (default 0 = all)");
    app.add_option("--device", args.device, "cpu (default), cuda or auto");
    app.add_option("--device-index", args.device_index,
                   "CUDA device for --device cuda|auto (default 0)");
    app.add_option("--max-device-memory", args.max_device_memory,
                   "--device cuda|auto: the GPU memory the bake may use (512M, 4G, ...; default "
                   "90% of what is free); interreflected bounces copy in what does not fit");
    app.add_option(
        "--bounces", args.bounces,
        fmt::format("Interreflected: bounces N (0 to {}; default 1) or 'converged'", kMaxBounces));
    app.add_option("--tolerance", args.tolerance,
                   "Interreflected, --bounces converged: stop when no vertex's transfer changes "
                   "by more than this fraction (default 1e-4)");
    app.add_option("--albedo", args.albedo,
                   "Interreflected: albedo R,G,B (linear, 0 to 1) for every vertex (default: the "
                   "scene's vertex colours, else its materials' diffuse colour, else 0.8 grey)");
    app.add_flag("--two-sided", args.two_sided,
                 "Interreflected: a back face reflects the light on its own side, as a renderer "
                 "does (default: it brings nothing; docs/interreflection.md says which to pick)");
    app.add_option("--indirect-samples", args.indirect_samples,
                   fmt::format("Interreflected: directions per receiver for the bounces (the "
                               "first of the bake's set; default --samples / {})",
                               kIndirectSampleShare));
    app.add_option("--source-spacing", args.source_spacing,
                   "Interreflected: the bounce sources' cell size in metres (default: the "
                   "scene's diagonal / 48), or 'vertices' for the mesh's vertices alone");
    app.add_option("--bounce-coeffs", args.bounce_coeffs,
                   fmt::format("Interreflected: coefficients the light carries from its second "
                               "bounce on (default {}, at most K; the first bounce keeps all K)",
                               kDefaultBounceCoeffs));
}

Vec3f parse_albedo(const std::string& text) {
    const std::vector<double> rgb = parse_numbers(text, 3, "--albedo R,G,B");
    for (double c : rgb)
        SHPRT_CHECK(c >= 0.0 && c <= 1.0, invalid_argument,
                    "--albedo {}: each component must be 0 to 1 (linear reflectance)", text);
    return Vec3f{float(rgb[0]), float(rgb[1]), float(rgb[2])};
}

void apply_albedo_option(const BakeOptionArgs& args, Mesh& mesh) {
    if (args.albedo.empty()) return;
    mesh.albedo.assign(mesh.vertex_count(), parse_albedo(args.albedo));
    mesh.albedo_source = "--albedo " + args.albedo;
}

// The CLI turns its text and wide integers into BakeOptions, naming the option it cannot convert;
// the ranges are the library's (bake.hpp), and bake() checks them again at its boundary.
BakeOptions bake_options_from(const BakeOptionArgs& a) {
    BakeOptions o;
    o.transfer = parse_transfer_kind(a.transfer);
    o.sampler = parse_sampler_kind(a.sampler);
    o.direction_frame = parse_direction_frame(a.directions);
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
    } else {
        o.K = default_coeffs(o.transfer);
    }
    SHPRT_CHECK(a.samples >= 1 && a.samples <= kMaxBakeSamples, invalid_argument,
                "--samples {}: must be 1 to {}", a.samples, kMaxBakeSamples);
    o.samples = static_cast<std::uint32_t>(a.samples);
    set_error_bound(o, a.target_error, a.max_samples, "--target-error ", "--max-samples ");
    o.seed = a.seed;
    SHPRT_CHECK(a.threads >= 0 && a.threads <= kMaxBakeThreads, invalid_argument,
                "--threads {}: must be 0 (all) to {}", a.threads, kMaxBakeThreads);
    o.threads = static_cast<int>(a.threads);
    SHPRT_CHECK(a.device_index >= 0 && a.device_index <= std::numeric_limits<int>::max(),
                invalid_argument, "--device-index {}: must be 0 or more", a.device_index);
    o.device_index = static_cast<int>(a.device_index);
    if (!a.max_device_memory.empty()) {
        SHPRT_CHECK(parse_byte_size(a.max_device_memory, o.device_memory_budget) &&
                        o.device_memory_budget > 0,
                    invalid_argument,
                    "--max-device-memory '{}': expected a size such as 512M or 4G (bytes, K, M, "
                    "G or T)",
                    a.max_device_memory);
        SHPRT_CHECK(o.device != Device::cpu, invalid_argument,
                    "--max-device-memory needs --device cuda or auto");
    }
    const bool interreflected = o.transfer == TransferKind::interreflected;
    SHPRT_CHECK(o.transfer != TransferKind::glossy || a.bounces.empty(), unsupported,
                "--bounces: interreflected glossy transfer is not implemented (glossy matrices "
                "hold the direct, shadowed light only)");
    SHPRT_CHECK(
        interreflected || (a.bounces.empty() && !a.tolerance && a.albedo.empty() && !a.two_sided &&
                           !a.indirect_samples && a.source_spacing.empty() && !a.bounce_coeffs),
        invalid_argument,
        "--bounces, --tolerance, --albedo, --two-sided, --indirect-samples, "
        "--source-spacing and --bounce-coeffs need --transfer interreflected");
    if (a.bounce_coeffs) {
        SHPRT_CHECK(*a.bounce_coeffs >= 1 && *a.bounce_coeffs <= o.K, invalid_argument,
                    "--bounce-coeffs {}: must be 1 to K = {} (the bake's basis size)",
                    *a.bounce_coeffs, o.K);
        o.bounce_coeffs = static_cast<int>(*a.bounce_coeffs);
    }
    if (a.indirect_samples) {
        SHPRT_CHECK(*a.indirect_samples >= 1 && *a.indirect_samples <= kMaxBakeSamples,
                    invalid_argument, "--indirect-samples {}: must be 1 to {}", *a.indirect_samples,
                    kMaxBakeSamples);
        o.indirect_samples = static_cast<std::uint32_t>(*a.indirect_samples);
    }
    if (!a.source_spacing.empty()) {
        if (a.source_spacing == "vertices") {
            o.source_spacing = std::numeric_limits<float>::infinity();
        } else {
            double metres = 0;
            SHPRT_CHECK(
                parse_number(a.source_spacing, metres) && metres > 0 && std::isfinite(metres),
                invalid_argument,
                "--source-spacing '{}': expected a cell size in metres (> 0) or "
                "'vertices'",
                a.source_spacing);
            o.source_spacing = float(metres);
        }
    }
    if (!a.bounces.empty()) {
        if (a.bounces == "converged") {
            o.converge = true;
        } else {
            std::int64_t n = 0;
            SHPRT_CHECK(
                parse_integer(a.bounces, n) == IntegerParse::ok && n >= 0 && n <= kMaxBounces,
                invalid_argument,
                "--bounces '{}': expected a number of bounces 0 to {} or 'converged'", a.bounces,
                kMaxBounces);
            o.bounces = static_cast<int>(n);
        }
    }
    if (a.tolerance) {
        SHPRT_CHECK(o.converge, invalid_argument, "--tolerance needs --bounces converged");
        SHPRT_CHECK(*a.tolerance > 0 && *a.tolerance < 1, invalid_argument,
                    "--tolerance {}: must be between 0 and 1 (a relative change)", *a.tolerance);
        o.tolerance = *a.tolerance;
    }
    o.two_sided = a.two_sided;
    validate(o);
    return o;
}

}  // namespace shprt::tools
