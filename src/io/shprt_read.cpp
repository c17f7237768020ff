// Reader of the .shprt file (layout: docs/file_format.md; sections: the table of
// shprt_sections.hpp, metadata: the field table of shprt_metadata.hpp, both shared with the
// writer; versions 1 to 3). Nothing read from the file is trusted before it is checked: the header
// and metadata against their CRCs, every section's offset and length against the file size, the
// sizes against V, T, K and channels; only then are arrays allocated (so a corrupt length cannot
// ask for more memory than the file holds) and read, each against its CRC-32.
#include "io/fuzzing.hpp"
#include "io/shprt_fields.hpp"
#include "io/shprt_metadata.hpp"
#include "io/shprt_sections.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/half.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_format.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/transfer/cpca.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace shprt {

namespace io_fuzzing {
namespace {
std::atomic<bool> g_checksums_advisory{false};
}
void set_checksums_advisory(bool advisory) noexcept { g_checksums_advisory.store(advisory); }
bool checksums_advisory() noexcept { return g_checksums_advisory.load(std::memory_order_relaxed); }
}  // namespace io_fuzzing

namespace {

using Json = nlohmann::json;
using detail::corrupt;
using detail::Fields;
using detail::parse_metadata;

constexpr std::size_t kMaxSections = 16;
constexpr std::size_t kReadChunk = std::size_t(1) << 20;

class InputFile {
public:
    explicit InputFile(const std::string& path) : m_path(path) {
        // O_NONBLOCK: opening a FIFO must not hang; it is refused below as not a regular file.
        m_fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
        SHPRT_CHECK(m_fd >= 0, io, "cannot open {}: {}", path, std::strerror(errno));
        struct stat st {};
        SHPRT_CHECK(::fstat(m_fd, &st) == 0, io, "cannot stat {}: {}", path, std::strerror(errno));
        SHPRT_CHECK(S_ISREG(st.st_mode), io, "{}: not a regular file", path);
        m_size = static_cast<std::uint64_t>(st.st_size);
    }
    ~InputFile() { ::close(m_fd); }
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;

    std::uint64_t size() const { return m_size; }

    // Reads exactly `size` bytes at `offset` (the caller has checked them against size()).
    void read(std::uint64_t offset, void* data, std::size_t size, const char* what) {
        auto* p = static_cast<unsigned char*>(data);
        while (size > 0) {
            const ssize_t n = ::pread(m_fd, p, size, static_cast<off_t>(offset));
            if (n < 0 && errno == EINTR) continue;
            SHPRT_CHECK(n >= 0, io, "cannot read {}: {}", m_path, std::strerror(errno));
            if (n == 0) corrupt(m_path, "truncated while reading {} (the file shrank)", what);
            p += n;
            offset += static_cast<std::uint64_t>(n);
            size -= static_cast<std::size_t>(n);
        }
    }

private:
    std::string m_path;
    int m_fd = -1;
    std::uint64_t m_size = 0;
};

// ---- sections --------------------------------------------------------------------------------

struct SectionSpec {
    const detail::SectionRule* rule;
    const char* name;
    std::string dtype;
    std::uint64_t rows, cols;
    std::uint64_t element_size;
    // Filled from the table:
    std::uint64_t offset = 0, length = 0;
    std::uint32_t crc = 0;
};

std::uint64_t checked_mul(const std::string& path, std::uint64_t a, std::uint64_t b,
                          const char* what) {
    std::uint64_t r = 0;
    if (__builtin_mul_overflow(a, b, &r)) corrupt(path, "{} overflows 64 bits", what);
    return r;
}

void check_section_entry(const std::string& path, const Json& entry, SectionSpec& spec,
                         std::uint64_t file_size) {
    if (!entry.is_object()) corrupt(path, "metadata: section entries must be objects");
    const Fields f{path, entry, fmt::format("metadata.sections['{}']", spec.name)};
    const std::string name = f.string("name");
    if (name != spec.name)
        corrupt(path, "metadata: section '{}' where '{}' was expected", name, spec.name);
    spec.offset = f.u64("offset");
    spec.length = f.u64("length");
    spec.crc = static_cast<std::uint32_t>(f.u64("crc32", 0, 0xffffffffu));
    // Against the file size first: nothing else is believed until the bytes exist.
    if (spec.offset > file_size || spec.length > file_size - spec.offset)
        corrupt(path, "truncated: section '{}' needs {} bytes at offset {} but the file has {}",
                spec.name, spec.length, spec.offset, file_size);
    const std::string dtype = f.string("dtype");
    if (dtype != spec.dtype)
        corrupt(path, "section '{}' has dtype '{}', expected '{}'", spec.name, dtype, spec.dtype);
    const Json& shape = f.get("shape");
    if (!shape.is_array() || shape.size() != 2 || !shape[0].is_number_unsigned() ||
        !shape[1].is_number_unsigned() || shape[0].get<std::uint64_t>() != spec.rows ||
        shape[1].get<std::uint64_t>() != spec.cols)
        corrupt(path, "section '{}' has shape {}, expected [{}, {}]", spec.name, shape.dump(),
                spec.rows, spec.cols);
    const std::uint64_t count = checked_mul(path, spec.rows, spec.cols, "section element count");
    if (f.u64("count") != count)
        corrupt(path, "section '{}' has count {}, expected {}", spec.name, f.u64("count"), count);
    const std::uint64_t bytes = checked_mul(path, count, spec.element_size, "section byte length");
    if (spec.length != bytes)
        corrupt(path, "section '{}' has length {} but {} {} elements take {} bytes", spec.name,
                spec.length, count, spec.dtype, bytes);
}

class Reader {
public:
    explicit Reader(const std::string& path) : m_path(path), m_file(path) {}

    // allow_part: read a part of a sharded bake too (else refuse it).
    ShprtFile read(bool allow_part);

private:
    using Counts = detail::MetaCounts;
    // The steps of read(), in order (each ends the read with one corrupt() line on failure;
    // the metadata's fields between the text and the section table: detail::read_metadata).
    ShprtHeader read_header();
    std::string read_metadata_text(const ShprtHeader& h);
    std::vector<SectionSpec> read_section_table(const Fields& m, const ShprtHeader& h,
                                                const Counts& c);
    void read_arrays(const std::vector<SectionSpec>& specs, const ShprtHeader& h, ShprtFile& out);
    void check_content(const Counts& c, ShprtFile& out);

    void check_zero_gap(std::uint64_t from, std::uint64_t to, const char* before);
    // Reads a section's bytes into `dst` (spec.length bytes), checking its CRC.
    void read_section(const SectionSpec& spec, void* dst);
    // Reads a section's bytes through `sink(const unsigned char*, size_t)` in chunks, checking
    // its CRC at the end.
    template <class Sink>
    void read_section_chunks(const SectionSpec& spec, Sink&& sink);
    void check_crc(const SectionSpec& spec, std::uint32_t crc) const;

    std::string m_path;
    InputFile m_file;
    std::uint64_t m_size = 0;  // of the file
};

void Reader::check_zero_gap(std::uint64_t from, std::uint64_t to, const char* before) {
    unsigned char gap[kShprtAlignment];
    const std::size_t n = static_cast<std::size_t>(to - from);
    m_file.read(from, gap, n, "padding");
    for (std::size_t i = 0; i < n; ++i)
        if (gap[i] != 0)
            corrupt(m_path, "corrupt: non-zero padding byte at offset {} (before {})", from + i,
                    before);
}

void Reader::check_crc(const SectionSpec& spec, std::uint32_t crc) const {
    if (crc != spec.crc && !io_fuzzing::checksums_advisory())
        corrupt(m_path, "corrupt: section '{}' fails its checksum (CRC-32 {:08x}, recorded {:08x})",
                spec.name, crc, spec.crc);
}

void Reader::read_section(const SectionSpec& spec, void* dst) {
    auto* p = static_cast<unsigned char*>(dst);
    std::uint32_t crc = 0;
    for (std::uint64_t done = 0; done < spec.length;) {  // chunks keep the CRC in cache
        const auto n =
            static_cast<std::size_t>(std::min<std::uint64_t>(kReadChunk, spec.length - done));
        m_file.read(spec.offset + done, p + done, n, spec.name);
        crc = crc32(p + done, n, crc);
        done += n;
    }
    check_crc(spec, crc);
}

template <class Sink>
void Reader::read_section_chunks(const SectionSpec& spec, Sink&& sink) {
    std::vector<unsigned char> buffer(
        static_cast<std::size_t>(std::min<std::uint64_t>(spec.length, kReadChunk)));
    std::uint32_t crc = 0;
    for (std::uint64_t done = 0; done < spec.length;) {
        const std::size_t n =
            static_cast<std::size_t>(std::min<std::uint64_t>(kReadChunk, spec.length - done));
        m_file.read(spec.offset + done, buffer.data(), n, spec.name);
        crc = crc32(buffer.data(), n, crc);
        sink(buffer.data(), n);
        done += n;
    }
    check_crc(spec, crc);
}

ShprtHeader Reader::read_header() {
    const std::uint64_t size = m_size;
    unsigned char head[kShprtHeaderSize] = {};
    const std::size_t got =
        static_cast<std::size_t>(std::min<std::uint64_t>(size, kShprtHeaderSize));
    m_file.read(0, head, got, "the header");
    const std::size_t magic_bytes = std::min(got, sizeof kShprtMagic);
    if (std::memcmp(head, kShprtMagic, magic_bytes) != 0) {
        if (std::memcmp(head + 1, kShprtMagic + 1, 5) == 0)
            corrupt(m_path,
                    "damaged magic: its line-ending or high-bit bytes were changed (copied "
                    "in text mode?)");
        corrupt(m_path, "not a .shprt file (wrong magic bytes)");
    }
    if (got < kShprtHeaderSize)
        corrupt(m_path, "truncated: the header needs {} bytes but the file has {}",
                kShprtHeaderSize, size);
    const ShprtHeader h = decode_shprt_header(head);
    if (h.version == 0) corrupt(m_path, "invalid format version 0");
    if (h.version > kShprtNewestReadVersion)
        corrupt(m_path, "format version {} is newer than this shprt reads ({}); use a newer shprt",
                h.version, kShprtNewestReadVersion);
    if (h.endian_marker == 0x04030201u) corrupt(m_path, "big-endian file: not supported");
    if (h.endian_marker != kShprtEndianMarker)
        corrupt(m_path, "bad endianness marker {:#010x}", h.endian_marker);
    if (h.header_size != kShprtHeaderSize)
        corrupt(m_path, "header size {} (expected {})", h.header_size, kShprtHeaderSize);
    const std::uint32_t header_crc = crc32(head, 44);
    if (header_crc != h.header_crc32 && !io_fuzzing::checksums_advisory())
        corrupt(m_path, "corrupt: the header fails its checksum (CRC-32 {:08x}, recorded {:08x})",
                header_crc, h.header_crc32);
    if (h.metadata_offset != kShprtHeaderSize)
        corrupt(m_path, "metadata offset {} (expected {})", h.metadata_offset, kShprtHeaderSize);
    if (h.metadata_length > size - kShprtHeaderSize)
        corrupt(m_path, "truncated: the metadata needs {} bytes at offset {} but the file has {}",
                h.metadata_length, h.metadata_offset, size);
    if (h.metadata_length > kShprtMaxMetadataBytes)
        corrupt(m_path, "metadata length {} exceeds the limit of {} bytes", h.metadata_length,
                kShprtMaxMetadataBytes);

    return h;
}

// The metadata's text (its checksum checked) and its top-level checks.
std::string Reader::read_metadata_text(const ShprtHeader& h) {
    std::string text(static_cast<std::size_t>(h.metadata_length), '\0');
    m_file.read(h.metadata_offset, text.data(), text.size(), "the metadata");
    const std::uint32_t meta_crc = crc32(text.data(), text.size());
    if (meta_crc != h.metadata_crc32 && !io_fuzzing::checksums_advisory())
        corrupt(m_path, "corrupt: the metadata fails its checksum (CRC-32 {:08x}, recorded {:08x})",
                meta_crc, h.metadata_crc32);
    return text;
}

// The section table matched to the rules (every required section, optional ones, nothing else)
// and the canonical layout: each section at the first aligned offset after the previous one, the
// file ending with the last.
std::vector<SectionSpec> Reader::read_section_table(const Fields& m, const ShprtHeader& h,
                                                    const Counts& c) {
    const TransferLayout& layout = c.layout;
    const std::uint64_t size = m_size;
    const Json& table = m.get("sections");
    if (!table.is_array() || table.size() > kMaxSections)
        corrupt(m_path, "metadata: 'sections' must be an array of at most {} entries",
                kMaxSections);
    // Match the listed sections to the table's rules in order: every required one present,
    // optional ones present or absent, nothing else.
    std::vector<SectionSpec> specs;
    std::size_t listed = 0;
    for (const detail::SectionRule& rule : detail::section_rules()) {
        // The metadata's counts say which rows apply (a CPCA file: every cpca_* section and no
        // "transfer"; probes: their matrices or their code's arrays).
        if (!rule.applies(c)) continue;
        const bool required = rule.required;
        const bool present = listed < table.size() && table[listed].is_object() &&
                             table[listed].contains("name") &&
                             table[listed]["name"] == std::string(rule.name);
        if (!present && !required) continue;
        if (!present && listed >= table.size())
            corrupt(m_path, "metadata: sections: required section '{}' is missing", rule.name);
        specs.push_back({&rule, rule.name, rule.dtype(layout), rule.row_count(c), rule.col_count(c),
                         rule.element_size(layout)});
        check_section_entry(m_path, table[listed], specs.back(), size);
        ++listed;
    }
    if (listed < table.size()) {
        const Json& extra = table[listed];
        corrupt(m_path, "metadata: unexpected section {} after '{}'",
                extra.is_object() && extra.contains("name") ? extra["name"].dump()
                                                            : std::string("entry"),
                specs.empty() ? "the metadata" : specs.back().name);
    }

    // Canonical layout: each section at the first aligned offset after the previous one, the
    // file ending with the last, so every byte is under a CRC or known to be zero padding.
    std::uint64_t end = kShprtHeaderSize + h.metadata_length;
    for (const SectionSpec& s : specs) {
        if (s.offset != shprt_align(end))
            corrupt(m_path, "section '{}' at offset {}, expected {}", s.name, s.offset,
                    shprt_align(end));
        end = s.offset + s.length;
    }
    if (size != end) corrupt(m_path, "{} unexpected bytes after the last section", size - end);

    return specs;
}

// The sections' arrays into the mesh and the transfer (all lengths proven to lie in the file).
void Reader::read_arrays(const std::vector<SectionSpec>& specs, const ShprtHeader& h,
                         ShprtFile& out) {
    TransferSet& t = out.transfer;
    Mesh& mesh = out.mesh;
    std::uint64_t end = kShprtHeaderSize + h.metadata_length;
    for (const SectionSpec& s : specs) {
        check_zero_gap(end, s.offset, s.name);
        end = s.offset + s.length;
        void* dst = s.rule->resize(mesh, t, s.rows * s.cols);
        if (s.element_size != 2) {
            read_section(s, dst);
        } else {  // float16 transfer, widened to float32
            auto* f = static_cast<float*>(dst);
            read_section_chunks(s, [&f](const unsigned char* src, std::size_t n) {
                for (std::size_t i = 0; i + 1 < n; i += 2)  // chunks hold whole elements
                    *f++ = half_to_float(static_cast<std::uint16_t>(src[i] | (src[i + 1] << 8)));
            });
        }
    }
}

// What the arrays hold: indices in range, finite values, albedo, normals, texels, BRDF indices,
// parents, and the scene's hash.
void Reader::check_content(const Counts& c, ShprtFile& out) {
    Mesh& mesh = out.mesh;
    TransferSet& t = out.transfer;
    const TransferLayout& layout = t.layout;
    const std::uint64_t V = c.vertices, total = c.total, clusters = c.clusters;
    const bool texel = is_texel(layout);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        for (std::uint32_t index : mesh.triangles[i])
            if (index >= V)
                corrupt(m_path, "triangle {} uses vertex {} but the file has {} vertices", i, index,
                        V);
    const auto check_finite = [&](const float* p, std::size_t n, const char* what) {
        // A branch-free max over the exponent bits first (it vectorises), the search on failure.
        std::uint32_t worst = 0;
        for (std::size_t i = 0; i < n; ++i)
            worst = std::max(worst, float_as_u32(p[i]) & 0x7f800000u);
        if (worst != 0x7f800000u) return;
        for (std::size_t i = 0; i < n; ++i)
            if (!std::isfinite(p[i])) corrupt(m_path, "{}: value {} is not finite", what, i);
    };
    if (clusters > 0) {
        check_finite(t.cpca.weights.data(), t.cpca.weights.size(), "cpca_weights");
        check_finite(t.cpca.means.data(), t.cpca.means.size(), "cpca_means");
        check_finite(t.cpca.basis.data(), t.cpca.basis.size(), "cpca_basis");
        try {
            reconstruct_cpca(t.cpca, layout.floats_per_receiver(), t.coeffs);
        } catch (const Error& e) {
            corrupt(m_path, "{}", e.what());
        }
    }
    static_assert(sizeof(Vec3f) == 3 * sizeof(float));
    check_finite(reinterpret_cast<const float*>(mesh.positions.data()), 3 * V, "positions");
    check_finite(reinterpret_cast<const float*>(mesh.normals.data()), 3 * V, "normals");
    check_finite(reinterpret_cast<const float*>(mesh.albedo.data()), 3 * V, "albedo");
    // What the writer refuses (a scene's albedo is clamped into [0, 1] when it is loaded; its
    // normals are never zero).
    if (const auto v = bad_albedo(mesh))
        corrupt(m_path, "albedo: vertex {} has ({}, {}, {}), outside [0, 1]", *v, mesh.albedo[*v].x,
                mesh.albedo[*v].y, mesh.albedo[*v].z);
    if (const auto v = zero_normal(mesh)) corrupt(m_path, "normals: vertex {} is zero", *v);
    check_finite(t.coeffs.data(), t.coeffs.size(), "transfer");
    check_finite(t.direct.data(), t.direct.size(), "transfer_direct");
    if (c.probes > 0) {
        std::uint64_t valid = 0;
        for (std::size_t i = 0; i < t.probes.valid.size(); ++i) {
            if (t.probes.valid[i] > 1)
                corrupt(m_path, "probe_valid: probe {} is {} (0 or 1)", i, t.probes.valid[i]);
            valid += t.probes.valid[i];
        }
        if (valid != c.probes_valid)
            corrupt(m_path, "probe_valid: {} valid probes, metadata.probes.valid says {}", valid,
                    c.probes_valid);
        if (c.probe_clusters > 0) {
            ProbeGrid& g = t.probes;
            check_finite(g.cpca.weights.data(), g.cpca.weights.size(), "probe_cpca_weights");
            check_finite(g.cpca.means.data(), g.cpca.means.size(), "probe_cpca_means");
            check_finite(g.cpca.basis.data(), g.cpca.basis.size(), "probe_cpca_basis");
            try {
                reconstruct_probes(g);
            } catch (const Error& e) {
                corrupt(m_path, "{}", e.what());
            }
        }
        check_finite(t.probes.matrices.data(), t.probes.matrices.size(), "probe_matrices");
    }
    // Texel domain: the UVs and every receiver's texel, in order and inside the image; and
    // neither for vertex transfer.
    if (texel != !t.texels.texel.empty() || texel != !mesh.uvs.empty())
        corrupt(m_path, "a {} transfer {} sections 'uvs' and 'texel_index'",
                to_string(layout.domain), texel ? "needs" : "cannot have");
    if (texel) {
        if (t.texels.texel.size() != total)
            corrupt(m_path, "section 'texel_index' lists {} texels, receivers.total is {}",
                    t.texels.texel.size(), total);
        const std::uint64_t image = std::uint64_t(t.texels.width) * std::uint64_t(t.texels.height);
        for (std::size_t i = 0; i < t.texels.texel.size(); ++i)
            if (t.texels.texel[i] >= image || (i > 0 && t.texels.texel[i] <= t.texels.texel[i - 1]))
                corrupt(m_path, "texel_index {} ({}) is out of order or outside the {}x{} image", i,
                        t.texels.texel[i], t.texels.width, t.texels.height);
        check_finite(reinterpret_cast<const float*>(mesh.uvs.data()), 2 * V, "uvs");
    }
    if (mesh.brdf_index.empty() != mesh.brdfs.empty())
        corrupt(m_path, "section 'brdf_index' and metadata scene.brdfs come together");
    if (const auto v = bad_brdf_index(mesh))
        corrupt(m_path, "brdf_index: vertex {} has BRDF {} but scene.brdfs lists {}", *v,
                mesh.brdf_index[*v], mesh.brdfs.size());
    for (std::size_t i = 0; i < mesh.parents.size(); ++i)
        for (std::uint32_t p : mesh.parents[i])
            if (p != Mesh::kNoParent && p >= i)
                corrupt(m_path, "vertex_parents: vertex {} has parent {} (parents come first)", i,
                        p);
    const std::string hash = format_mesh_hash(mesh_hash(mesh));
    if (hash != c.recorded_hash)
        corrupt(m_path, "scene hash {} differs from the recorded {}", hash, c.recorded_hash);
}

ShprtFile Reader::read(bool allow_part) {
    m_size = m_file.size();
    const ShprtHeader h = read_header();
    std::string text = read_metadata_text(h);
    const Json meta = parse_metadata(m_path, text);
    const Fields m{m_path, meta, "metadata"};
    ShprtFile out;
    Counts counts;
    detail::MetaTarget target{m_path, h.version, m_size, allow_part, out, counts};
    detail::read_metadata(m, target);
    counts.layout = out.transfer.layout;
    const std::vector<SectionSpec> specs = read_section_table(m, h, counts);
    read_arrays(specs, h, out);
    check_content(counts, out);
    out.metadata_json = std::move(text);
    return out;
}

}  // namespace

ShprtFile read_shprt(const std::string& path) { return Reader(path).read(false); }

ShprtFile read_shprt_part(const std::string& path) { return Reader(path).read(true); }

}  // namespace shprt
