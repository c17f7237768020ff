#include "shprt/io/checkpoint.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_format.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <utility>

namespace shprt {
namespace {

constexpr char kMagic[8] = {'S', 'H', 'P', 'R', 'T', 'C', 'K', 'P'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 64;
constexpr std::size_t kRecordHeadBytes = 32;
constexpr std::uint32_t kRecordTag = 0x4352'4b43;  // "CKRC" little-endian

std::array<unsigned char, kHeaderBytes> make_header(std::uint64_t fingerprint, std::size_t first,
                                                    std::size_t count, std::size_t floats) {
    std::array<unsigned char, kHeaderBytes> h{};
    std::memcpy(h.data(), kMagic, 8);
    put_u32(h.data() + 8, kVersion);
    put_u32(h.data() + 12, kHeaderBytes);
    put_u64(h.data() + 16, fingerprint);
    put_u64(h.data() + 24, first);
    put_u64(h.data() + 32, count);
    put_u64(h.data() + 40, floats);
    put_u32(h.data() + 60, crc32(h.data(), 60));
    return h;
}

// Reads up to `size` bytes at `offset`; returns how many were read (fewer only at the end).
std::size_t pread_some(int fd, void* data, std::size_t size, std::uint64_t offset,
                       const std::string& path) {
    auto* p = static_cast<unsigned char*>(data);
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::pread(fd, p + done, size - done, static_cast<off_t>(offset + done));
        if (n < 0 && errno == EINTR) continue;
        SHPRT_CHECK(n >= 0, io, "cannot read {}: {}", path, std::strerror(errno));
        if (n == 0) break;
        done += static_cast<std::size_t>(n);
    }
    return done;
}

}  // namespace

std::uint64_t checkpoint_fingerprint(const Mesh& occluders, std::size_t first, std::size_t count,
                                     const TransferInfo& d) {
    const std::uint64_t fields[] = {
        mesh_hash(occluders), first, count, static_cast<std::uint64_t>(d.kind),
        static_cast<std::uint64_t>(d.layout.domain), static_cast<std::uint64_t>(d.layout.channels),
        static_cast<std::uint64_t>(d.layout.K), static_cast<std::uint64_t>(d.layout.shape),
        // a local set's bit above the sampler: a sphere bake's
        // fingerprint stays what it was
        static_cast<std::uint64_t>(d.sampler) |
            (d.direction_frame == DirectionFrame::local ? 0x100u : 0u),
        static_cast<std::uint64_t>(d.samples), d.seed};
    return fnv1a64(fields, sizeof(fields));
}

CheckpointFile CheckpointFile::create(const std::string& path, std::uint64_t fingerprint,
                                      std::size_t first, std::size_t count,
                                      std::size_t floats_per_receiver, double sync_seconds) {
    struct stat st {};
    SHPRT_CHECK(::stat(path.c_str(), &st) != 0, invalid_argument,
                "{}: a checkpoint exists; continue its bake with --resume {}, or remove it", path,
                path);
    {
        AtomicFile out(path);
        const auto header = make_header(fingerprint, first, count, floats_per_receiver);
        out.write(header.data(), header.size());
        out.commit();
    }
    return resume(path, fingerprint, first, count, floats_per_receiver, sync_seconds);
}

CheckpointFile CheckpointFile::resume(const std::string& path, std::uint64_t fingerprint,
                                      std::size_t first, std::size_t count,
                                      std::size_t floats_per_receiver, double sync_seconds) {
    CheckpointFile f;
    f.m_path = path;
    f.m_first = first;
    f.m_count = count;
    f.m_floats = floats_per_receiver;
    f.m_sync_seconds = sync_seconds;
    f.m_last_sync = std::chrono::steady_clock::now();
    f.m_fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    SHPRT_CHECK(f.m_fd >= 0, io, "cannot open {}: {}", path, std::strerror(errno));
    struct stat st {};
    SHPRT_CHECK(::fstat(f.m_fd, &st) == 0 && S_ISREG(st.st_mode), io, "{}: not a regular file",
                path);
    const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);

    std::array<unsigned char, kHeaderBytes> h{};
    SHPRT_CHECK(pread_some(f.m_fd, h.data(), h.size(), 0, path) == h.size() &&
                    std::memcmp(h.data(), kMagic, 8) == 0 &&
                    get_u32(h.data() + 60) == crc32(h.data(), 60),
                format, "{}: not a shprt checkpoint (or its header is damaged)", path);
    SHPRT_CHECK(get_u32(h.data() + 8) == kVersion, format,
                "{}: checkpoint version {} (this shprt reads version {})", path,
                get_u32(h.data() + 8), kVersion);
    SHPRT_CHECK(get_u64(h.data() + 16) == fingerprint && get_u64(h.data() + 24) == first &&
                    get_u64(h.data() + 32) == count &&
                    get_u64(h.data() + 40) == floats_per_receiver,
                invalid_argument,
                "{}: the checkpoint is of another bake (the scene, its receivers or the bake "
                "options differ); resume with the same scene and options, or start afresh",
                path);

    // The records, up to the first that is cut short or damaged.
    const std::uint64_t row_bytes = std::uint64_t(floats_per_receiver) * sizeof(float);
    std::uint64_t at = kHeaderBytes;
    std::vector<unsigned char> rows;
    while (at + kRecordHeadBytes <= size) {
        unsigned char r[kRecordHeadBytes];
        if (pread_some(f.m_fd, r, sizeof r, at, path) != sizeof r) break;
        if (get_u32(r) != kRecordTag || get_u32(r + 28) != crc32(r, 28)) break;
        const std::uint64_t rf = get_u64(r + 8), rc = get_u64(r + 16);
        if (rc == 0 || rf < first || rf > first + count || rc > first + count - rf) break;
        const std::uint64_t bytes = rc * row_bytes;
        if (bytes > size - at - kRecordHeadBytes) break;
        rows.resize(bytes);
        if (pread_some(f.m_fd, rows.data(), bytes, at + kRecordHeadBytes, path) != bytes ||
            crc32(rows.data(), bytes) != get_u32(r + 4))
            break;
        f.m_found.push_back({at + kRecordHeadBytes, {rf, rc}});
        f.m_done.push_back({rf, rc});
        at += kRecordHeadBytes + bytes;
    }
    // Every receiver at most once, as merge_shprt_parts checks its parts: a bake never writes a
    // receiver twice, so records that overlap (each with a valid CRC) are a forged or foreign
    // file, and replaying them would let the later rows replace the earlier ones.
    if (const SpanOrder sorted = order_spans(f.m_done); sorted.overlap) {
        const ReceiverSpan a = f.m_done[sorted.overlap->first],
                           b = f.m_done[sorted.overlap->second];
        fail(ErrorCode::format,
             "{}: checkpoint records {} and {} both hold receivers [{}, {}) (a damaged or forged "
             "checkpoint); start afresh without --resume",
             path, sorted.overlap->first, sorted.overlap->second, std::max(a.first, b.first),
             std::min(a.first + a.count, b.first + b.count));
    }
    if (at < size)
        SHPRT_CHECK(::ftruncate(f.m_fd, static_cast<off_t>(at)) == 0, io, "cannot truncate {}: {}",
                    path, std::strerror(errno));
    SHPRT_CHECK(::lseek(f.m_fd, static_cast<off_t>(at), SEEK_SET) >= 0, io, "cannot seek {}: {}",
                path, std::strerror(errno));
    return f;
}

CheckpointFile::CheckpointFile(CheckpointFile&& o) noexcept
    : m_path(std::move(o.m_path)),
      m_fd(std::exchange(o.m_fd, -1)),
      m_first(o.m_first),
      m_count(o.m_count),
      m_floats(o.m_floats),
      m_sync_seconds(o.m_sync_seconds),
      m_found(std::move(o.m_found)),
      m_done(std::move(o.m_done)),
      m_last_sync(o.m_last_sync) {}

CheckpointFile::~CheckpointFile() {
    if (m_fd >= 0) ::close(m_fd);
}

std::size_t CheckpointFile::done_receivers() const {
    std::lock_guard lock(m_mutex);
    const std::vector<ReceiverSpan> left = remaining_spans(m_first, m_count, m_done);
    std::size_t n = m_count;
    for (const ReceiverSpan& s : left) n -= s.count;
    return n;
}

void CheckpointFile::append(std::size_t first, std::size_t count, const float* rows) {
    SHPRT_CHECK(
        rows != nullptr && count > 0 && first >= m_first && first + count <= m_first + m_count,
        invalid_argument, "checkpoint {}: rows {}+{} outside its range", m_path, first, count);
    const std::size_t bytes = count * m_floats * sizeof(float);
    unsigned char head[kRecordHeadBytes] = {};
    put_u32(head, kRecordTag);
    put_u32(head + 4, crc32(rows, bytes));
    put_u64(head + 8, first);
    put_u64(head + 16, count);
    put_u32(head + 28, crc32(head, 28));
    std::vector<unsigned char> record(kRecordHeadBytes + bytes);
    std::memcpy(record.data(), head, kRecordHeadBytes);
    std::memcpy(record.data() + kRecordHeadBytes, rows, bytes);

    std::lock_guard lock(m_mutex);
    SHPRT_CHECK(m_fd >= 0, io, "checkpoint {} is closed", m_path);
    std::size_t done = 0;
    while (done < record.size()) {
        const ssize_t n = ::write(m_fd, record.data() + done, record.size() - done);
        if (n < 0 && errno == EINTR) continue;
        SHPRT_CHECK(n > 0, io, "cannot write checkpoint {}: {}", m_path,
                    n < 0 ? std::strerror(errno) : "no progress");
        done += static_cast<std::size_t>(n);
    }
    m_done.push_back({first, count});
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - m_last_sync).count() >= m_sync_seconds) {
        SHPRT_CHECK(::fdatasync(m_fd) == 0, io, "cannot sync checkpoint {}: {}", m_path,
                    std::strerror(errno));
        m_last_sync = now;
    }
}

void CheckpointFile::replay(TransferSink& sink) const {
    std::vector<float> rows;
    for (const Record& r : m_found) {
        rows.resize(r.span.count * m_floats);
        SHPRT_CHECK(pread_some(m_fd, rows.data(), rows.size() * sizeof(float), r.offset, m_path) ==
                        rows.size() * sizeof(float),
                    io, "cannot read {}: it changed while resuming", m_path);
        sink.write(r.span.first, r.span.count, rows.data());
    }
}

void CheckpointFile::sync() {
    std::lock_guard lock(m_mutex);
    SHPRT_CHECK(m_fd >= 0 && ::fdatasync(m_fd) == 0, io, "cannot sync checkpoint {}: {}", m_path,
                std::strerror(errno));
}

void CheckpointFile::remove() {
    std::lock_guard lock(m_mutex);
    if (m_fd >= 0) ::close(m_fd);
    m_fd = -1;
    ::unlink(m_path.c_str());
}

void CheckpointSink::begin(const TransferLayout& layout, std::size_t first, std::size_t count) {
    SHPRT_CHECK(first >= m_file.first() && first + count <= m_file.first() + m_file.count(),
                invalid_argument, "checkpoint {}: receivers {}+{} outside its range", m_file.path(),
                first, count);
    if (m_begun) return;
    m_begun = true;
    m_inner.begin(layout, m_file.first(), m_file.count());
    m_file.replay(m_inner);
}

void CheckpointSink::write(std::size_t first, std::size_t count, const float* rows) {
    SHPRT_CHECK(rows != nullptr, unsupported,
                "a checkpoint takes rows from host memory (not a device buffer)");
    m_inner.write(first, count, rows);
    m_file.append(first, count, rows);
}

void CheckpointSink::finish() {
    if (m_finished || m_file.done_receivers() < m_file.count()) return;
    m_finished = true;
    m_inner.finish();
}

}  // namespace shprt
