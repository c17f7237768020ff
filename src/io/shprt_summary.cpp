// Human-readable description of a .shprt file, for `shprt info`.
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/transfer/estimates.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace shprt {
namespace {

using OrderedJson = nlohmann::ordered_json;

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

std::string describe_convergence(const InterreflectionInfo& ir) {
    if (ir.converge)
        return fmt::format("{}: last relative change {:.2g} {} tolerance {:.2g}",
                           ir.converged ? "converged" : "NOT converged", ir.last_change,
                           ir.converged ? "<" : ">=", ir.tolerance);
    if (ir.bounces == 0) return "the direct light only";
    // Issue 40: a fixed count's last change read as "not converged"; it is information.
    return fmt::format(
        "a fixed count, not tested for convergence; largest relative change by "
        "bounce {}: {:.2g}",
        ir.bounces, ir.last_change);
}

std::string shprt_summary(const ShprtFile& file) {
    // The metadata comes from read_shprt (already validated) or a writer; tolerate anything.
    OrderedJson meta = OrderedJson::parse(file.metadata_json, nullptr, /*allow_exceptions=*/false);
    if (!meta.is_object()) meta = OrderedJson::object();
    const auto str = [](const OrderedJson& j, const char* key, const char* fallback) {
        auto it = j.find(key);
        return it != j.end() && it->is_string() ? it->get<std::string>() : std::string(fallback);
    };

    const Mesh& mesh = file.mesh;
    const TransferSet& t = file.transfer;
    const int K = t.layout.K;
    const int bands = sh_bands_for(K);
    const int full = sh_count(bands) == K ? bands : bands - 1;
    std::string out;
    const auto line = [&out](const char* label, const std::string& value) {
        out += fmt::format("{:<13}{}\n", label, value);
    };

    line("scene", mesh.source.empty() ? "(unnamed)" : mesh.source);
    line("vertices", fmt::format("{}", mesh.vertex_count()));
    if (!mesh.parents.empty()) {
        std::size_t added = 0;
        for (const auto& p : mesh.parents) added += p[0] != Mesh::kNoParent;
        line("refined",
             fmt::format("{} vertices added by adaptive refinement (vertex_parents)", added));
    }
    if (t.layout.domain == ReceiverDomain::texel)
        line("texels", fmt::format("{}x{} image, {} covered ({:.1f}%), UV set {}", t.texels.width,
                                   t.texels.height, t.texels.texel.size(),
                                   100.0 * double(t.texels.texel.size()) /
                                       (double(t.texels.width) * double(t.texels.height)),
                                   t.texels.uv_set));
    line("triangles", fmt::format("{}", mesh.triangle_count()));
    if (!mesh.brdf_index.empty()) line("brdfs", describe_brdfs(mesh) + " (from the materials)");
    if (file.is_part())
        line("receivers",
             fmt::format("[{}, {}) of {}: one part of a sharded bake (join the parts with `shprt "
                         "merge`)",
                         file.receiver_first, file.receiver_first + t.receiver_count(),
                         mesh.vertex_count()));
    const int channels = t.layout.channels;
    const std::string shape = t.layout.shape == TransferShape::vector
                                  ? std::string()
                                  : fmt::format(", {} K×K per channel", to_string(t.layout.shape));
    line("transfer", fmt::format("{}, {} channel{} per {}{}", to_string(t.kind), channels,
                                 channels == 1 ? "" : "s", to_string(t.layout.domain), shape));
    if (full == bands)
        line("basis",
             fmt::format("K = {}: {} bands, last band full (rotation invariant)", K, bands));
    else
        line("basis", fmt::format("K = {}: {} bands, last band partial ({} of {} coefficients of "
                                  "band l = {}; only the first {} bands rotate exactly)",
                                  K, bands, K - sh_count(full), 2 * full + 1, full, full));
    line("sampling",
         fmt::format("{}{}, {}{} samples, seed {}", to_string(t.sampler),
                     t.direction_frame == DirectionFrame::local ? " (local: tangent frames)" : "",
                     t.target_error > 0 ? "at most " : "", t.samples, t.seed));
    if (t.target_error > 0) {
        line("target error",
             fmt::format("{:.3g} per receiver (error-bounded: docs/sampling.md)", t.target_error));
        const EstimateSummary estimates = summarize_estimates(t);
        if (!estimates.receivers_per_samples.empty()) {
            line("samples", "receivers per prefix " + samples_histogram_text(estimates));
            line("est. error", error_spread_text(estimates.error));
        }
    }
    line("precision", to_string(t.layout.encoding));
    if (!t.cpca.empty())
        line("cpca", fmt::format("{} clusters x {} vectors (k-means++ seed {}); rows rebuilt on "
                                 "reading",
                                 t.cpca.clusters, t.cpca.vectors, t.cpca.seed));
    if (!t.probes.empty()) line("probes", describe_probes(t.probes));
    if (t.kind == TransferKind::interreflected) {
        const InterreflectionInfo& ir = t.interreflection;
        const std::string bounces = fmt::format("{} (stored: T_0 + ... + T_{}), {}", ir.bounces,
                                                ir.bounces, describe_convergence(ir));
        line("bounces", bounces);
        line("albedo", ir.albedo_source.empty() ? "(source not recorded)" : ir.albedo_source);
        line("back faces", ir.two_sided ? "two-sided (a back face sends the light of its own side)"
                                        : "one-sided (a ray that hits a back face brings nothing)");
        const double rows = ir.sources > 0 ? double(ir.sources) : double(mesh.vertex_count());
        line("operator",
             fmt::format("nnz(A) = {} ({:.1f} per {}), {}, {} closest-hit rays", ir.operator_nnz,
                         rows > 0 ? double(ir.operator_nnz) / rows : 0.0,
                         ir.sources > 0 ? "bounce source" : "vertex",
                         bytes_text(double(ir.operator_bytes)), ir.operator_rays));
        if (ir.sources > 0) {
            const std::string cells =
                ir.source_spacing > 0 && std::isfinite(ir.source_spacing)
                    ? fmt::format("cells of at most {:.3g} m", ir.source_spacing)
                    : std::string("the mesh's vertices");
            line("sources",
                 fmt::format("{} bounce sources ({}), {} invalid (inside or under geometry: "
                             "filled from their neighbours); {} directions per receiver",
                             ir.sources, cells, ir.invalid_sources, ir.indirect_samples));
            if (ir.bounce_coeffs > 0)
                line("coeffs", fmt::format("K = {} after one bounce, the first {} after more", K,
                                           ir.bounce_coeffs));
            const std::size_t V = mesh.vertex_count();
            const std::uint64_t seeing = ir.receivers_seeing_back_faces;
            line("backs seen",
                 fmt::format("{} of {} receivers ({:.1f} %) see back faces{}", seeing, V,
                             V > 0 ? 100.0 * double(seeing) / double(V) : 0.0,
                             seeing > 0 ? ": a leaky or open asset? (docs/interreflection.md, "
                                          "\"Which side\")"
                                        : ""));
        }
        line("direct part", t.direct.empty() ? "absent" : "kept (transfer_direct: shade --direct)");
    }

    auto stats_it = meta.find("stats");
    if (stats_it != meta.end() && stats_it->is_object()) {
        const BakeStats& s = t.stats;
        // Every "seconds_*" entry except the total, in the order stored (the bake may add load
        // and write times through extra metadata).
        std::string split;
        for (auto it = stats_it->begin(); it != stats_it->end(); ++it) {
            const std::string& key = it.key();
            if (key.rfind("seconds_", 0) != 0 || key == "seconds_total" || !it->is_number())
                continue;
            split += fmt::format("{}{} {:.3f}", split.empty() ? "" : ", ", key.substr(8),
                                 it->get<double>());
        }
        line("time", fmt::format("{:.3f} s total{}{}{}", s.seconds_total, split.empty() ? "" : " (",
                                 split, split.empty() ? "" : ")"));
        std::string rays = fmt::format("{} cast", s.rays_cast);
        if (s.seconds_trace > 0)
            rays +=
                fmt::format(", {}rays/s tracing", rate_text(double(s.rays_cast) / s.seconds_trace));
        if (s.seconds_total > 0)
            rays +=
                fmt::format(", {}rays/s overall", rate_text(double(s.rays_cast) / s.seconds_total));
        line("rays", rays);
        line("peak memory", fmt::format("{} host, {} device", bytes_text(double(s.peak_bytes_host)),
                                        bytes_text(double(s.peak_bytes_device))));
        if (s.operator_bytes_spilled > 0)
            line("operator spilled",
                 fmt::format("{} of A read memory-mapped from a temporary file (memory budget)",
                             bytes_text(double(s.operator_bytes_spilled))));
        if (!s.device_name.empty()) line("device", s.device_name);
    } else {
        line("time", "not recorded (reproducible file)");
    }

    // The file ends with its last section (read_shprt checks this), so the table gives its size.
    std::uint64_t size = 0;
    auto sections = meta.find("sections");
    if (sections != meta.end() && sections->is_array())
        for (const OrderedJson& s : *sections)
            if (s.is_object() && s.value("offset", OrderedJson()).is_number_unsigned() &&
                s.value("length", OrderedJson()).is_number_unsigned())
                size = std::max(
                    size, s["offset"].get<std::uint64_t>() + s["length"].get<std::uint64_t>());
    line("file size", fmt::format("{} ({} bytes)", bytes_text(double(size)), size));
    auto scene = meta.find("scene");
    line("scene hash", scene != meta.end() && scene->is_object()
                           ? str(*scene, "hash", "?")
                           : format_mesh_hash(mesh_hash(mesh)));
    auto version = meta.find("format_version");
    line("written by", fmt::format("{} {}, format version {}", str(meta, "tool", "shprt"),
                                   str(meta, "tool_version", "?"),
                                   version != meta.end() ? version->dump() : "?"));
    return out;
}

}  // namespace shprt
