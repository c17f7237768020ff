// The bake options of `shprt bake`, shared with `shprt view SCENE --bake` so that both accept the
// same names and check them the same way: --transfer, --bands, --coeffs, --samples, --sampler,
// --seed, --threads, --device, --device-index, --max-device-memory and interreflection's.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/scene/mesh.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace shprt::tools {

struct BakeOptionArgs {
    std::string transfer = "shadowed", sampler = "sobol", directions = "sphere", device = "cpu";
    std::optional<long long> bands, coeffs;
    long long samples = 1024;
    std::uint64_t seed = 1;
    long long threads = 0;
    long long device_index = 0;
    std::string max_device_memory;  // --max-device-memory SIZE
    // Interreflected transfer: --bounces N|converged, --tolerance T, --two-sided (and --albedo,
    // which changes the scene: apply_albedo_option).
    std::string bounces;
    std::optional<double> tolerance;
    std::string albedo;
    bool two_sided = false;
    std::optional<long long> indirect_samples;  // --indirect-samples S'
    std::string source_spacing;                 // --source-spacing METRES|vertices
    std::optional<long long> bounce_coeffs;     // --bounce-coeffs K2
    // The error-bounded bake: --target-error E (0 = off), --max-samples N (0 = the default).
    double target_error = 0;
    long long max_samples = 0;
};

// Adds the options above, writing into `args` (which must outlive the parse).
void add_bake_options(CLI::App& app, BakeOptionArgs& args);

// Checks every option (one-line Error(invalid_argument) naming the option and value) and returns
// the BakeOptions they describe; progress is left empty.
BakeOptions bake_options_from(const BakeOptionArgs& args);

// --albedo R,G,B as a colour: linear, each component 0 to 1 (one-line Error(invalid_argument)
// otherwise). `bake --albedo` and the glossy shading's `--albedo` (shading_options.hpp).
Vec3f parse_albedo(const std::string& text);

// --albedo R,G,B: every vertex's albedo replaced (linear RGB, each in [0, 1]) and the source
// recorded; nothing when the option was not given.
void apply_albedo_option(const BakeOptionArgs& args, Mesh& mesh);

}  // namespace shprt::tools
