// A bake on a worker thread whose chunks are queued for display (bake_stream.hpp).
#include "bake_stream.hpp"

#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace shprt::viewer {

void ChunkQueue::push(std::size_t first_vertex, std::size_t vertex_count, const float* coeffs,
                      std::size_t floats_per_vertex) {
    TransferChunk chunk;
    chunk.first_vertex = first_vertex;
    chunk.vertex_count = vertex_count;
    // Copied outside the lock: the GL thread only waits for the append.
    chunk.coeffs.assign(coeffs, coeffs + vertex_count * floats_per_vertex);
    std::lock_guard lock(m_mutex);
    m_chunks.push_back(std::move(chunk));
    ++m_chunks_pushed;
    m_vertices_pushed += vertex_count;
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

std::size_t ChunkQueue::chunks_pushed() const {
    std::lock_guard lock(m_mutex);
    return m_chunks_pushed;
}

std::size_t ChunkQueue::vertices_pushed() const {
    std::lock_guard lock(m_mutex);
    return m_vertices_pushed;
}

void apply_chunk(TransferSet& transfer, const TransferChunk& chunk) {
    const std::size_t V = transfer.vertex_count();
    SHPRT_CHECK(transfer.channels == 1, invalid_argument,
                "apply_chunk: transfer has {} channels (bake chunks have 1)", transfer.channels);
    SHPRT_CHECK(chunk.first_vertex <= V && chunk.vertex_count <= V - chunk.first_vertex,
                invalid_argument, "chunk of vertices [{}, {}) outside the transfer's {}",
                chunk.first_vertex, chunk.first_vertex + chunk.vertex_count, V);
    const std::size_t K = static_cast<std::size_t>(transfer.K);
    SHPRT_CHECK(chunk.coeffs.size() == chunk.vertex_count * K, invalid_argument,
                "chunk holds {} floats, expected {} vertices × K = {}", chunk.coeffs.size(),
                chunk.vertex_count, K);
    std::copy(chunk.coeffs.begin(), chunk.coeffs.end(),
              transfer.coeffs.begin() + static_cast<std::ptrdiff_t>(chunk.first_vertex * K));
}

TransferSet empty_transfer(std::size_t vertex_count, int K, TransferKind kind) {
    TransferSet t;
    t.kind = kind;
    t.K = K;
    t.channels = 1;
    t.coeffs.assign(vertex_count * static_cast<std::size_t>(K), 0.0f);
    return t;
}

BackgroundBake::BackgroundBake(Mesh mesh, BakeOptions options, float* device_output)
    : m_mesh(std::move(mesh)), m_options(std::move(options)) {
    const std::size_t K = static_cast<std::size_t>(m_options.K);
    m_options.on_chunk = [this, K](std::size_t first, std::size_t count, const float* coeffs) {
        if (coeffs) m_chunks.push(first, count, coeffs, K);  // null: written to the device
    };
    m_options.progress = [this](const ProgressInfo& info) {
        if (info.total > 0) m_fraction = std::min(1.0, double(info.done) / double(info.total));
        return !m_cancel.load();
    };
    m_thread = std::thread([this, device_output] { run(device_output); });
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

void BackgroundBake::run(float* device_output) {
    const auto start = std::chrono::steady_clock::now();
    BakeState final_state = BakeState::finished;
    try {
        if (device_output) {
            const DirectionSet directions =
                make_direction_set(m_options.sampler, m_options.seed, m_options.samples);
            m_result = bake_gpu(m_mesh, m_options, directions, device_output);
        } else {
            m_result = bake(m_mesh, m_options);
        }
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

}  // namespace shprt::viewer
