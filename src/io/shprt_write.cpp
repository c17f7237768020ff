// Writer of the .shprt file (layout: docs/file_format.md, include/shprt/io/shprt_format.hpp;
// sections: the table of shprt_sections.hpp). Two passes over the arrays: the first computes each
// section's CRC-32 (the CRCs live in the metadata, which precedes the data), the second writes;
// float16 sections are converted in small chunks both times, so writing never holds a second copy
// of the coefficients.
#include "io/shprt_sections.hpp"
#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/half.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"
#include "shprt/sh/basis.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace shprt {
namespace {

using Json = nlohmann::ordered_json;

constexpr std::size_t kChunkElements = 1 << 16;

struct SectionOut {
    const char* name;
    std::string dtype;
    std::uint64_t rows, cols;  // shape [rows, cols]; count = rows · cols elements
    std::uint64_t element_size;
    const void* data;
    bool to_half = false;  // data is float32, stored as float16
    std::uint64_t offset = 0;
    std::uint32_t crc = 0;

    std::uint64_t count() const { return rows * cols; }
    std::uint64_t length() const { return count() * element_size; }
};

// Calls fn(bytes, size) over the section's stored bytes in order.
template <class Fn>
void for_each_chunk(const SectionOut& s, Fn&& fn) {
    if (!s.to_half) {
        const auto* p = static_cast<const unsigned char*>(s.data);
        const std::uint64_t chunk = kChunkElements * s.element_size;
        for (std::uint64_t done = 0; done < s.length(); done += chunk)
            fn(p + done, static_cast<std::size_t>(std::min(chunk, s.length() - done)));
        return;
    }
    const auto* f = static_cast<const float*>(s.data);
    std::vector<std::uint16_t> buffer(kChunkElements);
    for (std::uint64_t done = 0; done < s.count(); done += kChunkElements) {
        const std::size_t n =
            static_cast<std::size_t>(std::min<std::uint64_t>(kChunkElements, s.count() - done));
        for (std::size_t i = 0; i < n; ++i) buffer[i] = float_to_half(f[done + i]);
        fn(buffer.data(), n * sizeof(std::uint16_t));
    }
}

// Index of the first value whose magnitude bits (sign cleared) are >= `limit_bits`, or `n`.
// A branch-free max over the bits first (it vectorises), the search only on failure.
std::size_t first_magnitude_at_or_above(const float* p, std::size_t n, std::uint32_t limit_bits) {
    std::uint32_t worst = 0;
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, float_as_u32(p[i]) & 0x7fffffffu);
    if (worst < limit_bits) return n;
    for (std::size_t i = 0; i < n; ++i)
        if ((float_as_u32(p[i]) & 0x7fffffffu) >= limit_bits) return i;
    return n;
}

void check_inputs(const std::string& path, const Mesh& mesh, const TransferSet& t,
                  std::size_t first) {
    try {
        t.check_rows(mesh, first);
    } catch (const Error& e) {
        fail(ErrorCode::invalid_argument, "{}: {}", path, e.what());
    }
    const std::size_t V = mesh.positions.size();
    SHPRT_CHECK(mesh.source_vertex.empty() || mesh.source_vertex.size() == V, invalid_argument,
                "{}: mesh has {} positions but {} source_vertex entries", path, V,
                mesh.source_vertex.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        for (std::uint32_t index : mesh.triangles[i])
            SHPRT_CHECK(index < V, invalid_argument,
                        "{}: triangle {} uses vertex {} but the mesh has {} vertices", path, i,
                        index, V);
    SHPRT_CHECK(t.samples >= 0, invalid_argument, "{}: negative sample count {}", path, t.samples);
    // Finite, and in float16 below its overflow threshold 65520 (bits 0x477ff000).
    const bool half = t.layout.encoding == TransferEncoding::f16;
    const std::uint32_t limit = half ? 0x477ff000u : 0x7f800000u;
    const std::size_t bad = first_magnitude_at_or_above(t.coeffs.data(), t.coeffs.size(), limit);
    if (bad < t.coeffs.size()) {
        const float c = t.coeffs[bad];
        const std::size_t row = t.layout.floats_per_receiver();
        fail(ErrorCode::invalid_argument, "{}: transfer coefficient {} of vertex {} ({}) {}", path,
             bad % t.layout.floats_per_channel(), bad / row, c,
             std::isfinite(c) ? "overflows float16" : "is not finite");
    }
}

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

Json stats_json(const BakeStats& s) {
    Json j;
    j["device"] = s.device_name;
    j["seconds_bvh"] = s.seconds_bvh;
    j["seconds_trace"] = s.seconds_trace;
    j["seconds_project"] = s.seconds_project;
    j["seconds_total"] = s.seconds_total;
    j["rays_cast"] = s.rays_cast;
    j["peak_bytes_host"] = s.peak_bytes_host;
    j["peak_bytes_device"] = s.peak_bytes_device;
    return j;
}

Json build_metadata(const Mesh& mesh, const TransferSet& t, const WriteOptions& options,
                    const Json& extra, const std::vector<SectionOut>& sections) {
    const int bands = sh_bands_for(t.layout.K);
    Json m;
    m["format"] = "shprt";
    m["format_version"] = kShprtFormatVersion;
    m["tool"] = "shprt";
    m["tool_version"] = SHPRT_VERSION_STRING;
    m["convention"] = {
        {"basis", kShprtConventionBasis},
        {"index", "i = l*(l+1) + m, coefficients 0..K-1"},
        {"world", "right-handed, +Y up"},
        {"transfer",
         "T(w) = V(w) max(0, n.w); irradiance E = sum_i c_T[i] c_L[i]; "
         "outgoing radiance = albedo / pi * E"},
        {"layout",
         "transfer[(r*channels + c)*floats_per_channel + j]; floats_per_channel = K "
         "(vector), K*K (matrix, row-major) or K*(K+1)/2 (symmetric_matrix, upper "
         "triangle by rows)"},
    };
    m["transfer_kind"] = to_string(t.kind);
    m["domain"] = to_string(t.layout.domain);
    m["shape"] = to_string(t.layout.shape);
    m["K"] = t.layout.K;
    m["bands"] = bands;
    m["last_band_full"] = sh_count(bands) == t.layout.K;
    m["channels"] = t.layout.channels;
    m["precision"] = to_string(t.layout.encoding);
    m["sampler"] = to_string(t.sampler);
    m["samples"] = t.samples;
    m["seed"] = t.seed;
    m["scene"] = {
        {"source", mesh.source},
        {"hash", format_mesh_hash(mesh_hash(mesh))},
        {"vertices", mesh.positions.size()},
        {"triangles", mesh.triangles.size()},
    };
    // The rows' receivers: all of them, or a shard's range (a part, see shprt_file.hpp).
    m["receivers"] = {
        {"first", options.receiver_first},
        {"count", t.receiver_count()},
        {"total", mesh.positions.size()},
    };
    if (!options.reproducible) {
        m["stats"] = stats_json(t.stats);
        merge_extra(m, extra, "");
    }
    Json table = Json::array();
    for (const SectionOut& s : sections)
        table.push_back({{"name", s.name},
                         {"dtype", s.dtype},
                         {"shape", {s.rows, s.cols}},
                         {"count", s.count()},
                         {"offset", s.offset},
                         {"length", s.length()},
                         {"crc32", s.crc}});
    m["sections"] = std::move(table);
    return m;
}

}  // namespace

void write_shprt(const std::string& path, const Mesh& mesh, const TransferSet& transfer,
                 const WriteOptions& options) {
    check_inputs(path, mesh, transfer, options.receiver_first);
    Json extra = Json::object();
    if (!options.extra_metadata_json.empty()) {
        try {
            extra = Json::parse(options.extra_metadata_json);
        } catch (const Json::exception& e) {
            fail(ErrorCode::invalid_argument, "extra metadata is not valid JSON: {}", e.what());
        }
        SHPRT_CHECK(extra.is_object(), invalid_argument, "extra metadata must be a JSON object");
    }

    // The sections the table lists, in its order; an empty optional array is left out.
    const detail::SectionCounts counts{mesh.positions.size(), mesh.triangles.size(),
                                       transfer.receiver_count(), transfer.layout};
    std::vector<SectionOut> sections;
    for (const detail::SectionRule& rule : detail::section_rules()) {
        if (!rule.required && rule.count(mesh, transfer) == 0) continue;
        const bool to_half = rule.element_size(transfer.layout) == 2;  // float32 stored as f16
        sections.push_back({rule.name, rule.dtype(transfer.layout), rule.row_count(counts),
                            rule.col_count(transfer.layout), rule.element_size(transfer.layout),
                            rule.data(mesh, transfer), to_half});
    }
    for (SectionOut& s : sections)
        for_each_chunk(s, [&](const void* p, std::size_t n) { s.crc = crc32(p, n, s.crc); });

    // The offsets are written inside the metadata that precedes them: lay out, render the JSON,
    // and repeat until the data start no longer moves (the JSON only grows as offsets grow).
    std::string text;
    std::uint64_t data_start = shprt_align(kShprtHeaderSize);
    for (int iteration = 0;; ++iteration) {
        SHPRT_CHECK(iteration < 16, invalid_argument, "{}: metadata layout did not settle", path);
        std::uint64_t offset = data_start;
        for (SectionOut& s : sections) {
            s.offset = offset;
            offset = shprt_align(offset + s.length());
        }
        text = build_metadata(mesh, transfer, options, extra, sections)
                   .dump(2, ' ', false, Json::error_handler_t::replace);
        text += '\n';
        const std::uint64_t needed = shprt_align(kShprtHeaderSize + text.size());
        if (needed < data_start)  // cannot happen as offsets only grow; pad to stay canonical
            text.append(data_start - kShprtAlignment + 1 - kShprtHeaderSize - text.size(), ' ');
        if (needed <= data_start) break;
        data_start = needed;
    }
    SHPRT_CHECK(text.size() <= kShprtMaxMetadataBytes, invalid_argument,
                "{}: metadata is {} bytes (limit {})", path, text.size(), kShprtMaxMetadataBytes);

    ShprtHeader header;
    header.version = kShprtFormatVersion;
    header.endian_marker = kShprtEndianMarker;
    header.header_size = kShprtHeaderSize;
    header.metadata_offset = kShprtHeaderSize;
    header.metadata_length = text.size();
    header.metadata_crc32 = crc32(text.data(), text.size());
    unsigned char header_bytes[kShprtHeaderSize];
    encode_shprt_header(header, header_bytes);

    AtomicFile file(path);
    file.write(header_bytes, sizeof header_bytes);
    file.write(text);
    std::uint64_t position = kShprtHeaderSize + text.size();
    static constexpr unsigned char kZeros[kShprtAlignment] = {};
    for (const SectionOut& s : sections) {
        file.write(kZeros, static_cast<std::size_t>(s.offset - position));
        for_each_chunk(s, [&](const void* p, std::size_t n) { file.write(p, n); });
        position = s.offset + s.length();
    }
    file.commit();
}

}  // namespace shprt
