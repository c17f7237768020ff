// The streaming .shprt writer (shprt_stream.hpp): lay out first, rows through a sink as a bake
// finishes them, metadata last.
#include "shprt/io/shprt_stream.hpp"

#include "io/shprt_write_internal.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/half.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <vector>

namespace shprt {
namespace {

// Room the metadata keeps for what is known only after the bake (the transfer's CRC and the
// bake's statistics): far more than their longest rendering.
constexpr std::size_t kMetadataSlack = 4096;

}  // namespace

namespace detail {

// Rows into the transfer section of the temporary file: converted to the layout's encoding,
// checked, written with pwrite; each chunk's CRC-32 kept for the section's CRC. Not in the
// anonymous namespace: ShprtStreamWriter::State, declared in the header, holds one (gcc's
// -Wsubobject-linkage in a unity build, where this file is not the main file).
class SectionSink final : public TransferSink {
public:
    SectionSink(std::string path, int fd, std::uint64_t offset, const TransferLayout& layout,
                std::size_t first, std::size_t count)
        : m_path(std::move(path)),
          m_fd(fd),
          m_offset(offset),
          m_layout(layout),
          m_first(first),
          m_count(count) {}

    void begin(const TransferLayout& layout, std::size_t first, std::size_t count) override {
        TransferLayout stored = layout;  // the rows come as float32; the file chooses its encoding
        stored.encoding = m_layout.encoding;
        SHPRT_CHECK(stored == m_layout && first == m_first && count == m_count, invalid_argument,
                    "{}: the bake's rows (K = {}, receivers [{}, {})) are not the ones the file "
                    "was laid out for (K = {}, [{}, {}))",
                    m_path, layout.K, first, first + count, m_layout.K, m_first, m_first + m_count);
    }

    void write(std::size_t first, std::size_t count, const float* rows) override {
        SHPRT_CHECK(rows != nullptr && first >= m_first && first + count <= m_first + m_count,
                    invalid_argument, "{}: rows [{}, {}) outside [{}, {})", m_path, first,
                    first + count, m_first, m_first + m_count);
        const std::size_t n = m_layout.floats(count);
        detail::check_coefficients(m_path, rows, n, m_layout, first);
        const std::uint64_t element = bytes_per_value(m_layout.encoding);
        const std::uint64_t at = m_offset + m_layout.floats(first - m_first) * element;
        std::uint32_t crc = 0;
        if (element == 4) {
            crc = crc32(rows, n * sizeof(float));
            pwrite_all(m_fd, rows, n * sizeof(float), at, m_path);
        } else {
            std::vector<std::uint16_t> half(n);
            for (std::size_t i = 0; i < n; ++i) half[i] = float_to_half(rows[i]);
            crc = crc32(half.data(), n * sizeof(std::uint16_t));
            pwrite_all(m_fd, half.data(), n * sizeof(std::uint16_t), at, m_path);
        }
        const std::lock_guard<std::mutex> lock(m_mutex);
        m_chunks.push_back({first, n * element, crc});
    }

    // An error-bounded bake's estimates go to the writer's arrays (`estimates`, laid out as
    // sections before the bake and written at commit; 8 bytes a receiver in memory).
    void keep_estimates(TransferSet* estimates) { m_estimates = estimates; }
    void write_estimates(std::size_t first, std::size_t count, const std::uint32_t* samples,
                         const float* errors) override {
        SHPRT_CHECK(
            m_estimates != nullptr && first >= m_first && first + count <= m_first + m_count,
            invalid_argument, "{}: estimates for receivers [{}, {}) the file has no room for",
            m_path, first, first + count);
        const std::size_t at = first - m_first;
        std::copy(samples, samples + count,
                  m_estimates->receiver_samples.begin() + std::ptrdiff_t(at));
        std::copy(errors, errors + count, m_estimates->receiver_error.begin() + std::ptrdiff_t(at));
    }

    // The CRC-32 of the whole section, from its chunks' (zlib's crc32_combine); every receiver
    // must have been written exactly once.
    std::uint32_t section_crc() {
        const std::lock_guard<std::mutex> lock(m_mutex);
        std::sort(m_chunks.begin(), m_chunks.end(),
                  [](const Chunk& a, const Chunk& b) { return a.first < b.first; });
        std::uint32_t crc = 0;
        std::size_t next = m_first;
        const std::uint64_t element = bytes_per_value(m_layout.encoding);
        for (const Chunk& c : m_chunks) {
            SHPRT_CHECK(c.first == next, invalid_argument,
                        "{}: transfer rows from receiver {} were {} before the file was finished",
                        m_path, std::min(c.first, next),
                        c.first > next ? "never written" : "written twice");
            crc = static_cast<std::uint32_t>(
                ::crc32_combine(crc, c.crc, static_cast<z_off_t>(c.bytes)));
            next += c.bytes / element / m_layout.floats_per_receiver();
        }
        SHPRT_CHECK(next == m_first + m_count, invalid_argument,
                    "{}: transfer rows from receiver {} were never written", m_path, next);
        return crc;
    }

private:
    struct Chunk {
        std::size_t first;
        std::uint64_t bytes;
        std::uint32_t crc;
    };
    std::string m_path;
    int m_fd;
    std::uint64_t m_offset;
    TransferLayout m_layout;
    std::size_t m_first, m_count;
    std::mutex m_mutex;
    std::vector<Chunk> m_chunks;
    TransferSet* m_estimates = nullptr;
};

}  // namespace detail

struct ShprtStreamWriter::State {
    std::string path;
    const Mesh& mesh;
    TransferInfo info;
    std::size_t first, count;
    WriteOptions options;
    detail::Json extra;
    std::size_t reserve = 0;
    std::vector<detail::SectionOut> sections;
    AtomicFile file;
    std::unique_ptr<detail::SectionSink> sink;
    TransferSet estimates;  // an error-bounded bake's per-receiver sections, filled by the sink

    State(const std::string& p, const Mesh& m, const TransferInfo& i, std::size_t f, std::size_t c,
          WriteOptions o)
        : path(p), mesh(m), info(i), first(f), count(c), options(std::move(o)), file(p) {}
};

ShprtStreamWriter::ShprtStreamWriter(const std::string& path, const Mesh& mesh,
                                     const TransferInfo& info, std::size_t first, std::size_t count,
                                     WriteOptions options) {
    // The checks write_shprt makes of everything but the coefficients (checked per chunk).
    options.receiver_first = first;
    try {
        SHPRT_CHECK(!is_texel(info.layout), unsupported,
                    "streaming a {} transfer: only vertex transfer streams",
                    to_string(info.layout.domain));
        TransferSet::check_range(mesh, info.layout, first, count, mesh.vertex_count());
    } catch (const Error& e) {
        fail(ErrorCode::invalid_argument, "{}: {}", path, e.what());
    }
    detail::check_mesh(path, mesh);
    detail::check_samples(path, info.kind, info.samples);

    m_state = std::make_unique<State>(path, mesh, info, first, count, options);
    State& s = *m_state;
    s.extra = detail::parse_extra(s.options);
    if (info.target_error > 0) {  // laid out (as zeros) now, written at commit
        s.estimates.receiver_samples.assign(count, 0);
        s.estimates.receiver_error.assign(count, 0.0f);
    }
    s.sections = detail::plan_sections(mesh, info, count, nullptr, &s.estimates);
    // Lay out with a generous reserve for the metadata: with a placeholder CRC and stats now,
    // and the real ones at commit(), the metadata keeps this length.
    const std::string draft =
        detail::lay_out(path, mesh, info, count, s.options, s.extra, s.sections, 0);
    s.reserve = draft.size() + kMetadataSlack;
    const std::string text =
        detail::lay_out(path, mesh, info, count, s.options, s.extra, s.sections, s.reserve);
    detail::write_file_body(s.file, text, s.sections);
    SHPRT_CHECK(std::fflush(s.file.handle()) == 0, io, "cannot write {}: {}", path,
                std::strerror(errno));
    const detail::SectionOut& transfer = s.sections.back();
    s.sink = std::make_unique<detail::SectionSink>(path, ::fileno(s.file.handle()), transfer.offset,
                                                   info.layout, first, count);
    if (info.target_error > 0) s.sink->keep_estimates(&s.estimates);
}

ShprtStreamWriter::~ShprtStreamWriter() = default;

TransferSink& ShprtStreamWriter::sink() { return *m_state->sink; }

void ShprtStreamWriter::commit(const TransferInfo& info) {
    State& s = *m_state;
    TransferInfo final_info = info;
    final_info.layout.encoding = s.info.layout.encoding;  // the file's choice, as in begin()
    SHPRT_CHECK(info.kind == s.info.kind && final_info.layout == s.info.layout &&
                    info.sampler == s.info.sampler && info.samples == s.info.samples &&
                    info.direction_frame == s.info.direction_frame && info.seed == s.info.seed &&
                    info.target_error == s.info.target_error,
                invalid_argument, "{}: the bake's description differs from the file's layout",
                s.path);
    detail::SectionOut& transfer = s.sections.back();
    transfer.crc = s.sink->section_crc();
    const int fd = ::fileno(s.file.handle());
    // The estimates' sections, filled now (their data points into s.estimates).
    for (detail::SectionOut& section : s.sections) {
        const std::string_view name = section.name;
        if (name != "receiver_samples" && name != "receiver_error") continue;
        section.crc = crc32(section.data, section.length());
        pwrite_all(fd, section.data, section.length(), section.offset, s.path);
    }
    const std::string text = detail::lay_out(s.path, s.mesh, final_info, s.count, s.options,
                                             s.extra, s.sections, s.reserve);
    unsigned char header[kShprtHeaderSize];
    detail::encode_header(text, header, detail::file_version(s.sections));
    pwrite_all(fd, header, sizeof header, 0, s.path);
    pwrite_all(fd, text.data(), text.size(), kShprtHeaderSize, s.path);
    s.file.commit();
}

}  // namespace shprt
