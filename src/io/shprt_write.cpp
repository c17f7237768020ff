// Writer of the .shprt file (layout: docs/file_format.md, include/shprt/io/shprt_format.hpp;
// sections: the table of shprt_sections.hpp). Two passes over the arrays: the first computes each
// section's CRC-32 (the CRCs live in the metadata, which precedes the data), the second writes;
// float16 sections are converted in small chunks both times, so writing never holds a second copy
// of the coefficients. The pieces are shared with the streaming writer (shprt_stream.cpp).
#include "io/shprt_metadata.hpp"
#include "io/shprt_write_internal.hpp"
#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/half.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace shprt {
namespace detail {
namespace {

constexpr std::size_t kChunkElements = 1 << 16;

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

}  // namespace

void for_each_chunk(const SectionOut& s, const std::function<void(const void*, std::size_t)>& fn) {
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

void check_samples(const std::string& path, TransferKind kind, int samples) {
    if (const char* why = samples_refusal(kind, samples))
        fail(ErrorCode::invalid_argument, "{}: samples = {} for {} transfer, but {}", path, samples,
             to_string(kind), why);
}

void check_mesh(const std::string& path, const Mesh& mesh) {
    const std::size_t V = mesh.positions.size();
    SHPRT_CHECK(mesh.source_vertex.empty() || mesh.source_vertex.size() == V, invalid_argument,
                "{}: mesh has {} positions but {} source_vertex entries", path, V,
                mesh.source_vertex.size());
    SHPRT_CHECK(mesh.brdf_index.empty() || mesh.brdf_index.size() == V, invalid_argument,
                "{}: mesh has {} positions but {} BRDF indices", path, V, mesh.brdf_index.size());
    if (const auto v = bad_brdf_index(mesh))
        fail(ErrorCode::invalid_argument,
             "{}: vertex {} has BRDF index {} but the mesh has {} BRDFs", path, *v,
             mesh.brdf_index[*v], mesh.brdfs.size());
    SHPRT_CHECK(mesh.brdf_index.empty() == mesh.brdfs.empty(), invalid_argument,
                "{}: the mesh has {} BRDFs and {} BRDF indices (both or neither)", path,
                mesh.brdfs.size(), mesh.brdf_index.size());
    for (const Brdf& b : mesh.brdfs) check_brdf(b);
    if (const auto v = bad_albedo(mesh))
        fail(ErrorCode::invalid_argument, "{}: vertex {} has albedo ({}, {}, {}), outside [0, 1]",
             path, *v, mesh.albedo[*v].x, mesh.albedo[*v].y, mesh.albedo[*v].z);
    if (const auto v = zero_normal(mesh))
        fail(ErrorCode::invalid_argument, "{}: vertex {} has a zero (or non-finite) normal", path,
             *v);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        for (std::uint32_t index : mesh.triangles[i])
            SHPRT_CHECK(index < V, invalid_argument,
                        "{}: triangle {} uses vertex {} but the mesh has {} vertices", path, i,
                        index, V);
}

void check_coefficients(const std::string& path, const float* coeffs, std::size_t n,
                        const TransferLayout& layout, std::size_t first_receiver) {
    // Finite, and in float16 below its overflow threshold 65520 (bits 0x477ff000).
    const bool half = layout.encoding == TransferEncoding::f16;
    const std::uint32_t limit = half ? 0x477ff000u : 0x7f800000u;
    const std::size_t bad = first_magnitude_at_or_above(coeffs, n, limit);
    if (bad < n) {
        const float c = coeffs[bad];
        const std::size_t row = layout.floats_per_receiver();
        fail(ErrorCode::invalid_argument, "{}: transfer coefficient {} of vertex {} ({}) {}", path,
             bad % layout.floats_per_channel(), first_receiver + bad / row, c,
             std::isfinite(c) ? "overflows float16" : "is not finite");
    }
}

Json parse_extra(const WriteOptions& options) { return parse_extra(options.extra_metadata_json); }

Json parse_extra(const std::string& text) {
    Json extra = Json::object();
    if (text.empty()) return extra;
    try {
        extra = Json::parse(text);
    } catch (const Json::exception& e) {
        fail(ErrorCode::invalid_argument, "extra metadata is not valid JSON: {}", e.what());
    }
    SHPRT_CHECK(extra.is_object(), invalid_argument, "extra metadata must be a JSON object");
    return extra;
}

std::vector<SectionOut> plan_sections(const Mesh& mesh, const TransferInfo& info, std::size_t rows,
                                      const float* coeffs, const TransferSet* transfer) {
    // The table's accessors read the mesh and the optional transfer parts; the transfer's data
    // is `coeffs`.
    const TransferSet none;
    const TransferSet& parts = transfer ? *transfer : none;
    const detail::SectionCounts counts = section_counts(mesh, info.layout, rows, parts);
    std::vector<SectionOut> sections;
    for (const detail::SectionRule& rule : detail::section_rules()) {
        if (!rule.applies(counts)) continue;  // e.g. the rows when a CPCA code stands for them
        const bool is_transfer = rule.is_transfer();
        if (!rule.required && rule.count(mesh, parts) == 0) continue;
        const bool to_half = rule.element_size(info.layout) == 2;  // float32 stored as f16
        sections.push_back({rule.name, rule.dtype(info.layout), rule.row_count(counts),
                            rule.col_count(counts), rule.element_size(info.layout),
                            is_transfer ? coeffs : rule.data(mesh, parts), to_half});
        sections.back().since = rule.since;
        sections.back().streamed = is_transfer && coeffs == nullptr;
    }
    for (SectionOut& s : sections)
        if (!s.streamed)
            for_each_chunk(s, [&](const void* p, std::size_t n) { s.crc = crc32(p, n, s.crc); });
    return sections;
}

std::string lay_out(const std::string& path, const Mesh& mesh, const TransferInfo& info,
                    std::size_t rows, const WriteOptions& options, const Json& extra,
                    std::vector<SectionOut>& sections, std::size_t reserve, const CpcaCode* cpca,
                    const ProbeGrid* probes) {
    const auto render = [&] {
        return write_metadata({mesh, info, rows, options, extra, sections, cpca, probes})
                   .dump(2, ' ', false, Json::error_handler_t::replace) +
               '\n';
    };
    const auto place = [&](std::uint64_t data_start) {
        std::uint64_t offset = data_start;
        for (SectionOut& s : sections) {
            s.offset = offset;
            offset = shprt_align(offset + s.length());
        }
    };
    std::string text;
    if (reserve > 0) {  // a fixed length: the sections' places are known before the metadata
        place(shprt_align(kShprtHeaderSize + reserve));
        text = render();
        SHPRT_CHECK(text.size() <= reserve, invalid_argument,
                    "{}: metadata grew to {} bytes past the {} reserved for it", path, text.size(),
                    reserve);
        text.append(reserve - text.size(), ' ');
    } else {
        // The offsets are written inside the metadata that precedes them: lay out, render the
        // JSON, and repeat until the data start no longer moves (the JSON only grows as offsets
        // grow).
        std::uint64_t data_start = shprt_align(kShprtHeaderSize);
        for (int iteration = 0;; ++iteration) {
            SHPRT_CHECK(iteration < 16, invalid_argument, "{}: metadata layout did not settle",
                        path);
            place(data_start);
            text = render();
            const std::uint64_t needed = shprt_align(kShprtHeaderSize + text.size());
            if (needed < data_start)  // cannot happen as offsets only grow; pad to stay canonical
                text.append(data_start - kShprtAlignment + 1 - kShprtHeaderSize - text.size(), ' ');
            if (needed <= data_start) break;
            data_start = needed;
        }
    }
    SHPRT_CHECK(text.size() <= kShprtMaxMetadataBytes, invalid_argument,
                "{}: metadata is {} bytes (limit {})", path, text.size(), kShprtMaxMetadataBytes);
    return text;
}

std::uint32_t file_version(const std::vector<SectionOut>& sections) {
    std::uint32_t version = kShprtFormatVersion;
    for (const SectionOut& s : sections) version = std::max(version, s.since);
    return version;
}

void encode_header(const std::string& text, unsigned char out[kShprtHeaderSize],
                   std::uint32_t version) {
    ShprtHeader header;
    header.version = version;
    header.endian_marker = kShprtEndianMarker;
    header.header_size = kShprtHeaderSize;
    header.metadata_offset = kShprtHeaderSize;
    header.metadata_length = text.size();
    header.metadata_crc32 = crc32(text.data(), text.size());
    encode_shprt_header(header, out);
}

void write_file_body(AtomicFile& file, const std::string& text,
                     const std::vector<SectionOut>& sections) {
    unsigned char header_bytes[kShprtHeaderSize];
    encode_header(text, header_bytes, file_version(sections));
    file.write(header_bytes, sizeof header_bytes);
    file.write(text);
    std::uint64_t position = kShprtHeaderSize + text.size();
    static constexpr unsigned char kZeros[kShprtAlignment] = {};
    for (const SectionOut& s : sections) {
        if (s.streamed) break;  // the transfer (last) is written by its sink
        file.write(kZeros, static_cast<std::size_t>(s.offset - position));
        for_each_chunk(s, [&](const void* p, std::size_t n) { file.write(p, n); });
        position = s.offset + s.length();
    }
}

}  // namespace detail

void write_shprt(const std::string& path, const Mesh& mesh, const TransferSet& transfer,
                 const WriteOptions& options) {
    try {
        transfer.check_rows(mesh, options.receiver_first);
    } catch (const Error& e) {
        fail(ErrorCode::invalid_argument, "{}: {}", path, e.what());
    }
    detail::check_mesh(path, mesh);
    detail::check_samples(path, transfer.kind, transfer.samples);
    detail::check_coefficients(path, transfer.coeffs.data(), transfer.coeffs.size(),
                               transfer.layout, options.receiver_first);
    if (!transfer.direct.empty()) {
        detail::check_coefficients(path, transfer.direct.data(), transfer.direct.size(),
                                   direct_part_layout(transfer.layout), options.receiver_first);
    }
    if (!transfer.probes.empty()) {
        try {
            transfer.probes.validate();
        } catch (const Error& e) {
            fail(ErrorCode::invalid_argument, "{}: {}", path, e.what());
        }
        const auto& p = transfer.probes.matrices;
        const auto bad =
            std::find_if(p.begin(), p.end(), [](float v) { return !std::isfinite(v); });
        SHPRT_CHECK(bad == p.end(), invalid_argument, "{}: probe matrix value {} is not finite",
                    path, bad - p.begin());
    }
    const detail::Json extra = detail::parse_extra(options);
    const std::size_t rows = transfer.receiver_count();
    std::vector<detail::SectionOut> sections =
        detail::plan_sections(mesh, transfer, rows, transfer.coeffs.data(), &transfer);
    const std::string text = detail::lay_out(path, mesh, transfer, rows, options, extra, sections,
                                             0, &transfer.cpca, &transfer.probes);
    AtomicFile file(path);
    detail::write_file_body(file, text, sections);
    file.commit();
}

}  // namespace shprt
