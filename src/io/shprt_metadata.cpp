// The .shprt metadata field table (shprt_metadata.hpp): one row per field, written, read and
// summarised from the same rows.
#include "io/shprt_metadata.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_format.hpp"
#include "shprt/scene/material.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/transfer/estimates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>

namespace shprt::detail {
namespace {

constexpr std::size_t kMaxBrdfs = 1 << 16;  // materials' BRDFs in metadata scene.brdfs
// The most a CPCA code's rebuilt rows (or probe matrices) may exceed the file's size by.
constexpr std::uint64_t kMaxCpcaExpansion = 256;

using F = FieldType;
using Src = MetaSource;
using Out = MetaTarget;
using Lines = SummaryLines;
constexpr bool kMust = true, kMay = false;                // required, optional
constexpr const char* kKeptMetadata = "(kept metadata)";  // the merge point of the kept metadata

TransferSet& into(Out& t) { return t.out.transfer; }
InterreflectionInfo& ir_into(Out& t) { return t.out.transfer.interreflection; }
bool reproducible_file(const Src& s) { return s.options.reproducible; }
bool interreflected(const Src& s) { return s.info.kind == TransferKind::interreflected; }
bool with_sources(const Src& s) { return s.info.interreflection.sources > 0; }
bool with_probes(const Src& s) { return s.probes && !s.probes->empty(); }

// An enumeration's name parsed, the parser's complaint as the reader's one line.
template <class Parse>
auto parse_name(const Fields& f, const char* leaf, Out& t, Parse parse) {
    try {
        return parse(f.string(leaf));
    } catch (const Error& e) {
        corrupt(t.path, "metadata: {}", e.what());
    }
}

// Accessors of plain members: of the interreflection's description and of the bake's stats.
template <auto Member>
Json ir_value(const Src& s) {
    return s.info.interreflection.*Member;
}
template <auto Member>
void ir_whole(const Fields& f, const char* leaf, Out& t) {
    ir_into(t).*Member = f.u64(leaf);
}
template <auto Member>
void ir_boolean(const Fields& f, const char* leaf, Out& t) {
    ir_into(t).*Member = f.boolean(leaf);
}
template <auto Member>
void ir_number(const Fields& f, const char* leaf, Out& t) {
    ir_into(t).*Member = f.number_or_zero(leaf);
}
template <auto Member>
Json stat_value(const Src& s) {
    return s.info.stats.*Member;
}
template <auto Member>
void stat_whole(const Fields& f, const char* leaf, Out& t) {
    into(t).stats.*Member = f.u64(leaf);
}
template <auto Member>
void stat_number(const Fields& f, const char* leaf, Out& t) {
    into(t).stats.*Member = f.number_or_zero(leaf);
}
template <auto Member>
Json probe_cpca_value(const Src& s) {
    return s.probes->cpca.*Member;
}

// A CPCA code's clusters or vectors (1 to `most`), into the counts and the code.
void code_size(const Fields& f, const char* leaf, std::uint64_t most, std::uint64_t& count,
               int& code) {
    count = f.u64(leaf, 1, most);
    code = static_cast<int>(count);
}

// A CPCA code's rows are rebuilt in memory: bounded by the file's size, as every allocation of
// the reader is (a real code is ~10-100× smaller than its rows).
bool rebuilds_too_much(const Out& t, double rows, double floats_per_row) {
    return rows * floats_per_row * 4.0 > double(kMaxCpcaExpansion) * double(t.file_size);
}

// metadata.probes' origin and spacing: 3 finite numbers (positive ones for the spacing).
Vec3f read_vec3(const Fields& p, const char* key, bool positive, const Out& t) {
    const nlohmann::json& v = p.get(key);
    if (!v.is_array() || v.size() != 3)
        corrupt(t.path, "metadata.probes: '{}' must be 3 numbers", key);
    Vec3f out;
    for (int a = 0; a < 3; ++a) {
        const nlohmann::json& x = v[std::size_t(a)];
        if (!x.is_number() || !std::isfinite(x.get<double>()) ||
            !std::isfinite(float(x.get<double>())) || (positive && !(x.get<float>() > 0)))
            corrupt(t.path, "metadata.probes: '{}' must be 3 finite{} numbers, not {}", key,
                    positive ? " positive" : "", v.dump());
        out[a] = x.get<float>();
    }
    return out;
}
Json xyz(Vec3f v) { return Json::array({v.x, v.y, v.z}); }

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

std::string text_or(const nlohmann::ordered_json& j, const char* key, const char* fallback) {
    auto it = j.find(key);
    return it != j.end() && it->is_string() ? it->get<std::string>() : std::string(fallback);
}

// ---- summaries (`shprt info`), one per summarised row -----------------------------------------

void summarise_interreflection(const Lines& s) {
    const TransferSet& t = s.file.transfer;
    const Mesh& mesh = s.file.mesh;
    if (t.kind != TransferKind::interreflected) return;
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

// ---- the table --------------------------------------------------------------------------------

// clang-format off
const std::array kFields = {
    // key, type, since, required, pass, with, written, value, read, summary rank, summarise
    FieldRule{"format", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json { return "shprt"; },
        [](const Fields& f, const char* leaf, Out& t) {
            if (f.string(leaf) != "shprt") corrupt(t.path, "metadata: format is not 'shprt'");
        }, 0, nullptr},
    // A version 3 file is a CPCA file (the "cpca" object and sections); only those carry it.
    FieldRule{"format_version", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json {
            return s.cpca ? kShprtCpcaFormatVersion : kShprtFormatVersion;
        },
        [](const Fields& f, const char* leaf, Out& t) {
            if (f.u64(leaf) != t.version)
                corrupt(t.path, "metadata: format_version {} differs from the header's {}",
                        f.u64(leaf), t.version);
            if (t.version < kShprtCpcaFormatVersion && f.obj.contains("cpca"))
                corrupt(t.path, "metadata: 'cpca' in a version {} file (CPCA files are version {})",
                        t.version, kShprtCpcaFormatVersion);
        }, 0, nullptr},
    FieldRule{"tool", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json { return "shprt"; }, nullptr, 190,
        [](const Lines& s) {
            auto version = s.meta.find("format_version");
            s.line("written by", fmt::format("{} {}, format version {}",
                                             text_or(s.meta, "tool", "shprt"),
                                             text_or(s.meta, "tool_version", "?"),
                                             version != s.meta.end() ? version->dump() : "?"));
        }},
    FieldRule{"tool_version", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json { return SHPRT_VERSION_STRING; }, nullptr, 0, nullptr},
    FieldRule{"convention", F::object, 1, kMust, 1, nullptr, nullptr, nullptr, nullptr, 0,
              nullptr},
    FieldRule{"convention.basis", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json { return kShprtConventionBasis; },
        [](const Fields& f, const char* leaf, Out& t) {
            const std::string basis = f.string(leaf);
            if (basis != kShprtConventionBasis)
                corrupt(t.path, "metadata: unsupported SH convention '{}'", basis);
        }, 0, nullptr},
    FieldRule{"convention.index", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json { return "i = l*(l+1) + m, coefficients 0..K-1"; }, nullptr, 0,
        nullptr},
    FieldRule{"convention.world", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json { return "right-handed, +Y up"; }, nullptr, 0, nullptr},
    FieldRule{"convention.transfer", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json {
            return "T(w) = V(w) max(0, n.w); irradiance E = sum_i c_T[i] c_L[i]; "
                   "outgoing radiance = albedo / pi * E";
        }, nullptr, 0, nullptr},
    FieldRule{"convention.layout", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json {
            return "transfer[(r*channels + c)*floats_per_channel + j]; floats_per_channel = K "
                   "(vector), K*K (matrix, row-major) or K*(K+1)/2 (symmetric_matrix, upper "
                   "triangle by rows)";
        }, nullptr, 0, nullptr},
    // What the transfer is. The enumerations' parse errors are reported as "metadata: <error>"
    // (with the field's own complaint inside: as the reader always did).
    FieldRule{"transfer_kind", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return to_string(s.info.kind); },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).kind = parse_name(f, leaf, t, parse_transfer_kind);
        }, 80,
        [](const Lines& s) {
            const TransferSet& t = s.file.transfer;
            const int channels = t.layout.channels;
            const std::string shape =
                t.layout.shape == TransferShape::vector
                    ? std::string()
                    : fmt::format(", {} K×K per channel", to_string(t.layout.shape));
            s.line("transfer", fmt::format("{}, {} channel{} per {}{}", to_string(t.kind), channels,
                                           channels == 1 ? "" : "s", to_string(t.layout.domain),
                                           shape));
        }},
    // Version 1 knew only per-vertex vectors; version 2 names the domain and the shape. A texel
    // transfer's receivers are texels: it needs the image ("texels") and their count.
    FieldRule{"domain", F::text, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return to_string(s.info.layout.domain); },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).layout.domain = parse_name(f, leaf, t, parse_receiver_domain);
            if (into(t).layout.domain == ReceiverDomain::texel &&
                (!f.obj.contains("receivers") || !f.obj.contains("texels")))
                corrupt(t.path, "metadata: a texel transfer needs 'receivers' and 'texels'");
        }, 0, nullptr},
    FieldRule{"shape", F::text, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return to_string(s.info.layout.shape); },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).layout.shape = parse_name(f, leaf, t, parse_transfer_shape);
        }, 0, nullptr},
    FieldRule{"K", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.info.layout.K; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).layout.K = f.integer(leaf, 1, kMaxTransferK);
        }, 90, summarise_basis},
    FieldRule{"bands", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return sh_bands_for(s.info.layout.K); },
        [](const Fields& f, const char* leaf, Out& t) {
            const int K = into(t).layout.K, bands = sh_bands_for(K);
            if (f.u64(leaf) != std::uint64_t(bands))
                corrupt(t.path, "metadata: bands = {} but K = {} needs {}", f.u64(leaf), K, bands);
        }, 0, nullptr},
    FieldRule{"last_band_full", F::boolean, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json {
            return sh_count(sh_bands_for(s.info.layout.K)) == s.info.layout.K;
        },
        [](const Fields& f, const char* leaf, Out& t) {
            const int K = into(t).layout.K;
            if (f.boolean(leaf) != (sh_count(sh_bands_for(K)) == K))
                corrupt(t.path, "metadata: last_band_full contradicts K = {}", K);
        }, 0, nullptr},
    FieldRule{"channels", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.info.layout.channels; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).layout.channels = f.integer(leaf, 1, 3);
            if (into(t).layout.channels == 2)
                corrupt(t.path, "metadata: channels must be 1 or 3, not 2");
        }, 0, nullptr},
    // Read after the kind and the shape (a version 1 file has none: a vector), the first
    // field whose check needs both.
    FieldRule{"precision", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return to_string(s.info.layout.encoding); },
        [](const Fields& f, const char* leaf, Out& t) {
            TransferLayout& layout = into(t).layout;
            if (into(t).kind == TransferKind::glossy &&
                layout.shape != TransferShape::symmetric_matrix)
                corrupt(t.path, "metadata: transfer_kind glossy needs shape symmetric_matrix, not {}",
                        to_string(layout.shape));
            const std::string precision = f.string(leaf);
            if (precision != "float32" && precision != "float16")
                corrupt(t.path, "metadata: precision '{}' (expected float32 or float16)", precision);
            layout.encoding = parse_transfer_encoding(precision);
        }, 120,
        [](const Lines& s) { s.line("precision", to_string(s.file.transfer.layout.encoding)); }},
    FieldRule{"sampler", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return to_string(s.info.sampler); },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).sampler = parse_name(f, leaf, t, parse_sampler_kind);
        }, 100,
        [](const Lines& s) {
            const TransferSet& t = s.file.transfer;
            s.line("sampling",
                   fmt::format("{}{}, {}{} samples, seed {}", to_string(t.sampler),
                               t.direction_frame == DirectionFrame::local
                                   ? " (local: tangent frames)"
                                   : "",
                               t.target_error > 0 ? "at most " : "", t.samples, t.seed));
        }},
    // Written only for a local set: a sphere bake's metadata (and bytes) stay as before it.
    FieldRule{"directions", F::text, 2, kMay, 1, nullptr,
        [](const Src& s) { return s.info.direction_frame != DirectionFrame::sphere; },
        [](const Src& s) -> Json { return to_string(s.info.direction_frame); },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).direction_frame = parse_name(f, leaf, t, parse_direction_frame);
        }, 0, nullptr},
    FieldRule{"samples", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.info.samples; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).samples = f.integer(leaf, 0, INT_MAX);
            if (const char* why = samples_refusal(into(t).kind, into(t).samples))
                corrupt(t.path, "metadata: samples = 0 for {} transfer, but {}",
                        to_string(into(t).kind), why);
        }, 0, nullptr},
    FieldRule{"seed", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.info.seed; },
        [](const Fields& f, const char* leaf, Out& t) { into(t).seed = f.u64(leaf); }, 0, nullptr},
    // An error-bounded bake's bound (its samples are then the most a receiver has); absent for
    // other bakes (0).
    FieldRule{"target_error", F::number, 2, kMay, 1, nullptr,
        [](const Src& s) { return s.info.target_error > 0; },
        [](const Src& s) -> Json { return s.info.target_error; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).target_error = f.number_or_zero(leaf);
            if (!(into(t).target_error >= 0 && into(t).target_error <= 1))
                corrupt(t.path, "metadata: target_error = {} is outside [0, 1]",
                        into(t).target_error);
        }, 110, summarise_target_error},
    // An interreflected bake's description (InterreflectionInfo).
    FieldRule{"interreflection", F::object, 2, kMay, 1, nullptr, interreflected, nullptr,
              nullptr, 150, summarise_interreflection},
    FieldRule{"interreflection.bounces", F::whole, 2, kMust, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::bounces>,
        [](const Fields& f, const char* leaf, Out& t) { ir_into(t).bounces = f.integer(leaf, 0, INT_MAX); },
        0, nullptr},
    FieldRule{"interreflection.converge", F::boolean, 2, kMust, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::converge>, ir_boolean<&InterreflectionInfo::converge>, 0,
        nullptr},
    FieldRule{"interreflection.converged", F::boolean, 2, kMust, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::converged>, ir_boolean<&InterreflectionInfo::converged>,
        0, nullptr},
    FieldRule{"interreflection.tolerance", F::number, 2, kMay, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::tolerance>, ir_number<&InterreflectionInfo::tolerance>,
        0, nullptr},
    FieldRule{"interreflection.last_change", F::number, 2, kMay, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::last_change>, ir_number<&InterreflectionInfo::last_change>,
        0, nullptr},
    FieldRule{"interreflection.two_sided", F::boolean, 2, kMust, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::two_sided>, ir_boolean<&InterreflectionInfo::two_sided>,
        0, nullptr},
    FieldRule{"interreflection.albedo_source", F::text, 2, kMust, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::albedo_source>,
        [](const Fields& f, const char* leaf, Out& t) { ir_into(t).albedo_source = f.string(leaf); },
        0, nullptr},
    FieldRule{"interreflection.operator_nnz", F::whole, 2, kMust, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::operator_nnz>, ir_whole<&InterreflectionInfo::operator_nnz>,
        0, nullptr},
    FieldRule{"interreflection.operator_bytes", F::whole, 2, kMust, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::operator_bytes>,
        ir_whole<&InterreflectionInfo::operator_bytes>, 0, nullptr},
    FieldRule{"interreflection.operator_rays", F::whole, 2, kMay, 1, nullptr, nullptr,
        ir_value<&InterreflectionInfo::operator_rays>,
        ir_whole<&InterreflectionInfo::operator_rays>, 0, nullptr},
    // The bounce sources (issue 34): absent with no bounces, and in files from before them.
    FieldRule{"interreflection.sources", F::whole, 2, kMay, 1, nullptr, with_sources,
        ir_value<&InterreflectionInfo::sources>, ir_whole<&InterreflectionInfo::sources>, 0,
        nullptr},
    // 0: the mesh's vertices alone (an infinite spacing, which JSON cannot hold).
    FieldRule{"interreflection.source_spacing", F::number, 2, kMay, 1, "sources",
        with_sources,
        [](const Src& s) -> Json {
            const double spacing = s.info.interreflection.source_spacing;
            return std::isfinite(spacing) ? spacing : 0.0;
        }, ir_number<&InterreflectionInfo::source_spacing>, 0, nullptr},
    FieldRule{"interreflection.invalid_sources", F::whole, 2, kMust, 1, "sources",
        with_sources, ir_value<&InterreflectionInfo::invalid_sources>,
        ir_whole<&InterreflectionInfo::invalid_sources>, 0, nullptr},
    FieldRule{"interreflection.indirect_samples", F::whole, 2, kMust, 1, "sources",
        with_sources, ir_value<&InterreflectionInfo::indirect_samples>,
        ir_whole<&InterreflectionInfo::indirect_samples>, 0, nullptr},
    FieldRule{"interreflection.receivers_seeing_back_faces", F::whole, 2, kMust, 1, "sources",
        with_sources, ir_value<&InterreflectionInfo::receivers_seeing_back_faces>,
        ir_whole<&InterreflectionInfo::receivers_seeing_back_faces>, 0, nullptr},
    // Since the bounces' coefficients (0: all K).
    FieldRule{"interreflection.bounce_coeffs", F::whole, 2, kMay, 1, "sources",
        [](const Src& s) { return with_sources(s) && s.info.interreflection.bounce_coeffs > 0; },
        ir_value<&InterreflectionInfo::bounce_coeffs>,
        [](const Fields& f, const char* leaf, Out& t) {
            ir_into(t).bounce_coeffs = std::uint64_t(f.integer(leaf, 1, into(t).layout.K));
        }, 0, nullptr},
    // A CPCA code instead of the rows (version 3 files only; pass 3: bounded by the receivers).
    FieldRule{"cpca", F::object, 3, kMust, 3, nullptr,
        [](const Src& s) { return s.cpca != nullptr; }, nullptr, nullptr, 130,
        [](const Lines& s) {
            const CpcaCode& c = s.file.transfer.cpca;
            if (c.empty()) return;
            s.line("cpca", fmt::format("{} clusters x {} vectors (k-means++ seed {}); rows rebuilt "
                                       "on reading",
                                       c.clusters, c.vectors, c.seed));
        }},
    FieldRule{"cpca.clusters", F::whole, 3, kMust, 3, nullptr, nullptr,
        [](const Src& s) -> Json { return s.cpca->clusters; },
        [](const Fields& f, const char* leaf, Out& t) {
            code_size(f, leaf, t.counts.receivers, t.counts.clusters, into(t).cpca.clusters);
        }, 0, nullptr},
    FieldRule{"cpca.vectors", F::whole, 3, kMust, 3, nullptr, nullptr,
        [](const Src& s) -> Json { return s.cpca->vectors; },
        [](const Fields& f, const char* leaf, Out& t) {
            code_size(f, leaf, into(t).layout.floats_per_receiver(), t.counts.vectors,
                      into(t).cpca.vectors);
        }, 0, nullptr},
    FieldRule{"cpca.seed", F::whole, 3, kMust, 3, nullptr, nullptr,
        [](const Src& s) -> Json { return s.cpca->seed; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).cpca.seed = f.u64(leaf);
            const double D = double(into(t).layout.floats_per_receiver());
            if (rebuilds_too_much(t, double(t.counts.receivers), D))
                corrupt(t.path,
                        "CPCA code of {} bytes would rebuild {:.0f} bytes of rows (more than {}× "
                        "the file)",
                        t.file_size, double(t.counts.receivers) * D * 4.0, kMaxCpcaExpansion);
        }, 0, nullptr},
    FieldRule{"cpca.method", F::text, 3, kMust, 3, nullptr, nullptr,
        [](const Src&) -> Json {
            return "k-means++ seeding (std::mt19937_64) + Lloyd, then per-cluster PCA, Frobenius "
                   "metric; row = means[cluster] + sum_i weights[i] * basis[cluster][i]";
        }, nullptr, 0, nullptr},
    // The scene the transfer belongs to (its hash is checked against the arrays once read).
    FieldRule{"scene", F::object, 1, kMust, 1, nullptr, nullptr, nullptr, nullptr, 0, nullptr},
    FieldRule{"scene.source", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.mesh.source; },
        [](const Fields& f, const char* leaf, Out& t) { t.out.mesh.source = f.string(leaf); }, 10,
        [](const Lines& s) {
            s.line("scene", s.file.mesh.source.empty() ? "(unnamed)" : s.file.mesh.source);
        }},
    FieldRule{"scene.hash", F::text, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return format_mesh_hash(mesh_hash(s.mesh)); },
        [](const Fields& f, const char* leaf, Out& t) { t.counts.recorded_hash = f.string(leaf); },
        180,
        [](const Lines& s) {
            auto scene = s.meta.find("scene");
            s.line("scene hash", scene != s.meta.end() && scene->is_object()
                                     ? text_or(*scene, "hash", "?")
                                     : format_mesh_hash(mesh_hash(s.file.mesh)));
        }},
    // The vertex domain's receivers are the vertices (all of them unless "receivers" says).
    FieldRule{"scene.vertices", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.mesh.positions.size(); },
        [](const Fields& f, const char* leaf, Out& t) {
            t.counts.vertices = t.counts.receivers = t.counts.total = f.u64(leaf);
        }, 20,
        [](const Lines& s) { s.line("vertices", fmt::format("{}", s.file.mesh.vertex_count())); }},
    FieldRule{"scene.triangles", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.mesh.triangles.size(); },
        [](const Fields& f, const char* leaf, Out& t) { t.counts.triangles = f.u64(leaf); }, 50,
        [](const Lines& s) {
            s.line("triangles", fmt::format("{}", s.file.mesh.triangle_count()));
        }},
    // The materials' BRDFs (with a brdf_index section only).
    FieldRule{"scene.brdfs", F::list, 2, kMay, 1, nullptr,
        [](const Src& s) { return !s.mesh.brdf_index.empty(); },
        [](const Src& s) -> Json {
            Json brdfs = Json::array();
            for (const Brdf& b : s.mesh.brdfs) brdfs.push_back(to_string(b));
            return brdfs;
        },
        [](const Fields& f, const char* leaf, Out& t) {
            const nlohmann::json& brdfs = f.get(leaf);
            if (!brdfs.is_array() || brdfs.size() > kMaxBrdfs)
                corrupt(t.path, "metadata.scene: 'brdfs' must be an array of at most {} specs",
                        kMaxBrdfs);
            for (const nlohmann::json& spec : brdfs) {
                if (!spec.is_string())
                    corrupt(t.path, "metadata.scene.brdfs: {} is not a BRDF spec", spec.dump());
                try {
                    t.out.mesh.brdfs.push_back(parse_brdf(spec.get<std::string>()));
                } catch (const Error& e) {
                    corrupt(t.path, "metadata.scene.brdfs: {}", e.what());
                }
            }
        }, 60,
        [](const Lines& s) {
            if (!s.file.mesh.brdf_index.empty())
                s.line("brdfs", describe_brdfs(s.file.mesh) + " (from the materials)");
        }},
    // The rows' receivers: all of them, or a shard's range (a part, see shprt_file.hpp); absent
    // in version 1 files (all vertices). Read as one (pass 2: a texel transfer's count is bounded
    // by its image).
    FieldRule{"receivers", F::object, 2, kMay, 2, nullptr, nullptr, nullptr,
        [](const Fields& f, const char* leaf, Out& t) {
            const Fields r = f.object(leaf);
            MetaCounts& c = t.counts;
            const TexelAtlas& x = into(t).texels;
            if (into(t).layout.domain == ReceiverDomain::texel)
                c.total = r.u64("total", 1, std::uint64_t(x.width) * std::uint64_t(x.height));
            if (r.u64("total") != c.total)
                corrupt(t.path, "metadata: receivers.total = {} but the scene has {} vertices",
                        r.u64("total"), c.vertices);
            const std::uint64_t first = r.u64("first", 0, c.total);
            c.receivers = r.u64("count", 1, c.total - std::min(first, c.total));
            t.out.receiver_first = static_cast<std::size_t>(first);
            if ((first != 0 || c.receivers != c.total) && !t.allow_part)
                corrupt(t.path,
                        "is part of a sharded bake (receivers [{}, {}) of {}): join the parts "
                        "with `shprt merge`",
                        first, first + c.receivers, c.total);
        }, 70,
        [](const Lines& s) {
            const ShprtFile& file = s.file;
            if (file.is_part())
                s.line("receivers",
                       fmt::format("[{}, {}) of {}: one part of a sharded bake (join the parts "
                                   "with `shprt merge`)",
                                   file.receiver_first,
                                   file.receiver_first + file.transfer.receiver_count(),
                                   file.mesh.vertex_count()));
        }},
    FieldRule{"receivers.first", F::whole, 2, kMust, 2, nullptr, nullptr,
        [](const Src& s) -> Json { return s.options.receiver_first; }, nullptr, 0, nullptr},
    FieldRule{"receivers.count", F::whole, 2, kMust, 2, nullptr, nullptr,
        [](const Src& s) -> Json { return s.rows; }, nullptr, 0, nullptr},
    FieldRule{"receivers.total", F::whole, 2, kMust, 2, nullptr, nullptr,
        [](const Src& s) -> Json {
            return s.info.layout.domain == ReceiverDomain::texel ? s.info.texels.texel.size()
                                                                 : s.mesh.positions.size();
        }, nullptr, 0, nullptr},
    // The texel domain's image (docs/texels.md); its receivers' texels are section "texel_index".
    FieldRule{"texels", F::object, 2, kMay, 1, nullptr,
        [](const Src& s) { return s.info.layout.domain == ReceiverDomain::texel; }, nullptr,
        nullptr, 40,
        [](const Lines& s) {
            const TransferSet& t = s.file.transfer;
            if (t.layout.domain != ReceiverDomain::texel) return;
            s.line("texels", fmt::format("{}x{} image, {} covered ({:.1f}%), UV set {}",
                                         t.texels.width, t.texels.height, t.texels.texel.size(),
                                         100.0 * double(t.texels.texel.size()) /
                                             (double(t.texels.width) * double(t.texels.height)),
                                         t.texels.uv_set));
        }},
    FieldRule{"texels.width", F::whole, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.info.texels.width; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).texels.width = f.integer(leaf, 1, INT_MAX);
        }, 0, nullptr},
    FieldRule{"texels.height", F::whole, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.info.texels.height; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).texels.height = f.integer(leaf, 1, INT_MAX);
        }, 0, nullptr},
    FieldRule{"texels.uv_set", F::whole, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.info.texels.uv_set; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).texels.uv_set = f.integer(leaf, 0, 7);
        }, 0, nullptr},
    FieldRule{"texels.origin", F::text, 2, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json {
            return "row 0 at v = 1 (top); texel (x, y) centre u = (x + 0.5) / width, v = 1 - "
                   "(y + 0.5) / height";
        }, nullptr, 0, nullptr},
    // Transfer probes (docs/probes.md); their arrays are sections "probe_matrices" (or the
    // probe_cpca_* code) and "probe_valid". The counts are bounded (kMaxProbeSide, kMaxProbes)
    // before any array is sized.
    FieldRule{"probes", F::object, 2, kMay, 1, nullptr, with_probes, nullptr, nullptr, 140,
        [](const Lines& s) {
            if (!s.file.transfer.probes.empty())
                s.line("probes", describe_probes(s.file.transfer.probes));
        }},
    FieldRule{"probes.origin", F::list, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return xyz(s.probes->origin); },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).probes.origin = read_vec3(f, leaf, false, t);
        }, 0, nullptr},
    FieldRule{"probes.spacing", F::list, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return xyz(s.probes->spacing); },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).probes.spacing = read_vec3(f, leaf, true, t);
        }, 0, nullptr},
    FieldRule{"probes.counts", F::list, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.probes->counts; },
        [](const Fields& f, const char* leaf, Out& t) {
            ProbeGrid& g = into(t).probes;
            const nlohmann::json& n = f.get(leaf);
            if (!n.is_array() || n.size() != 3)
                corrupt(t.path, "metadata.probes: 'counts' must be 3 whole numbers");
            for (std::size_t a = 0; a < 3; ++a) {
                if (!n[a].is_number_unsigned() || n[a].get<std::uint64_t>() < 1 ||
                    n[a].get<std::uint64_t>() > std::uint64_t(kMaxProbeSide))
                    corrupt(t.path, "metadata.probes: counts {} (each 1 to {})", n.dump(),
                            kMaxProbeSide);
                g.counts[a] = int(n[a].get<std::uint64_t>());
            }
            if (g.count() > kMaxProbes)
                corrupt(t.path, "metadata.probes: {} probes (at most {})", g.count(), kMaxProbes);
            t.counts.probes = g.count();
        }, 0, nullptr},
    FieldRule{"probes.K", F::whole, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.probes->K; },
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).probes.K = f.integer(leaf, 1, kMaxTransferK);
        }, 0, nullptr},
    FieldRule{"probes.channels", F::whole, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return s.probes->channels; },
        [](const Fields& f, const char* leaf, Out& t) {
            ProbeGrid& g = into(t).probes;
            g.channels = f.integer(leaf, 1, 3);
            if (g.channels == 2)
                corrupt(t.path, "metadata.probes: channels must be 1 or 3, not 2");
            t.counts.probe_floats =
                std::uint64_t(g.channels) * std::uint64_t(g.K) * std::uint64_t(g.K);
        }, 0, nullptr},
    // Checked against section probe_valid once read.
    FieldRule{"probes.valid", F::whole, 2, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json {
            std::size_t valid = 0;
            for (std::uint8_t v : s.probes->valid) valid += v;
            return valid;
        },
        [](const Fields& f, const char* leaf, Out& t) {
            t.counts.probes_valid = f.u64(leaf, 0, t.counts.probes);
        }, 0, nullptr},
    FieldRule{"probes.layout", F::text, 2, kMust, 1, nullptr, nullptr,
        [](const Src&) -> Json {
            return "probe (x, y, z) at origin + (x, y, z) * spacing is number x + nx*(y + ny*z); "
                   "probe_matrices[(probe*channels + c)*K*K + i*K + j]: radiance coefficient i "
                   "from light coefficient j (row-major)";
        }, nullptr, 0, nullptr},
    // The matrices stored as a CPCA code (sections probe_cpca_*, one row per valid probe, in
    // probe order), rebuilt once read: bounded by the file's size as a transfer's code is.
    FieldRule{"probes.cpca", F::object, 2, kMay, 1, nullptr,
        [](const Src& s) { return !s.probes->cpca.empty(); }, nullptr,
        [](const Fields&, const char*, Out& t) {
            if (t.counts.probes_valid == 0)
                corrupt(t.path, "metadata.probes: a CPCA code ('cpca') with no valid probe");
        }, 0, nullptr},
    FieldRule{"probes.cpca.clusters", F::whole, 2, kMust, 1, nullptr, nullptr,
        probe_cpca_value<&CpcaCode::clusters>,
        [](const Fields& f, const char* leaf, Out& t) {
            code_size(f, leaf, t.counts.probes_valid, t.counts.probe_clusters,
                      into(t).probes.cpca.clusters);
        }, 0, nullptr},
    FieldRule{"probes.cpca.vectors", F::whole, 2, kMust, 1, nullptr, nullptr,
        probe_cpca_value<&CpcaCode::vectors>,
        [](const Fields& f, const char* leaf, Out& t) {
            code_size(f, leaf, t.counts.probe_floats, t.counts.probe_vectors,
                      into(t).probes.cpca.vectors);
        }, 0, nullptr},
    FieldRule{"probes.cpca.seed", F::whole, 2, kMust, 1, nullptr, nullptr,
        probe_cpca_value<&CpcaCode::seed>,
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).probes.cpca.seed = f.u64(leaf);
            const MetaCounts& c = t.counts;
            if (rebuilds_too_much(t, double(c.probes), double(c.probe_floats)))
                corrupt(t.path,
                        "metadata.probes: a CPCA code in {} bytes would rebuild {:.0f} bytes of "
                        "probe matrices (more than {}× the file)",
                        t.file_size, double(c.probes) * double(c.probe_floats) * 4.0,
                        kMaxCpcaExpansion);
        }, 0, nullptr},
    // WriteOptions::kept_metadata_json: facts the same inputs reproduce, kept in reproducible
    // files too — the bake's "texel_bake" (coverage, unwrap) and "refinement" (passes, budget).
    FieldRule{kKeptMetadata, F::extra, 2, kMay, 1, nullptr, nullptr, nullptr, nullptr, 0,
              nullptr},
    FieldRule{"texel_bake", F::object, 2, kMay, 1, nullptr, nullptr, nullptr, nullptr, 0,
              nullptr},
    // Summarised from section vertex_parents, which every refined mesh has.
    FieldRule{"refinement", F::object, 2, kMay, 1, nullptr, nullptr, nullptr, nullptr, 30,
        [](const Lines& s) {
            const Mesh& mesh = s.file.mesh;
            if (mesh.parents.empty()) return;
            std::size_t added = 0;
            for (const auto& p : mesh.parents) added += p[0] != Mesh::kNoParent;
            s.line("refined",
                   fmt::format("{} vertices added by adaptive refinement (vertex_parents)", added));
        }},
    // The bake's statistics: what differs between two runs of one bake (not in reproducible
    // files). Absent numbers read as 0.
    FieldRule{"stats", F::object, 1, kMay, 1, nullptr,
        [](const Src& s) { return !reproducible_file(s); }, nullptr, nullptr, 160, summarise_stats},
    FieldRule{"stats.device", F::text, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::device_name>,
        [](const Fields& f, const char* leaf, Out& t) {
            into(t).stats.device_name = f.string(leaf);
        }, 0, nullptr},
    FieldRule{"stats.seconds_bvh", F::number, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::seconds_bvh>, stat_number<&BakeStats::seconds_bvh>, 0, nullptr},
    FieldRule{"stats.seconds_trace", F::number, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::seconds_trace>, stat_number<&BakeStats::seconds_trace>, 0, nullptr},
    FieldRule{"stats.seconds_project", F::number, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::seconds_project>, stat_number<&BakeStats::seconds_project>, 0,
        nullptr},
    FieldRule{"stats.seconds_total", F::number, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::seconds_total>, stat_number<&BakeStats::seconds_total>, 0, nullptr},
    FieldRule{"stats.rays_cast", F::whole, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::rays_cast>, stat_whole<&BakeStats::rays_cast>, 0, nullptr},
    FieldRule{"stats.peak_bytes_host", F::whole, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::peak_bytes_host>, stat_whole<&BakeStats::peak_bytes_host>, 0,
        nullptr},
    FieldRule{"stats.peak_bytes_device", F::whole, 1, kMay, 1, nullptr, nullptr,
        stat_value<&BakeStats::peak_bytes_device>, stat_whole<&BakeStats::peak_bytes_device>, 0,
        nullptr},
    // An interreflected bake's two more stages.
    FieldRule{"stats.seconds_operator", F::number, 2, kMay, 1, nullptr,
        [](const Src& s) {
            return s.info.stats.seconds_operator > 0 || s.info.stats.seconds_bounces > 0;
        },
        stat_value<&BakeStats::seconds_operator>, stat_number<&BakeStats::seconds_operator>, 0,
        nullptr},
    FieldRule{"stats.seconds_bounces", F::number, 2, kMay, 1, nullptr,
        [](const Src& s) {
            return s.info.stats.seconds_operator > 0 || s.info.stats.seconds_bounces > 0;
        },
        stat_value<&BakeStats::seconds_bounces>, stat_number<&BakeStats::seconds_bounces>, 0,
        nullptr},
    FieldRule{"stats.operator_bytes_spilled", F::whole, 2, kMay, 1, nullptr,
        [](const Src& s) { return s.info.stats.operator_bytes_spilled > 0; },
        stat_value<&BakeStats::operator_bytes_spilled>,
        stat_whole<&BakeStats::operator_bytes_spilled>, 0, nullptr},
    // WriteOptions::extra_metadata_json (timings, the command line, a shard's index): not in
    // reproducible files.
    FieldRule{"(extra metadata)", F::extra, 1, kMay, 1, nullptr,
        [](const Src& s) { return !reproducible_file(s); }, nullptr, nullptr, 0, nullptr},
    // The section table (shprt_sections.hpp), last: the reader matches it to the section rules
    // itself (shprt_read.cpp, read_section_table).
    FieldRule{"sections", F::list, 1, kMust, 3, nullptr, nullptr,
        [](const Src& s) -> Json {
            Json table = Json::array();
            for (const SectionOut& e : s.sections)
                table.push_back({{"name", e.name},
                                 {"dtype", e.dtype},
                                 {"shape", {e.rows, e.cols}},
                                 {"count", e.count()},
                                 {"offset", e.offset},
                                 {"length", e.length()},
                                 {"crc32", e.crc}});
            return table;
        }, nullptr, 170, summarise_file_size},
};
// clang-format on

// Adds `extra` into `target`: objects merge recursively, any other collision is an error (the
// writer's own fields must stay what the reader expects).
void merge_extra(Json& target, const Json& extra, const std::string& where) {
    for (auto it = extra.begin(); it != extra.end(); ++it) {
        const std::string key = where.empty() ? it.key() : where + "." + it.key();
        if (!target.contains(it.key())) {
            target[it.key()] = it.value();
        } else if (target[it.key()].is_object() && it.value().is_object()) {
            merge_extra(target[it.key()], it.value(), key);
        } else {
            fail(ErrorCode::invalid_argument,
                 "extra metadata key '{}' would replace a value the writer sets", key);
        }
    }
}

// The row of the object holding `rule` (null at the root).
const FieldRule* parent_of(const FieldRule& rule) {
    const std::string_view key = rule.key;
    const std::size_t dot = key.rfind('.');
    if (dot == std::string_view::npos) return nullptr;
    for (const FieldRule& r : kFields)
        if (key.substr(0, dot) == r.key) return &r;
    return nullptr;
}

const char* leaf_of(const FieldRule& rule) {
    const char* dot = std::strrchr(rule.key, '.');
    return dot ? dot + 1 : rule.key;
}

bool is_written(const FieldRule& rule, const Src& s) {
    const FieldRule* parent = parent_of(rule);
    // The parent first: a row's own test may look into its parent's part (s.probes, s.cpca).
    return (!parent || is_written(*parent, s)) && (!rule.written || rule.written(s));
}

// The object that holds `rule` in the file (nullopt: absent and optional, or not read in a file
// of that version); a required object that is absent is the "missing field" error.
std::optional<Fields> parent_fields(const FieldRule& rule, const Fields& root, const Out& t) {
    const FieldRule* parent = parent_of(rule);
    if (!parent) return root;
    const std::optional<Fields> above = parent_fields(*parent, root, t);
    if (!above || parent->since > t.version) return std::nullopt;
    const char* leaf = leaf_of(*parent);
    if (!parent->required && !above->obj.contains(leaf)) return std::nullopt;
    return above->object(leaf);
}

// Whether `value` is of the JSON type the row states (checked in debug builds, as written).
[[maybe_unused]] bool has_type(FieldType type, const Json& value) {
    switch (type) {
        case FieldType::text:
            return value.is_string();
        case FieldType::whole:
            return value.is_number_integer();
        case FieldType::number:
            return value.is_number();
        case FieldType::boolean:
            return value.is_boolean();
        case FieldType::list:
            return value.is_array();
        case FieldType::object:
            return value.is_object();
        case FieldType::extra:
            break;
    }
    return false;
}

}  // namespace

void SummaryLines::line(const char* label, const std::string& value) const {
    out += fmt::format("{:<13}{}\n", label, value);
}

std::span<const FieldRule> field_rules() { return kFields; }

Json write_metadata(const MetaSource& s) {
    Json m;
    for (const FieldRule& rule : kFields) {
        if (!is_written(rule, s)) continue;
        if (rule.type == FieldType::extra) {
            const bool kept = std::string_view(rule.key) == kKeptMetadata;
            merge_extra(m, kept ? parse_extra(s.options.kept_metadata_json) : s.extra, "");
        } else if (rule.value) {
            std::string pointer = std::string("/") + rule.key;
            std::replace(pointer.begin(), pointer.end(), '.', '/');
            Json& field = m[Json::json_pointer(pointer)];
            field = rule.value(s);
            SHPRT_DCHECK(has_type(rule.type, field));
        }
    }
    return m;
}

void read_metadata(const Fields& metadata, MetaTarget& t) {
    for (int pass = 1; pass <= 3; ++pass)
        for (const FieldRule& rule : kFields) {
            if (rule.pass != pass || !rule.read || rule.since > t.version) continue;
            const std::optional<Fields> parent = parent_fields(rule, metadata, t);
            if (!parent) continue;
            const char* leaf = leaf_of(rule);
            if (rule.with && !parent->obj.contains(rule.with)) continue;
            if (!rule.required && !parent->obj.contains(leaf)) continue;
            rule.read(*parent, leaf, t);
        }
}

std::string summarise_metadata(const ShprtFile& file) {
    // The metadata comes from read_shprt (already validated) or a writer; tolerate anything.
    nlohmann::ordered_json meta =
        nlohmann::ordered_json::parse(file.metadata_json, nullptr, /*allow_exceptions=*/false);
    if (!meta.is_object()) meta = nlohmann::ordered_json::object();
    std::vector<const FieldRule*> rows;
    for (const FieldRule& rule : kFields)
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
