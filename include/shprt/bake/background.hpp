// A bake shown while it refines (`shprt view SCENE --bake`, and later Python): the bake runs on a
// worker thread into a ChunkQueue — a sink that copies each finished chunk of rows — and the
// consumer (the viewer's GL thread) drains the queue when it likes. Nothing here touches
// OpenGL, so the queue logic is tested without a window: applying every chunk to an all-zero
// TransferSet (TransferChunk::apply_to) reproduces the normal bake bit for bit, because the
// chunks are the bake's own output rows.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/bake/session.hpp"
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

    // An error-bounded bake's per-receiver prefixes and estimates (BakeOptions::target_error),
    // kept for the receivers [first, first + count) of the last begin(); empty otherwise.
    void begin_estimates() override;
    void write_estimates(std::size_t first, std::size_t count, const std::uint32_t* samples,
                         const float* errors) override;
    // The estimates written since the last begin() (samples, errors: one per receiver, 0 where
    // none was written yet).
    void copy_estimates(std::vector<std::uint32_t>& samples, std::vector<float>& errors) const;

private:
    mutable std::mutex m_mutex;
    TransferLayout m_layout;
    std::size_t m_first = 0;
    std::vector<std::uint32_t> m_samples;
    std::vector<float> m_errors;
    std::vector<TransferChunk> m_chunks;
    std::size_t m_chunks_written = 0, m_receivers_written = 0;
};

enum class BakeState { running, finished, failed, cancelled };

// An error-bounded bake refining toward its target in the viewer (BackgroundBake): the bake runs
// in rounds whose largest prefix grows 4× a round, kTargetFirstSamples·4 = 256, 1024, … up to the
// options' max_samples, each an error-bounded bake to the same target whose rows replace the last
// round's; the last round is the bake asked for, bit for bit. The rounds run on one bake session
// (session.hpp, bake_to): a round goes on from the last one's sums, so every ray is cast once and
// the rounds together cost what the last one alone would.
struct RefineRound {
    int round = 0, rounds = 0;      // 1-based: the round finished last (0: none yet), of `rounds`
    std::uint32_t max_samples = 0;  // that round's largest prefix
    double worst = 0, p99 = 0;      // its estimated errors (docs/sampling.md)
    double over_target = 0;         // the fraction of receivers whose estimate is still over E
    double mean_samples = 0;
};

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
    // Rays cast by every round once done (BakeSession::rays_cast: each ray once).
    std::uint64_t rays_cast() const { return m_rays.load(); }
    // An error-bounded bake's last finished round (error_bound_rounds; round = 0 before the first).
    RefineRound refine_round() const;
    // Every round finished so far, oldest first.
    std::vector<RefineRound> refine_history() const;

private:
    void run();
    void record_round(int round, int rounds, std::uint32_t max_samples);

    Mesh m_mesh;
    BakeOptions m_options;
    ChunkQueue m_chunks;
    std::unique_ptr<TransferSink> m_device_sink;
    TransferInfo m_result;
    std::atomic<bool> m_cancel{false};
    std::atomic<BakeState> m_state{BakeState::running};
    std::atomic<double> m_fraction{0.0}, m_seconds{0.0};
    std::atomic<std::uint64_t> m_rays{0};
    mutable std::mutex m_error_mutex;
    std::string m_error;
    std::vector<RefineRound> m_rounds;  // under m_error_mutex
    std::thread m_thread;
};

}  // namespace shprt
