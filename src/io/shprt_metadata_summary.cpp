// `shprt info`'s summary of the metadata (shprt_metadata.hpp): the rows' summaries that take more
// than a line of the table, and the walk over the rows in summary order.
#include "io/shprt_metadata.hpp"

#include "shprt/sh/basis.hpp"
#include "shprt/transfer/estimates.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace shprt::detail {
namespace {

using Lines = SummaryLines;

std::string bytes_text(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 4) {
        bytes /= 1024.0;
        ++u;
    }
    return u == 0 ? fmt::format("{:.0f} B", bytes) : fmt::format("{:.1f} {}", bytes, units[u]);
}

std::string rate_text(double per_second) {
    if (per_second >= 1e9) return fmt::format("{:.2f} G", per_second / 1e9);
    if (per_second >= 1e6) return fmt::format("{:.2f} M", per_second / 1e6);
    if (per_second >= 1e3) return fmt::format("{:.2f} k", per_second / 1e3);
    return fmt::format("{:.0f} ", per_second);
}

}  // namespace

void SummaryLines::line(const char* label, const std::string& value) const {
    out += fmt::format("{:<13}{}\n", label, value);
}

void summarise_interreflection(const Lines& s) {
    const TransferSet& t = s.file.transfer;
    const Mesh& mesh = s.file.mesh;
    if (!kind_row(t.kind).interreflection) return;
    const InterreflectionInfo& ir = t.interreflection;
    s.line("bounces", fmt::format("{} (stored: T_0 + ... + T_{}), {}", ir.bounces, ir.bounces,
                                  describe_convergence(ir)));
    s.line("albedo", ir.albedo_source.empty() ? "(source not recorded)" : ir.albedo_source);
    s.line("back faces", ir.two_sided ? "two-sided (a back face sends the light of its own side)"
                                      : "one-sided (a ray that hits a back face brings nothing)");
    const double rows = ir.sources > 0 ? double(ir.sources) : double(mesh.vertex_count());
    s.line("operator", fmt::format("nnz(A) = {} ({:.1f} per {}), {}, {} closest-hit rays",
                                   ir.operator_nnz, rows > 0 ? double(ir.operator_nnz) / rows : 0.0,
                                   ir.sources > 0 ? "bounce source" : "vertex",
                                   bytes_text(double(ir.operator_bytes)), ir.operator_rays));
    if (ir.sources > 0) {
        const std::string cells = ir.source_spacing > 0 && std::isfinite(ir.source_spacing)
                                      ? fmt::format("cells of at most {:.3g} m", ir.source_spacing)
                                      : std::string("the mesh's vertices");
        s.line("sources", fmt::format("{} bounce sources ({}), {} invalid (inside or under "
                                      "geometry: filled from their neighbours); {} directions per "
                                      "receiver",
                                      ir.sources, cells, ir.invalid_sources, ir.indirect_samples));
        if (ir.bounce_coeffs > 0)
            s.line("coeffs", fmt::format("K = {} after one bounce, the first {} after more",
                                         t.layout.K, ir.bounce_coeffs));
        const std::size_t V = mesh.vertex_count();
        const std::uint64_t seeing = ir.receivers_seeing_back_faces;
        s.line("backs seen",
               fmt::format("{} of {} receivers ({:.1f} %) see back faces{}", seeing, V,
                           V > 0 ? 100.0 * double(seeing) / double(V) : 0.0,
                           seeing > 0 ? ": a leaky or open asset? (docs/interreflection.md, "
                                        "\"Which side\")"
                                      : ""));
    }
    s.line("direct part", t.direct.empty() ? "absent" : "kept (transfer_direct: shade --direct)");
}

void summarise_stats(const Lines& l) {
    auto stats_it = l.meta.find("stats");
    if (stats_it == l.meta.end() || !stats_it->is_object()) {
        l.line("time", "not recorded (reproducible file)");
        return;
    }
    const BakeStats& s = l.file.transfer.stats;
    // Every "seconds_*" entry except the total, in the order stored (the bake may add load and
    // write times through extra metadata).
    std::string split;
    for (auto it = stats_it->begin(); it != stats_it->end(); ++it) {
        const std::string& key = it.key();
        if (key.rfind("seconds_", 0) != 0 || key == "seconds_total" || !it->is_number()) continue;
        split +=
            fmt::format("{}{} {:.3f}", split.empty() ? "" : ", ", key.substr(8), it->get<double>());
    }
    l.line("time", fmt::format("{:.3f} s total{}{}{}", s.seconds_total, split.empty() ? "" : " (",
                               split, split.empty() ? "" : ")"));
    std::string rays = fmt::format("{} cast", s.rays_cast);
    if (s.seconds_trace > 0)
        rays += fmt::format(", {}rays/s tracing", rate_text(double(s.rays_cast) / s.seconds_trace));
    if (s.seconds_total > 0)
        rays += fmt::format(", {}rays/s overall", rate_text(double(s.rays_cast) / s.seconds_total));
    l.line("rays", rays);
    l.line("peak memory", fmt::format("{} host, {} device", bytes_text(double(s.peak_bytes_host)),
                                      bytes_text(double(s.peak_bytes_device))));
    if (s.operator_bytes_spilled > 0)
        l.line("operator spilled",
               fmt::format("{} of A read memory-mapped from a temporary file (memory budget)",
                           bytes_text(double(s.operator_bytes_spilled))));
    if (!s.device_name.empty()) l.line("device", s.device_name);
}

void summarise_basis(const Lines& s) {
    const int K = s.file.transfer.layout.K;
    const int bands = sh_bands_for(K);
    const int full = sh_count(bands) == K ? bands : bands - 1;
    if (full == bands)
        s.line("basis",
               fmt::format("K = {}: {} bands, last band full (rotation invariant)", K, bands));
    else
        s.line("basis", fmt::format("K = {}: {} bands, last band partial ({} of {} coefficients "
                                    "of band l = {}; only the first {} bands rotate exactly)",
                                    K, bands, K - sh_count(full), 2 * full + 1, full, full));
}

void summarise_target_error(const Lines& s) {
    const TransferSet& t = s.file.transfer;
    if (t.target_error <= 0) return;
    s.line("target error",
           fmt::format("{:.3g} per receiver (error-bounded: docs/sampling.md)", t.target_error));
    const EstimateSummary estimates = summarize_estimates(t);
    if (!estimates.receivers_per_samples.empty()) {
        s.line("samples", "receivers per prefix " + samples_histogram_text(estimates));
        s.line("est. error", error_spread_text(estimates.error));
        s.line("error bands", "receivers " + error_bands_text(estimates));
    }
}

// The file ends with its last section (read_shprt checks this), so the table gives its size.
void summarise_file_size(const Lines& s) {
    std::uint64_t size = 0;
    auto sections = s.meta.find("sections");
    if (sections != s.meta.end() && sections->is_array())
        for (const nlohmann::ordered_json& e : *sections)
            if (e.is_object() && e.value("offset", nlohmann::ordered_json()).is_number_unsigned() &&
                e.value("length", nlohmann::ordered_json()).is_number_unsigned())
                size = std::max(
                    size, e["offset"].get<std::uint64_t>() + e["length"].get<std::uint64_t>());
    s.line("file size", fmt::format("{} ({} bytes)", bytes_text(double(size)), size));
}

std::string summarise_metadata(const ShprtFile& file) {
    // The metadata comes from read_shprt (already validated) or a writer; tolerate anything.
    nlohmann::ordered_json meta =
        nlohmann::ordered_json::parse(file.metadata_json, nullptr, /*allow_exceptions=*/false);
    if (!meta.is_object()) meta = nlohmann::ordered_json::object();
    std::vector<const FieldRule*> rows;
    for (const FieldRule& rule : field_rules())
        if (rule.summarise) rows.push_back(&rule);
    std::sort(rows.begin(), rows.end(), [](const FieldRule* a, const FieldRule* b) {
        return a->summary_rank < b->summary_rank;
    });
    std::string out;
    const SummaryLines lines{file, meta, out};
    for (const FieldRule* rule : rows) rule->summarise(lines);
    return out;
}

}  // namespace shprt::detail
