// A bake shown while it refines (`shprt view SCENE --bake`): the bake runs on a worker thread,
// each finished chunk of vertices is copied into a queue (BakeOptions::on_chunk), and the GL
// thread drains the queue once per frame into the renderer's transfer buffer
// (Renderer::update_transfer). OpenGL is only ever touched by the thread that owns the context.
//
// No OpenGL here, so the queue logic is tested without a window: applying every chunk to a
// zero-filled TransferSet (apply_chunk) reproduces the normal bake bit for bit, because the
// chunks are the bake's own output rows.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/scene/mesh.hpp"

#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace shprt::viewer {

// Coefficients of vertices [first_vertex, first_vertex + vertex_count): vertex_count × K floats
// (one channel, vertex-major, the TransferSet layout).
struct TransferChunk {
    std::size_t first_vertex = 0, vertex_count = 0;
    std::vector<float> coeffs;
};

// A thread-safe FIFO of chunks: one producer (the bake's on_chunk, serialised by the bake), one
// consumer (the GL thread).
class ChunkQueue {
public:
    // Copies `vertex_count × floats_per_vertex` floats from `coeffs` (valid only during the call).
    void push(std::size_t first_vertex, std::size_t vertex_count, const float* coeffs,
              std::size_t floats_per_vertex);
    // Everything pushed so far, oldest first; the queue is empty afterwards.
    std::vector<TransferChunk> take_all();
    std::size_t pending() const;
    // Chunks and vertices pushed since construction.
    std::size_t chunks_pushed() const;
    std::size_t vertices_pushed() const;

private:
    mutable std::mutex m_mutex;
    std::vector<TransferChunk> m_chunks;
    std::size_t m_chunks_pushed = 0, m_vertices_pushed = 0;
};

// Writes `chunk` into `transfer` (channels must be 1 and the chunk inside the vertex range;
// Error(invalid_argument) otherwise). The host twin of Renderer::update_transfer.
void apply_chunk(TransferSet& transfer, const TransferChunk& chunk);

// A transfer of `vertex_count` vertices, one channel, basis size K, all zero: what the renderer
// starts from before the first chunk arrives (an unlit, black scene).
TransferSet empty_transfer(std::size_t vertex_count, int K, TransferKind kind);

enum class BakeState { running, finished, failed, cancelled };

// bake(mesh, options) on a worker thread, started by the constructor. options.on_chunk is
// replaced by a push into chunks(); options.progress is replaced by one that records the
// fraction done and returns false once cancel() was called (the bake then stops promptly and the
// state becomes cancelled). The destructor cancels and joins.
//
// device_output (GPU bakes with CUDA–OpenGL interop only): when non-null, bake_gpu writes the
// coefficients there directly (a mapped GL buffer) and no chunks are queued; null for CPU bakes.
class BackgroundBake {
public:
    BackgroundBake(Mesh mesh, BakeOptions options, float* device_output = nullptr);
    ~BackgroundBake();
    BackgroundBake(const BackgroundBake&) = delete;
    BackgroundBake& operator=(const BackgroundBake&) = delete;

    ChunkQueue& chunks() { return m_chunks; }
    // Asks the bake to stop (returns at once; the worker notices at its next progress report).
    void cancel() { m_cancel = true; }
    // Blocks until the worker has finished (in any state).
    void wait();

    BakeState state() const { return m_state.load(); }
    bool done() const { return state() != BakeState::running; }
    // Rays done / rays estimated, in [0, 1]; 1 once finished.
    double fraction_done() const { return m_fraction.load(); }
    // The error message when failed ("" otherwise).
    std::string error() const;
    // The full result (coeffs empty for a device_output bake), after state() == finished.
    const TransferSet& result() const { return m_result; }
    const BakeOptions& options() const { return m_options; }
    double seconds() const { return m_seconds.load(); }  // wall time of the bake once done

private:
    void run(float* device_output);

    Mesh m_mesh;
    BakeOptions m_options;
    ChunkQueue m_chunks;
    TransferSet m_result;
    std::atomic<bool> m_cancel{false};
    std::atomic<BakeState> m_state{BakeState::running};
    std::atomic<double> m_fraction{0.0}, m_seconds{0.0};
    mutable std::mutex m_error_mutex;
    std::string m_error;
    std::thread m_thread;
};

}  // namespace shprt::viewer
