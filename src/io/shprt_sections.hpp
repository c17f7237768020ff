// The one section table of the .shprt file, shared by the reader and the writer: for every
// section, in file order, its name, element type, shape rule, whether it is required, and where
// its data lives in memory. A new section is one line in kSections (shprt_sections.cpp).
//
// Rules (docs/file_format.md): sections appear in table order; a section applies to a file when
// its row's `applies` says so from the file's counts (the transfer's rows and a CPCA code stand
// for each other, as do the probes' matrices and their code); a required section is present
// whenever it applies; an optional one is written when its array is non-empty and may be absent.
// A file's format version is the newest `since` of the sections it holds (file_version). Rows count
// vertices, triangles or receivers (the transfer's rows: vertices for the vertex domain); columns
// are fixed or, for the transfer, layout.floats_per_receiver(). The transfer's element type is
// its layout's encoding (float32 or float16).
#pragma once

#include "shprt/io/shprt_file.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace shprt::detail {

enum class SectionType { f32, u32, u8, transfer };  // transfer: the layout's encoding
// clusters and basis_rows (clusters × vectors): the CPCA code's arrays (TransferSet::cpca);
// probes: the transfer probes' (TransferSet::probes); valid_probes, probe_clusters and
// probe_basis_rows: the probes' CPCA code's (ProbeGrid::cpca: one row per valid probe).
enum class SectionRows {
    vertices,
    triangles,
    receivers,
    clusters,
    basis_rows,
    probes,
    valid_probes,
    probe_clusters,
    probe_basis_rows
};

// What the sizes of a file's sections follow from (all from the metadata).
struct SectionCounts {
    std::uint64_t vertices = 0, triangles = 0, receivers = 0;
    TransferLayout layout;
    std::uint64_t clusters = 0, vectors = 0;     // a CPCA code's (0: none)
    std::uint64_t probes = 0, probe_floats = 0;  // the probe grid's probes, channels·K² (0: none)
    std::uint64_t probes_valid = 0;              // its valid probes
    std::uint64_t probe_clusters = 0, probe_vectors = 0;  // its CPCA code's (0: none)
};

// The counts of `rows` transfer rows of `layout` on `mesh`, with the optional parts of `parts`
// (its CPCA code and probes; their own sizes), as the writer lays them out.
SectionCounts section_counts(const Mesh& mesh, const TransferLayout& layout, std::uint64_t rows,
                             const TransferSet& parts);

struct SectionRule {
    const char* name;
    SectionType type;
    SectionRows rows;
    std::uint64_t cols;  // 0 = layout.floats_per_receiver(), kPerChannel = floats_per_channel(),
                         // kVectors = the CPCA code's vectors, kProbeFloats = channels·K² of
                         // the probes, kProbeVectors = the probes' CPCA code's vectors
    bool required;       // present whenever it applies
    // Whether the section belongs in a file of these counts (the reader's, from the metadata; the
    // writer's, from the parts it writes): one predicate per row, so neither walk asks which
    // part a row is.
    bool (*applies)(const SectionCounts& counts);
    std::uint32_t since;  // the format version whose files first hold it
    // The array in memory: its data and scalar element count (rows·cols when present; an empty
    // optional array means "absent"); `resize` sizes it for reading and returns its data.
    const void* (*data)(const Mesh& mesh, const TransferSet& transfer);
    std::uint64_t (*count)(const Mesh& mesh, const TransferSet& transfer);
    void* (*resize)(Mesh& mesh, TransferSet& transfer, std::uint64_t count);

    std::string dtype(const TransferLayout& layout) const;
    std::uint64_t element_size(const TransferLayout& layout) const;
    std::uint64_t row_count(const SectionCounts& counts) const;
    static constexpr std::uint64_t kPerChannel = ~std::uint64_t(0);
    static constexpr std::uint64_t kVectors = ~std::uint64_t(1);
    static constexpr std::uint64_t kProbeFloats = ~std::uint64_t(2);
    static constexpr std::uint64_t kProbeVectors = ~std::uint64_t(3);
    std::uint64_t col_count(const SectionCounts& counts) const {
        if (cols == kPerChannel) return counts.layout.floats_per_channel();
        if (cols == kVectors) return counts.vectors;
        if (cols == kProbeFloats) return counts.probe_floats;
        if (cols == kProbeVectors) return counts.probe_vectors;
        return cols != 0 ? cols : std::uint64_t(counts.layout.floats_per_receiver());
    }
    // The transfer itself (the streamed section, always last), not the optional direct part.
    bool is_transfer() const {
        return type == SectionType::transfer && cols == 0 && rows == SectionRows::receivers;
    }
};

// The table, in file order.
std::span<const SectionRule> section_rules();

}  // namespace shprt::detail
