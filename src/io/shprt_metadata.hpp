// The one metadata field table of the .shprt file, shared by the writer (shprt_write.cpp), the
// reader (shprt_read.cpp) and `shprt info` (shprt_summary.cpp), as the sections share theirs
// (shprt_sections.hpp): for every field, in the metadata's key order, its JSON key (nested keys
// dotted: "interreflection.bounces"), its type, the format version it came with, whether a file
// must have it, how it is set from the written set and read back into it, and how `shprt info`
// summarises it. A new field is one row in kFields (shprt_metadata.cpp).
//
// Rules (docs/file_format.md): the writer walks the rows in order, so the rows' order is the
// metadata's key order (the writer's Json is ordered); a row whose `written` says no, or whose
// object is not written, is left out. The reader walks them pass by pass (a field read in a later
// pass depends on one read before it: the receivers on the texel image, the CPCA code's bounds on
// the receivers), in order within a pass; a field of a newer version than the file's is not read;
// an optional field (or one whose parent lacks `with`) that is absent is not read; a required one
// that is absent is the reader's one-line "missing field" error. The summary walks the rows with a
// summary in `summary_rank` order. Private to io/.
#pragma once

#include "io/shprt_fields.hpp"
#include "io/shprt_write_internal.hpp"
#include "shprt/io/shprt_file.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace shprt::detail {

// A field's JSON type: `extra` marks where the caller's metadata is merged (WriteOptions's kept
// and extra metadata: keys the caller owns; the writer refuses one that would replace its own).
enum class FieldType { text, whole, number, boolean, list, object, extra };

// What the writer's fields come from.
struct MetaSource {
    const Mesh& mesh;
    const TransferInfo& info;
    std::size_t rows;
    const WriteOptions& options;
    const Json& extra;  // options.extra_metadata_json, parsed
    const std::vector<SectionOut>& sections;
    const CpcaCode* cpca;     // the transfer's code (read only in a file whose sections hold it)
    const ProbeGrid* probes;  // null or empty: none
};

// What the metadata says of the sizes: the sections' (SectionCounts; its layout is the
// transfer's, set once the fields are read) and, for the content checks, the domain's receivers
// and the recorded scene hash.
struct MetaCounts : SectionCounts {
    std::uint64_t total = 0;  // receivers of the whole domain (vertices or texels); `receivers`
                              // are those stored (all, or a part's)
    std::string recorded_hash;
};

// Where the reader's fields go.
struct MetaTarget {
    const std::string& path;
    std::uint32_t version;  // the header's
    std::uint64_t file_size;
    bool allow_part;  // a part of a sharded bake may be read (else it is refused)
    ShprtFile& out;
    MetaCounts& counts;
};

// What a summary line is made from, and where it goes.
struct SummaryLines {
    const ShprtFile& file;
    const nlohmann::ordered_json& meta;  // as stored (any JSON: the summary tolerates anything)
    std::string& out;
    void line(const char* label, const std::string& value) const;
};

struct FieldRule {
    const char* key;  // dotted path from the metadata's root
    FieldType type;
    std::uint32_t since;  // the format version whose files first hold it
    bool required;        // in every file of version >= since whose parent object is there
    int pass;             // the reader's pass (1, 2 or 3)
    const char* with;     // null, or: read only when the parent also has this key
    bool (*written)(const MetaSource& s);  // null: whenever its parent is written
    // The value written; null for an object its rows fill (or an `extra` merge point).
    Json (*value)(const MetaSource& s);
    // Reads the field `leaf` from its parent object into the target, with its checks; null:
    // the reader does not read it (it is informative, or read with another field).
    void (*read)(const Fields& parent, const char* leaf, MetaTarget& t);
    int summary_rank;  // the order of `shprt info`'s lines; 0: not summarised
    void (*summarise)(const SummaryLines& s);
};

// The key of the row where the caller's kept metadata is merged (an `extra` row).
inline constexpr const char* kKeptMetadata = "(kept metadata)";

// The table, in the metadata's key order (shprt_metadata.cpp).
std::span<const FieldRule> field_rules();

// The metadata of a file (every row's value, the merge points' metadata, the section table).
Json write_metadata(const MetaSource& source);
// Reads every field into `target`, pass by pass; one corrupt() line on the first problem
// (shprt_metadata_walk.cpp, as write_metadata).
void read_metadata(const Fields& metadata, MetaTarget& target);
// `shprt info`'s lines, in summary order (shprt_metadata_summary.cpp).
std::string summarise_metadata(const ShprtFile& file);

// The rows' summaries that are more than a line of the table (shprt_metadata_summary.cpp).
void summarise_interreflection(const SummaryLines& s);
void summarise_stats(const SummaryLines& s);
void summarise_basis(const SummaryLines& s);
void summarise_target_error(const SummaryLines& s);
void summarise_file_size(const SummaryLines& s);

}  // namespace shprt::detail
