// `shprt compress`'s checks before the fit and its summary lines (cpca_summary.hpp).
#include "shprt/transfer/cpca_summary.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fmt/format.h>
#include <fmt/printf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <utility>

namespace shprt {
namespace {

// The receivers, named in what is said: vertices, or texels.
const char* units_of(const TransferSet& t) { return is_texel(t.layout) ? "texels" : "vertices"; }

}  // namespace

std::string describe_matrices(const TransferSet& t) {
    const int K = t.layout.K;
    const std::string matrices = fmt::format("{}x{} matrices", K, K);
    if (t.cpca.empty()) return matrices;
    return fmt::format("CPCA {}x{} (clusters x vectors) of {}", t.cpca.clusters, t.cpca.vectors,
                       matrices);
}

void check_cpca_fit(const TransferSet& t, const CpcaOptions& options, const std::string& what) {
    const std::size_t V = t.receiver_count();
    const std::size_t D = t.layout.floats_per_receiver();
    const char* unit = to_string(t.layout.domain);
    SHPRT_CHECK(std::size_t(options.clusters) <= V, invalid_argument,
                "{}: {} clusters for {} {} (at most one per {})", what, options.clusters, V,
                units_of(t), unit);
    SHPRT_CHECK(std::size_t(options.vectors) <= D, invalid_argument,
                "{}: {} vectors, more than the {} floats of a {} ({} transfer, K = {}; a symmetric "
                "K×K matrix stores K(K+1)/2 ≤ K²)",
                what, options.vectors, D, unit, to_string(t.layout.shape), t.layout.K);
}

void check_probe_cpca_fit(const ProbeGrid& probes, const CpcaOptions& options,
                          const std::string& what) {
    SHPRT_CHECK(!probes.empty(), invalid_argument,
                "{}: the file has no probes (bake with --probes)", what);
    const std::size_t valid =
        std::size_t(std::count(probes.valid.begin(), probes.valid.end(), std::uint8_t(1)));
    const double floats = double(probes.channels) * probes.K * probes.K;
    SHPRT_CHECK(std::size_t(options.clusters) <= valid && double(options.vectors) <= floats,
                invalid_argument,
                "{}: at most {} clusters (the valid probes) and {} vectors (channels x K x K = {} "
                "x {} x {})",
                what, valid, floats, probes.channels, probes.K, probes.K);
}

std::string cpca_summary(const TransferSet& t, const CpcaResult& r, const CpcaOptions& options,
                         bool half, const std::string& light_name) {
    const char* unit = to_string(t.layout.domain);
    const char* views = is_matrix(t.layout) ? "5 views" : "diffuse";
    const TransferError& e = r.error;
    std::vector<float> sorted = e.receiver_rmse;
    std::sort(sorted.begin(), sorted.end());
    const auto pct = [&](double q) {
        return 100.0 * sorted[std::min(sorted.size() - 1, std::size_t(q * double(sorted.size())))];
    };
    std::string out = fmt::sprintf(
        "cpca: %d clusters x %d vectors (k-means++ seed %llu, at most %d Lloyd iterations), "
        "%s, fit %.3f s\n",
        options.clusters, options.vectors, static_cast<unsigned long long>(options.seed),
        options.iterations, half ? "float16" : "float32", r.seconds_fit);
    out += fmt::sprintf(
        "size: %.1f B/%s (raw float32: %.0f B/%s as stored, %.0f B/%s as full matrices) = "
        "%.1fx / %.1fx smaller\n",
        r.bytes_per_receiver, unit, r.raw_bytes_per_receiver, unit, r.raw_full_bytes_per_receiver,
        unit, r.raw_bytes_per_receiver / r.bytes_per_receiver,
        r.raw_full_bytes_per_receiver / r.bytes_per_receiver);
    if (r.direct_bytes_per_receiver > 0)
        out += fmt::sprintf("direct part: kept beside the code (--direct), %.0f B/%s\n",
                            r.direct_bytes_per_receiver, unit);
    out += fmt::sprintf(
        "error: exit radiance relative RMSE %.3f%% (8 test lights x %s); per %s (RMSE / "
        "scene RMS): median %.3f%%, p99 %.3f%%, max %.3f%%\n",
        100.0 * e.relative_rmse, views, unit, pct(0.5), pct(0.99), pct(1.0));
    if (r.light_error)
        out += fmt::sprintf("error under %s: exit radiance relative RMSE %.3f%% (%s)\n", light_name,
                            100.0 * r.light_error->relative_rmse, views);
    std::string worst;
    for (std::size_t i = 0; i < std::min<std::size_t>(5, e.worst.size()); ++i)
        worst += fmt::format("{}{} ({:.2f}%)", i ? ", " : "", e.worst[i],
                             100.0 * e.receiver_rmse[e.worst[i]]);
    return out + fmt::sprintf("worst %s: %s\n", units_of(t), worst);
}

std::string compress_summary(const TransferSet& t, const SetCompression& r, const CpcaFits& fits,
                             bool half, const std::string& light_name) {
    std::string out = cpca_summary(t, r.rows, fits.transfer, half, light_name);
    if (r.probes) out += probe_cpca_summary(*r.probes, *fits.probes, light_name);
    return out;
}

std::string probe_cpca_summary(const ProbeCpcaResult& r, const CpcaOptions& options,
                               const std::string& light_name) {
    const double ratio = r.raw_bytes_per_probe / r.bytes_per_probe;
    std::string out = fmt::sprintf(
        "probes: %d clusters x %d vectors, float32, %.1f B/probe (raw %.0f B) = %s, fit %.3f s\n",
        options.clusters, options.vectors, r.bytes_per_probe, r.raw_bytes_per_probe,
        ratio >= 1 ? fmt::format("{:.1f}x smaller", ratio)
                   : fmt::format("{:.1f}x larger than the raw matrices: use fewer clusters or "
                                 "vectors",
                                 1 / ratio),
        r.seconds_fit);
    out += fmt::sprintf(
        "probe error: incident radiance relative RMSE %.3f%% (lights of unit coefficients)",
        100.0 * r.relative_rmse);
    if (r.light_relative_rmse)
        out += fmt::sprintf(", %.3f%% under %s", 100.0 * *r.light_relative_rmse, light_name);
    return out + "\n";
}

const std::vector<OptionRow<CpcaChoice>>& cpca_option_table() {
    static const std::vector<OptionRow<CpcaChoice>> table = [] {
        using C = CpcaChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "cpca", &C::cpca,
                "CLUSTERS,VECTORS: clusters (1 to the vertex count) and PCA vectors "
                "per cluster (1 to the floats per vertex)");
        add_row(t, "probe_cpca", &C::probe_cpca,
                "CLUSTERS,VECTORS: compress the file's transfer probes too (clusters 1 to "
                "the valid probes, vectors 1 to channels x K x K); without it they are "
                "kept as they are");
        add_row(t, "half", &C::half, "Store the code as float16 (not the probes')");
        add_row(t, "seed", &C::seed, "Seed of the k-means++ seeding (default 1)");
        add_row(t, "iterations", &C::iterations, "Lloyd iterations at most (default 16)");
        add_row(t, "threads", &C::threads, "Worker threads (default 0 = all)");
        return complete_rows(std::move(t));
    }();
    return table;
}

CpcaFits cpca_options_from(const CpcaChoice& c) {
    // CLUSTERS,VECTORS of `option`: two whole numbers ≥ 1.
    const auto parse = [&c](const std::string& option, const std::string& text) {
        const std::vector<double> cv = parse_numbers(text, 2, option + " CLUSTERS,VECTORS");
        SHPRT_CHECK(cv[0] >= 1 && cv[1] >= 1 && cv[0] == std::floor(cv[0]) &&
                        cv[1] == std::floor(cv[1]) && cv[0] < 1e9 && cv[1] < 1e9,
                    invalid_argument, "{} {}: CLUSTERS and VECTORS must be whole numbers ≥ 1",
                    option, text);
        return std::pair{int(cv[0]), int(cv[1])};
    };
    CpcaOptions rows;
    std::tie(rows.clusters, rows.vectors) = parse("--cpca", c.cpca);
    rows.seed = c.seed;
    rows.iterations = c.iterations;
    rows.threads = c.threads;
    std::optional<std::pair<int, int>> probes;
    if (!c.probe_cpca.empty()) probes = parse("--probe-cpca", c.probe_cpca);
    SHPRT_CHECK(c.iterations >= 0, invalid_argument, "--iterations {}: must be ≥ 0", c.iterations);
    return cpca_fits(rows, probes);
}

CpcaFits cpca_fits(const CpcaOptions& rows, std::optional<std::pair<int, int>> probes) {
    CpcaFits fits{rows, std::nullopt};
    if (probes) {
        fits.probes = rows;
        fits.probes->clusters = probes->first;
        fits.probes->vectors = probes->second;
    }
    return fits;
}

SetCompression compress_set(const TransferSet& transfer, const std::vector<Vec3f>& normals,
                            const CpcaFits& fits, bool half,
                            const std::optional<std::vector<float>>& light,
                            const std::optional<std::vector<float>>& probe_light,
                            const std::string& probe_option) {
    SHPRT_CHECK(!fits.probes || !transfer.probes.empty(), invalid_argument,
                "{}: the file has no probes (bake with probes)", probe_option);
    SetCompression out;
    out.rows = compress_transfer(transfer, normals, fits.transfer, half, light ? &*light : nullptr);
    if (!fits.probes) return out;
    try {
        out.probes =
            compress_probes(transfer.probes, *fits.probes, probe_light ? &*probe_light : nullptr);
    } catch (const Error& e) {
        fail(e.code(), "{}: {}", probe_option, e.what());
    }
    out.rows.compressed.probes = std::move(out.probes->compressed);
    return out;
}

}  // namespace shprt
