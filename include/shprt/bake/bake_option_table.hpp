// The bake options as the front ends take them — `shprt bake` and `shprt view --bake` on the
// command line, shprt.bake in Python — and their one table (core/options.hpp): name, type,
// default, limits, help and the field of BakeOptionChoice each one sets. The command line
// registers its options by walking bake_option_table(); Python's keywords take their defaults
// from BakeOptionChoice{} and fill one; both turn it into BakeOptions with bake_options_from,
// which checks every value once, naming the option as the front end spells it.
//
// Beside the bake request (request.hpp): its receivers are ReceiverChoice's, parsed by
// parse_receivers.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/core/options.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace shprt {

// The bake options as typed: text where a value has names ("converged", "vertices", "512M"), wide
// integers so that a value too large for the field is refused rather than wrapped, optionals where
// "unset" differs from every value. The member defaults are both front ends' defaults.
struct BakeOptionChoice {
    std::string transfer = "shadowed", sampler = "sobol", directions = "local", device = "cpu";
    std::optional<long long> bands, coeffs;  // unset both: default_coeffs(transfer)
    long long samples = 1024;
    std::uint64_t seed = 1;
    long long threads = 0;
    long long device_index = 0;     // command line only
    std::string max_device_memory;  // command line only: "512M", "4G"
    // The error-bounded bake: target_error E (0 = off), max_samples N (0 = kDefaultMaxSamples).
    double target_error = 0;
    long long max_samples = 0;
    // Interreflected transfer. bounces: "N" or "converged" (unset: 1).
    std::string bounces;
    std::optional<double> tolerance;  // with bounces "converged" (unset: 1e-4)
    std::string albedo;               // command line only: R,G,B for every vertex (the scene's)
    bool two_sided = false;
    std::optional<long long> indirect_samples;  // unset: samples / kIndirectSampleShare
    std::string source_spacing;                 // metres or "vertices" (unset: the default)
    std::optional<long long> bounce_coeffs;     // unset: kDefaultBounceCoeffs, at most K
};

// One row per option, in the command line's help order.
const std::vector<OptionRow<BakeOptionChoice>>& bake_option_table();

// The BakeOptions `choice` describes, every value checked (one-line Error(invalid_argument), or
// unsupported, naming the option as `spelling` writes it); the progress callback is left empty.
// Options that need another (--tolerance needs --bounces converged; the interreflected ones need
// --transfer interreflected) are refused here too. `albedo` is not applied: it changes the scene
// (apply_albedo_choice).
BakeOptions bake_options_from(const BakeOptionChoice& choice, Spelling spelling);

// choice.albedo (R,G,B, linear, each 0 to 1): every vertex's albedo replaced and the source
// recorded; nothing when unset. One-line Error(invalid_argument) naming --albedo otherwise.
void apply_albedo_choice(const BakeOptionChoice& choice, Mesh& mesh);

}  // namespace shprt
