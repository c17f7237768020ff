// A bake shown while it refines (`shprt view SCENE --bake`, and later Python): the bake runs on a
// worker thread into a ChunkQueue — a sink that copies each finished chunk of rows — and the
// consumer (the viewer's GL thread) drains the queue when it likes. Nothing here touches
// OpenGL, so the queue logic is tested without a window: applying every chunk to an all-zero
// TransferSet (TransferChunk::apply_to) reproduces the normal bake bit for bit, because the
// chunks are the bake's own output rows.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/sink.hpp"

#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace shprt {

// The rows of receivers [first, first + count): layout.floats(count) floats.
struct TransferChunk {
    std::size_t first = 0, count = 0;
    std::vector<float> rows;

    // Writes the rows into `transfer`, whose layout must be the chunk's (layout.floats(count) ==
    // rows.size()) and which must hold the range; Error(invalid_argument) otherwise. The host
    // twin of Renderer::update_transfer.
    void apply_to(TransferSet& transfer) const;
};

// A thread-safe FIFO sink: write() (from the bake's workers) copies the rows, take_all() (from
// the consumer) returns what was written so far. Rows written to a device buffer (rows = nullptr)
// are counted but not queued.
class ChunkQueue final : public TransferSink {
public:
    void begin(const TransferLayout& layout, std::size_t first, std::size_t count) override;
    void write(std::size_t first, std::size_t count, const float* rows) override;
    // Everything written so far, oldest first; the queue is empty afterwards.
    std::vector<TransferChunk> take_all();
    std::size_t pending() const;
    // Chunks and receivers written since construction.
    std::size_t chunks_written() const;
    std::size_t receivers_written() const;

private:
    mutable std::mutex m_mutex;
    TransferLayout m_layout;
    std::vector<TransferChunk> m_chunks;
    std::size_t m_chunks_written = 0, m_receivers_written = 0;
};

enum class BakeState { running, finished, failed, cancelled };

// bake() of every vertex of `mesh` on a worker thread, started by the constructor, into
// chunks() — or, when `device_sink` is given (a DeviceSink over a mapped OpenGL buffer, for the
// GPU bake with CUDA–OpenGL interop), into that sink, with nothing queued. options.progress is
// replaced by one that records the fraction done and returns false once cancel() was called (the
// bake then stops promptly and the state becomes cancelled). The destructor cancels and joins.
class BackgroundBake {
public:
    BackgroundBake(Mesh mesh, BakeOptions options, std::unique_ptr<TransferSink> device_sink = {});
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
    // The error message when failed or cancelled ("" otherwise).
    std::string error() const;
    // What the bake produced (layout, sampling, stats), after state() == finished.
    const TransferInfo& result() const { return m_result; }
    const BakeOptions& options() const { return m_options; }
    double seconds() const { return m_seconds.load(); }  // wall time of the bake once done

private:
    void run();

    Mesh m_mesh;
    BakeOptions m_options;
    ChunkQueue m_chunks;
    std::unique_ptr<TransferSink> m_device_sink;
    TransferInfo m_result;
    std::atomic<bool> m_cancel{false};
    std::atomic<BakeState> m_state{BakeState::running};
    std::atomic<double> m_fraction{0.0}, m_seconds{0.0};
    mutable std::mutex m_error_mutex;
    std::string m_error;
    std::thread m_thread;
};

}  // namespace shprt
