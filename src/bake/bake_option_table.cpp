// The bake options' table and their one check (bake/bake_option_table.hpp).
#include "shprt/bake/bake_option_table.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fmt/format.h>

#include <climits>
#include <cmath>
#include <limits>

namespace shprt {

namespace {

// A named value as the front end writes it: interreflected, or 'interreflected' in Python.
std::string named(Spelling s, const char* value) {
    return s == Spelling::python ? fmt::format("'{}'", value) : value;
}

using Row = OptionRow<BakeOptionChoice>;
using C = BakeOptionChoice;

std::vector<Row> make_table() {
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    std::vector<Row> t;
    add_row(t, "transfer", &C::transfer,
            "unshadowed, shadowed (default), interreflected (RGB, with bounces) or glossy (K×K "
            "matrices, at most 8 bands)");
    add_row(t, "bands", &C::bands,
            fmt::format("SH bands n (K = n², 1 to {}); default 4 (glossy: 5, at most 8)",
                        kMaxComputeBands),
            {1, double(kMaxComputeBands)});
    add_row(t, "coeffs", &C::coeffs,
            fmt::format("Basis size K, 1 to {} (need not be a square); default 16 (4 bands: smooth "
                        "skies; a sun projected into SH wants more, e.g. the paper's 256)",
                        kMaxBakeCoeffs),
            {1, double(kMaxBakeCoeffs)});
    add_row(t, "samples", &C::samples,
            "Directions per vertex S (default 1024; not used with --target-error)",
            {1, double(kMaxBakeSamples)});
    add_row(
        t, "target_error", &C::target_error,
        fmt::format("Error-bounded bake: each receiver gets the smallest prefix {}, {}, ... of the "
                    "nested set whose estimated relative error is at most E (e.g. 0.01; above 0, "
                    "at most 1; default 0 = off: every receiver gets --samples). Shadowed, "
                    "unshadowed or interreflected, sobol or uniform; on the CPU, or on the GPU "
                    "(--device cuda) with the local set (the default); docs/sampling.md",
                    2 * kTargetFirstSamples, 4 * kTargetFirstSamples),
        {0, 1});
    add_row(
        t, "max_samples", &C::max_samples,
        fmt::format("--target-error: the most directions a receiver gets, a power of two {} to {} "
                    "(default 0 = {})",
                    kTargetFirstSamples, kMaxBakeSamples, kDefaultMaxSamples),
        {0, double(kMaxBakeSamples)},
        fmt::format("0 or a power of two {} to {}", kTargetFirstSamples, kMaxBakeSamples));
    add_row(t, "sampler", &C::sampler,
            "sobol (default: 7x lower error than the paper's set at the same cost), uniform (the "
            "paper's), stratified or fibonacci");
    add_row(t, "directions", &C::directions,
            "local (default: one cosine-weighted set in each receiver's tangent frame, every ray "
            "above the horizon: 1 % error about 1.6x sooner) or sphere (one set on the sphere, the "
            "paper's); docs/sampling.md");
    add_row(t, "seed", &C::seed, "Seed of the direction set (default 1)");
    add_row(t, "threads", &C::threads, "Worker threads (default 0 = all)",
            {0, double(kMaxBakeThreads)}, fmt::format("0 (all) to {}", kMaxBakeThreads));
    add_row(t, "device", &C::device, "cpu (default), cuda or auto");
    add_row(t, "device_index", &C::device_index, "CUDA device for --device cuda|auto (default 0)",
            {0, double(INT_MAX)}, "0 or more")
        .cli_only = true;
    add_row(
        t, "max_device_memory", &C::max_device_memory,
        "--device cuda|auto: the GPU memory the bake may use (512M, 4G, ...; default 90% of what "
        "is free); interreflected bounces copy in what does not fit")
        .cli_only = true;
    add_row(
        t, "bounces", &C::bounces,
        fmt::format("Interreflected: bounces N (0 to {}; default 1) or 'converged'", kMaxBounces),
        {0, double(kMaxBounces)}, fmt::format("0 to {} or 'converged'", kMaxBounces));
    add_row(
        t, "tolerance", &C::tolerance,
        "Interreflected, --bounces converged: stop when no vertex's transfer changes by more than "
        "this fraction (default 1e-4)",
        {0, 1, true});
    add_row(t, "albedo", &C::albedo,
            "Interreflected: albedo R,G,B (linear, 0 to 1) for every vertex (default: the scene's "
            "vertex colours, else its materials' diffuse colour, else 0.8 grey)")
        .cli_only = true;  // Python's albedo= is the per-vertex array
    add_row(t, "two_sided", &C::two_sided,
            "Interreflected: a back face reflects the light on its own side, as a renderer does "
            "(default: it brings nothing; docs/interreflection.md says which to pick)");
    add_row(t, "indirect_samples", &C::indirect_samples,
            fmt::format("Interreflected: directions per receiver for the bounces (the first of the "
                        "bake's set; default --samples / {})",
                        kIndirectSampleShare),
            {1, double(kMaxBakeSamples)});
    add_row(
        t, "source_spacing", &C::source_spacing,
        "Interreflected: the bounce sources' cell size in metres (default: the scene's diagonal "
        "/ 48), or 'vertices' for the mesh's vertices alone",
        {0, kNone, true}, "> 0 (metres) or 'vertices'");
    add_row(t, "bounce_coeffs", &C::bounce_coeffs,
            fmt::format("Interreflected: coefficients the light carries from its second bounce on "
                        "(default {}, at most K; the first bounce keeps all K)",
                        kDefaultBounceCoeffs),
            {1, kNone}, "1 to K");
    return complete_rows(std::move(t));
}

Vec3f parse_albedo(const std::string& text) {
    const std::vector<double> rgb = parse_numbers(text, 3, "--albedo R,G,B");
    for (double c : rgb)
        SHPRT_CHECK(c >= 0.0 && c <= 1.0, invalid_argument,
                    "--albedo {}: each component must be 0 to 1 (linear reflectance)", text);
    return Vec3f{float(rgb[0]), float(rgb[1]), float(rgb[2])};
}

void set_bounces(const BakeOptionChoice& a, const Row& row, Spelling s, BakeOptions& o) {
    if (a.bounces == "converged") {
        o.converge = true;
        return;
    }
    std::int64_t n = 0;
    SHPRT_CHECK(parse_integer(a.bounces, n) == IntegerParse::ok && double(n) >= row.limits.min &&
                    double(n) <= row.limits.max,
                invalid_argument, "{}: expected a number of bounces {}",
                row.spelled(s, "'" + a.bounces + "'"), row.limits_text);
    o.bounces = static_cast<int>(n);
}

void set_source_spacing(const BakeOptionChoice& a, const Row& row, Spelling s, BakeOptions& o) {
    if (a.source_spacing == "vertices") {
        o.source_spacing = std::numeric_limits<float>::infinity();
        return;
    }
    double metres = 0;
    SHPRT_CHECK(parse_number(a.source_spacing, metres) && metres > 0 && std::isfinite(metres),
                invalid_argument, "{}: expected a cell size in metres (> 0) or 'vertices'",
                row.spelled(s, "'" + a.source_spacing + "'"));
    o.source_spacing = float(metres);
}

// The interreflected options, after K is known.
void set_interreflection(const BakeOptionChoice& a, Spelling s, BakeOptions& o) {
    const auto& t = bake_option_table();
    const auto row = [&](const char* name) -> const Row& { return find_row(t, name); };
    const bool interreflected = kind_row(o.transfer).interreflection;
    SHPRT_CHECK(!is_matrix(kind_row(o.transfer)) || a.bounces.empty(), unsupported,
                "{}: interreflected glossy transfer is not implemented (glossy matrices hold the "
                "direct, shadowed light only)",
                row("bounces").label(s));
    const bool given = !a.bounces.empty() || a.tolerance || !a.albedo.empty() || a.two_sided ||
                       a.indirect_samples || !a.source_spacing.empty() || a.bounce_coeffs;
    if (!interreflected && given) {
        std::string names;
        const char* list[] = {"bounces",          "tolerance",      "albedo",       "two_sided",
                              "indirect_samples", "source_spacing", "bounce_coeffs"};
        std::vector<std::string> labels;
        for (const char* name : list)
            if (s == Spelling::command_line || !row(name).cli_only)
                labels.push_back(row(name).label(s));
        for (std::size_t i = 0; i < labels.size(); ++i)
            names += (i == 0 ? "" : i + 1 == labels.size() ? " and " : ", ") + labels[i];
        fail(ErrorCode::invalid_argument, "{} need {}", names,
             row("transfer").spelled(s, named(s, "interreflected")));
    }
    if (a.bounce_coeffs) {
        SHPRT_CHECK(*a.bounce_coeffs >= 1 && *a.bounce_coeffs <= o.K, invalid_argument,
                    "{}: must be 1 to K = {} (the bake's basis size)",
                    row("bounce_coeffs").spelled(s, std::to_string(*a.bounce_coeffs)), o.K);
        o.bounce_coeffs = static_cast<int>(*a.bounce_coeffs);
    }
    if (a.indirect_samples) {
        check_limits(row("indirect_samples"), *a.indirect_samples, s);
        o.indirect_samples = static_cast<std::uint32_t>(*a.indirect_samples);
    }
    if (!a.source_spacing.empty()) set_source_spacing(a, row("source_spacing"), s, o);
    if (!a.bounces.empty()) set_bounces(a, row("bounces"), s, o);
    if (a.tolerance) {
        SHPRT_CHECK(o.converge, invalid_argument, "{} needs {}", row("tolerance").label(s),
                    row("bounces").spelled(s, named(s, "converged")));
        check_limits(row("tolerance"), *a.tolerance, s, " (a relative change)");
        o.tolerance = *a.tolerance;
    }
    o.two_sided = a.two_sided;
}

}  // namespace

const std::vector<OptionRow<BakeOptionChoice>>& bake_option_table() {
    static const std::vector<Row> table = make_table();
    return table;
}

BakeOptions bake_options_from(const BakeOptionChoice& a, Spelling s) {
    const auto& t = bake_option_table();
    const auto row = [&](const char* name) -> const Row& { return find_row(t, name); };
    BakeOptions o;
    o.transfer = parse_transfer_kind(a.transfer);
    o.sampler = parse_sampler_kind(a.sampler);
    o.direction_frame = parse_direction_frame(a.directions);
    o.device = parse_device(a.device);
    SHPRT_CHECK(!(a.bands && a.coeffs), invalid_argument,
                "{} and {} both given; use one (K = "
                "bands²)",
                row("bands").label(s), row("coeffs").label(s));
    if (a.bands) {
        check_limits(row("bands"), *a.bands, s,
                     fmt::format(" (K = bands², at most {})", kMaxBakeCoeffs));
        o.K = sh_count(static_cast<int>(*a.bands));
    } else if (a.coeffs) {
        check_limits(row("coeffs"), *a.coeffs, s);
        o.K = static_cast<int>(*a.coeffs);
    } else {
        o.K = default_coeffs(o.transfer);
    }
    check_limits(row("samples"), a.samples, s);
    o.samples = static_cast<std::uint32_t>(a.samples);
    const bool cli = s == Spelling::command_line;
    set_error_bound(o, a.target_error, a.max_samples, cli ? "--target-error " : "target_error=",
                    cli ? "--max-samples " : "max_samples=");
    o.seed = a.seed;
    check_limits(row("threads"), a.threads, s);
    o.threads = static_cast<int>(a.threads);
    check_limits(row("device_index"), a.device_index, s);
    o.device_index = static_cast<int>(a.device_index);
    if (!a.max_device_memory.empty()) {
        const Row& memory = row("max_device_memory");
        SHPRT_CHECK(parse_byte_size(a.max_device_memory, o.device_memory_budget) &&
                        o.device_memory_budget > 0,
                    invalid_argument,
                    "{}: expected a size such as 512M or 4G (bytes, K, M, G or T)",
                    memory.spelled(s, "'" + a.max_device_memory + "'"));
        SHPRT_CHECK(o.device != Device::cpu, invalid_argument, "{} needs {} cuda or auto",
                    memory.label(s), row("device").label(s));
    }
    set_interreflection(a, s, o);
    validate(o);
    return o;
}

void apply_albedo_choice(const BakeOptionChoice& choice, Mesh& mesh) {
    if (choice.albedo.empty()) return;
    mesh.albedo.assign(mesh.vertex_count(), parse_albedo(choice.albedo));
    mesh.albedo_source = "--albedo " + choice.albedo;
}

}  // namespace shprt
