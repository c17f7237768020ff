// Where the finished blocks of the transport operator A go (bake_internal.hpp:
// TransportBlockStore): kept in memory while they fit the bake's budget, else spilled to a
// temporary file and mapped back read-only; and the budget A gets (transport_memory_budget).
// Shared by the CPU's operator pass (interreflect.cpp) and the GPU backend (bake_gpu.cpp).
#include "bake/bake_internal.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace shprt::detail {

namespace {

// The blocks of A that do not fit the memory budget: appended to one temporary file as they
// finish (any thread; each block's bytes at an offset reserved under a lock, written with pwrite
// outside it), then mapped read-only. The file is an AtomicFile's temporary, never committed: it
// is removed when this object goes (an error, a cancel) and by the CLI's signal handlers, and
// unlinked as soon as it is mapped, so that only the mapping keeps its pages.
class SpillFile {
public:
    explicit SpillFile(std::string directory) : m_directory(std::move(directory)) {
        if (m_directory.empty()) {
            const char* tmp = std::getenv("TMPDIR");
            m_directory = tmp && *tmp ? tmp : "/tmp";
        }
    }

    // Where a spilled block's arrays are in the file.
    struct Record {
        std::uint64_t offset = 0;  // row starts, then columns, then the three channels' values
        std::size_t rows = 0, nnz = 0;
    };

    // Writes the block's arrays and frees its vectors.
    Record append(TransportOperator::Block& b) {
        Record r;
        r.rows = b.rows();
        r.nnz = b.nnz();
        const std::uint64_t length = b.bytes();
        int fd = -1;
        {
            const std::lock_guard lock(m_mutex);
            if (!m_file) m_file.emplace(m_directory + "/shprt-transport-operator");
            fd = ::fileno(m_file->handle());
            r.offset = m_size;
            m_size += length;
        }
        const std::string what = "the transport operator's spill file in " + m_directory;
        std::uint64_t at = r.offset;
        const auto put = [&](const void* data, std::size_t bytes) {
            if (bytes) pwrite_all(fd, data, bytes, at, what);
            at += bytes;
        };
        put(b.row_start.data(), b.row_start.size() * sizeof(std::int32_t));
        put(b.column.data(), b.column.size() * sizeof(std::int32_t));
        for (const auto& v : b.values) put(v.data(), v.size() * sizeof(float));
        m_spilled.fetch_add(length);
        // Freed, not cleared: `v = {}` would keep the capacity (initializer-list assignment).
        std::vector<std::int32_t>().swap(b.row_start);
        std::vector<std::int32_t>().swap(b.column);
        for (auto& v : b.values) std::vector<float>().swap(v);
        return r;
    }

    std::uint64_t spilled() const { return m_spilled.load(); }

    // After the last append: maps the file read-only, unlinks it, and points the spilled blocks
    // (records[i].rows > 0) into the mapping, which the returned owner keeps.
    std::shared_ptr<const void> map(TransportOperator& A, const std::vector<Record>& records) {
        if (!m_file) return nullptr;
        const std::string& temp = m_file->temp_path();
        const int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
        SHPRT_CHECK(fd >= 0, io, "cannot read back {}: {}", temp, std::strerror(errno));
        void* base = ::mmap(nullptr, m_size, PROT_READ, MAP_SHARED, fd, 0);
        const int err = errno;
        ::close(fd);
        SHPRT_CHECK(base != MAP_FAILED, io, "cannot map {}: {}", temp, std::strerror(err));
        m_file.reset();  // unlinks the file; the mapping keeps its pages
        const std::size_t length = m_size;
        std::shared_ptr<const void> owner(
            base, [length](const void* p) { ::munmap(const_cast<void*>(p), length); });
        const auto* bytes = static_cast<const unsigned char*>(base);
        for (std::size_t i = 0; i < records.size(); ++i) {
            const Record& r = records[i];
            if (r.rows == 0) continue;
            TransportOperator::Block::Mapped& m = A.blocks[i].mapped;
            const unsigned char* p = bytes + r.offset;
            m.rows = r.rows;
            m.nnz = r.nnz;
            m.row_start = reinterpret_cast<const std::int32_t*>(p);
            m.column = m.row_start + (r.rows + 1);
            const auto* values = reinterpret_cast<const float*>(m.column + r.nnz);
            for (std::size_t c = 0; c < 3; ++c) m.values[c] = values + c * r.nnz;
        }
        return owner;
    }

private:
    std::string m_directory;
    std::mutex m_mutex;
    std::optional<AtomicFile> m_file;
    std::uint64_t m_size = 0;
    std::atomic<std::uint64_t> m_spilled{0};
};

}  // namespace

struct TransportBlockStore::Impl {
    std::uint64_t budget;
    SpillFile spill;
    std::atomic<std::uint64_t> resident{0};
    std::mutex mutex;  // guards records
    std::vector<SpillFile::Record> records;

    Impl(std::uint64_t b, std::string directory) : budget(b), spill(std::move(directory)) {}
};

TransportBlockStore::TransportBlockStore(std::uint64_t budget, std::string spill_directory)
    : m_impl(std::make_unique<Impl>(budget, std::move(spill_directory))) {}

TransportBlockStore::~TransportBlockStore() = default;

void TransportBlockStore::keep(std::size_t index, TransportOperator::Block& block) {
    Impl& m = *m_impl;
    const std::uint64_t bytes = block.bytes();
    // Its vectors may have grown by doubling: trimmed to their size, so that the memory A holds
    // is A.bytes() (the slack was ~10 % of A, seen in the process's RSS).
    if (m.budget == 0 || m.resident.fetch_add(bytes) + bytes <= m.budget) {
        block.row_start.shrink_to_fit();
        block.column.shrink_to_fit();
        for (auto& v : block.values) v.shrink_to_fit();
        return;
    }
    m.resident.fetch_sub(bytes);
    const SpillFile::Record record = m.spill.append(block);
    const std::lock_guard lock(m.mutex);
    if (m.records.size() <= index) m.records.resize(index + 1);
    m.records[index] = record;
}

void TransportBlockStore::finish(TransportOperator& A) {
    Impl& m = *m_impl;
    m.records.resize(A.blocks.size());
    A.spill = m.spill.map(A, m.records);
    A.spilled_bytes = m.spill.spilled();
}

std::uint64_t transport_memory_budget(const Mesh& mesh, const BakeOptions& options) {
    if (options.memory_budget == 0) return 0;
    const std::uint64_t rest =
        estimate_bake_peak_bytes(mesh.triangle_count(), mesh.vertex_count(), options, true,
                                 bake_bounce_source_count(mesh, options));
    return options.memory_budget > rest ? options.memory_budget - rest : 1;
}

}  // namespace shprt::detail
