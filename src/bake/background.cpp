// A bake on a worker thread whose chunks are queued for display (background.hpp).
#include "shprt/bake/background.hpp"

#include "shprt/core/error.hpp"

#include <algorithm>
#include <chrono>

namespace shprt {

void TransferChunk::apply_to(TransferSet& transfer) const {
    const std::size_t R = transfer.receiver_count();
    SHPRT_CHECK(first <= R && count <= R - first, invalid_argument,
                "chunk of receivers [{}, {}) outside the transfer's {}", first, first + count, R);
    SHPRT_CHECK(rows.size() == transfer.layout.floats(count), invalid_argument,
                "chunk holds {} floats, expected {} receivers × {} = {}", rows.size(), count,
                transfer.layout.floats_per_receiver(), transfer.layout.floats(count));
    std::copy(rows.begin(), rows.end(),
              transfer.coeffs.begin() + static_cast<std::ptrdiff_t>(transfer.layout.offset(first)));
}

void ChunkQueue::begin(const TransferLayout& layout, std::size_t, std::size_t) {
    std::lock_guard lock(m_mutex);
    m_layout = layout;
}

void ChunkQueue::write(std::size_t first, std::size_t count, const float* rows) {
    TransferChunk chunk;
    chunk.first = first;
    chunk.count = count;
    std::size_t floats = 0;
    {
        std::lock_guard lock(m_mutex);
        floats = m_layout.floats(count);
        ++m_chunks_written;
        m_receivers_written += count;
    }
    if (rows == nullptr) return;  // written to a device buffer: nothing to queue
    // Copied outside the lock: the consumer only waits for the append.
    chunk.rows.assign(rows, rows + floats);
    std::lock_guard lock(m_mutex);
    m_chunks.push_back(std::move(chunk));
}

std::vector<TransferChunk> ChunkQueue::take_all() {
    std::lock_guard lock(m_mutex);
    std::vector<TransferChunk> out;
    out.swap(m_chunks);
    return out;
}

std::size_t ChunkQueue::pending() const {
    std::lock_guard lock(m_mutex);
    return m_chunks.size();
}

std::size_t ChunkQueue::chunks_written() const {
    std::lock_guard lock(m_mutex);
    return m_chunks_written;
}

std::size_t ChunkQueue::receivers_written() const {
    std::lock_guard lock(m_mutex);
    return m_receivers_written;
}

BackgroundBake::BackgroundBake(Mesh mesh, BakeOptions options,
                               std::unique_ptr<TransferSink> device_sink)
    : m_mesh(std::move(mesh)),
      m_options(std::move(options)),
      m_device_sink(std::move(device_sink)) {
    m_options.progress = [this](const ProgressInfo& info) {
        if (info.total > 0) m_fraction = std::min(1.0, double(info.done) / double(info.total));
        return !m_cancel.load();
    };
    m_thread = std::thread([this] { run(); });
}

BackgroundBake::~BackgroundBake() {
    cancel();
    wait();
}

void BackgroundBake::wait() {
    if (m_thread.joinable()) m_thread.join();
}

std::string BackgroundBake::error() const {
    std::lock_guard lock(m_error_mutex);
    return m_error;
}

void BackgroundBake::run() {
    const auto start = std::chrono::steady_clock::now();
    BakeState final_state = BakeState::finished;
    try {
        BakeJob job;
        job.occluders = &m_mesh;
        job.receivers = vertex_receivers(m_mesh);
        job.sink = m_device_sink ? m_device_sink.get() : &m_chunks;
        m_result = bake(job, m_options);
        m_fraction = 1.0;
    } catch (const Error& e) {
        final_state = e.code() == ErrorCode::cancelled ? BakeState::cancelled : BakeState::failed;
        std::lock_guard lock(m_error_mutex);
        m_error = e.what();
    } catch (const std::exception& e) {
        final_state = BakeState::failed;
        std::lock_guard lock(m_error_mutex);
        m_error = e.what();
    }
    m_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m_state = final_state;
}

}  // namespace shprt
