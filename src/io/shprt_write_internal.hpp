// Pieces of the .shprt writer shared by write_shprt (shprt_write.cpp) and the streaming writer
// (shprt_stream.cpp). Private to src/io.
#pragma once

#include "io/shprt_sections.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace shprt::detail {

using Json = nlohmann::ordered_json;

// One section as written: its table entry's values and where its bytes come from.
struct SectionOut {
    const char* name;
    std::string dtype;
    std::uint64_t rows, cols;  // shape [rows, cols]; count = rows · cols elements
    std::uint64_t element_size;
    const void* data;       // null: the transfer of a streamed file, written by its sink
    bool to_half = false;   // data is float32, stored as float16
    bool streamed = false;  // the transfer of a streamed file: written by its sink, CRC later
    std::uint64_t offset = 0;
    std::uint32_t crc = 0;
    std::uint32_t since = 1;  // the format version whose files first hold it (its table row's)

    std::uint64_t count() const { return rows * cols; }
    std::uint64_t length() const { return count() * element_size; }
};

// Calls fn(bytes, size) over the section's stored bytes in order (float16 converted in chunks).
void for_each_chunk(const SectionOut& s, const std::function<void(const void*, std::size_t)>& fn);

// Error(invalid_argument) "<path>: ..." for a source_vertex of the wrong size or a triangle index
// out of range.
void check_mesh(const std::string& path, const Mesh& mesh);
// Error(invalid_argument) "<path>: samples = N, but ..." where samples_refusal (transfer.hpp)
// gives a reason.
void check_samples(const std::string& path, TransferKind kind, int samples);
// Error(invalid_argument) "<path>: ..." for a coefficient that is not finite or, for float16,
// out of its range; `first_receiver` numbers the receivers in the message.
void check_coefficients(const std::string& path, const float* coeffs, std::size_t n,
                        const TransferLayout& layout, std::size_t first_receiver);
// options.extra_metadata_json as a JSON object (Error(invalid_argument) otherwise).
Json parse_extra(const WriteOptions& options);
// The same for any JSON text (WriteOptions::kept_metadata_json); empty text is {}.
Json parse_extra(const std::string& text);
// The sections of the table for `mesh` and `rows` transfer rows of `info`'s layout, with their
// CRCs computed; the transfer's data is `coeffs` (null for a streamed file: no CRC yet); the
// optional transfer sections (the direct part) come from `transfer` (null: none).
std::vector<SectionOut> plan_sections(const Mesh& mesh, const TransferInfo& info, std::size_t rows,
                                      const float* coeffs, const TransferSet* transfer = nullptr);
// Places the sections (their offsets) and renders the metadata. reserve = 0: the canonical
// layout right after the metadata; reserve > 0: the metadata is exactly `reserve` bytes (padded
// with spaces; Error(invalid_argument) if it would be longer), so the offsets do not depend on
// what the metadata says.
std::string lay_out(const std::string& path, const Mesh& mesh, const TransferInfo& info,
                    std::size_t rows, const WriteOptions& options, const Json& extra,
                    std::vector<SectionOut>& sections, std::size_t reserve,
                    const CpcaCode* cpca = nullptr, const ProbeGrid* probes = nullptr);
// The format version of a file of these sections: the newest `since` among them, at least
// kShprtFormatVersion (a file with a CPCA code's sections is version 3). The header and the
// metadata's format_version both say it; the metadata writes the fields that version holds.
std::uint32_t file_version(const std::vector<SectionOut>& sections);
// The 48 header bytes for metadata `text` of a file of format `version`.
void encode_header(const std::string& text, unsigned char out[kShprtHeaderSize],
                   std::uint32_t version);
// Writes the header, the metadata and every section with data (padding between them).
void write_file_body(AtomicFile& file, const std::string& text,
                     const std::vector<SectionOut>& sections);

}  // namespace shprt::detail
