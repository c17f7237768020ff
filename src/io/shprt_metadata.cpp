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
#include "shprt/transfer/kind_table.hpp"

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
constexpr bool kMust = true, kMay = false;  // required, optional

TransferSet& into(Out& t) { return t.out.transfer; }
InterreflectionInfo& ir_into(Out& t) { return t.out.transfer.interreflection; }
bool reproducible_file(const Src& s) { return s.options.reproducible; }
bool interreflected(const Src& s) { return kind_row(s.info.kind).interreflection; }
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

std::string text_or(const nlohmann::ordered_json& j, const char* key, const char* fallback) {
    auto it = j.find(key);
    return it != j.end() && it->is_string() ? it->get<std::string>() : std::string(fallback);
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
    // The newest version among the file's sections (file_version: a CPCA code's make it 3); the
    // rows of a newer version than the file's are neither written nor allowed (the walks).
    FieldRule{"format_version", F::whole, 1, kMust, 1, nullptr, nullptr,
        [](const Src& s) -> Json { return file_version(s.sections); },
        [](const Fields& f, const char* leaf, Out& t) {
            if (f.u64(leaf) != t.version)
                corrupt(t.path, "metadata: format_version {} differs from the header's {}",
                        f.u64(leaf), t.version);
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
                !is_matrix(t.layout)
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
            if (is_texel(into(t).layout) &&
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
            // A matrix kind is stored as its row's matrices (a vector kind may be narrowed).
            const TransferKindRow& row = kind_row(into(t).kind);
            if (is_matrix(row) && layout.shape != row.shape)
                corrupt(t.path, "metadata: transfer_kind {} needs shape {}, not {}", row.name,
                        to_string(row.shape), to_string(layout.shape));
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
    // A CPCA code instead of the rows (version 3 files, those with the code's sections: every
    // one; pass 3: bounded by the receivers).
    FieldRule{"cpca", F::object, 3, kMust, 3, nullptr, nullptr, nullptr, nullptr, 130,
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
            if (is_texel(into(t).layout))
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
            return is_texel(s.info.layout) ? s.info.texels.texel.size()
                                                                 : s.mesh.positions.size();
        }, nullptr, 0, nullptr},
    // The texel domain's image (docs/texels.md); its receivers' texels are section "texel_index".
    FieldRule{"texels", F::object, 2, kMay, 1, nullptr,
        [](const Src& s) { return is_texel(s.info.layout); }, nullptr,
        nullptr, 40,
        [](const Lines& s) {
            const TransferSet& t = s.file.transfer;
            if (!is_texel(t.layout)) return;
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

}  // namespace

std::span<const FieldRule> field_rules() { return kFields; }

}  // namespace shprt::detail
