// A bake on a worker thread whose chunks are queued for display (background.hpp).
#include "shprt/bake/background.hpp"

#include "shprt/bake/session.hpp"

#include "shprt/core/error.hpp"
#include "shprt/transfer/estimates.hpp"

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

void ChunkQueue::begin(const TransferLayout& layout, std::size_t first, std::size_t) {
    std::lock_guard lock(m_mutex);
    m_layout = layout;
    m_first = first;
    m_samples.clear();
    m_errors.clear();
}

void ChunkQueue::begin_estimates() {}

void ChunkQueue::write_estimates(std::size_t first, std::size_t count, const std::uint32_t* samples,
                                 const float* errors) {
    std::lock_guard lock(m_mutex);
    const std::size_t end = first - m_first + count;
    if (m_samples.size() < end) m_samples.resize(end, 0), m_errors.resize(end, 0.0f);
    std::copy(samples, samples + count, m_samples.begin() + std::ptrdiff_t(first - m_first));
    std::copy(errors, errors + count, m_errors.begin() + std::ptrdiff_t(first - m_first));
}

void ChunkQueue::copy_estimates(std::vector<std::uint32_t>& samples,
                                std::vector<float>& errors) const {
    std::lock_guard lock(m_mutex);
    samples = m_samples;
    errors = m_errors;
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

RefineRound BackgroundBake::refine_round() const {
    std::lock_guard lock(m_error_mutex);
    return m_rounds.empty() ? RefineRound{} : m_rounds.back();
}

std::vector<RefineRound> BackgroundBake::refine_history() const {
    std::lock_guard lock(m_error_mutex);
    return m_rounds;
}

void BackgroundBake::run() {
    const auto start = std::chrono::steady_clock::now();
    BakeState final_state = BakeState::finished;
    try {
        BakeJob job;
        job.occluders = &m_mesh;
        job.receivers = vertex_receivers(m_mesh);
        job.sink = m_device_sink ? m_device_sink.get() : &m_chunks;
        // One session for every round: the tracer and tables are built once, and each round of
        // an error-bounded bake goes on from the last, tracing only the new segments.
        BakeSession session(job, m_options);
        // The fraction done over every round, each weighed by its largest prefix (the rays a
        // whole bake to it would cast; on a session a round casts about the difference).
        const std::vector<std::uint32_t> rounds = error_bound_rounds(m_options);
        double total = 0, before = 0;
        for (const std::uint32_t s : rounds) total += double(s);
        for (std::size_t r = 0; r < rounds.size(); ++r) {
            const double share = double(rounds[r]) / total;
            ProgressFn progress = [this, before, share](const ProgressInfo& info) {
                if (info.total > 0)
                    m_fraction =
                        std::min(1.0, before + share * double(info.done) / double(info.total));
                return !m_cancel.load();
            };
            m_result = m_options.target_error > 0
                           ? session.bake_to(rounds[r], *job.sink, std::move(progress))
                           : session.bake(job, std::move(progress));
            before += share;
            if (m_options.target_error > 0) record_round(int(r) + 1, int(rounds.size()), rounds[r]);
        }
        m_rays = session.rays_cast();
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

void BackgroundBake::record_round(int round, int rounds, std::uint32_t max_samples) {
    std::vector<std::uint32_t> samples;
    std::vector<float> errors;
    m_chunks.copy_estimates(samples, errors);
    RefineRound r;
    r.round = round;
    r.rounds = rounds;
    r.max_samples = max_samples;
    std::vector<double> e(errors.begin(), errors.end());
    std::size_t over = 0;
    double sum = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        over += e[i] > m_options.target_error ? 1 : 0;
        sum += double(samples[i]);
    }
    if (!e.empty()) {
        r.over_target = double(over) / double(e.size());
        r.mean_samples = sum / double(e.size());
        const ErrorSpread spread = error_spread(std::move(e));
        r.worst = spread.worst;
        r.p99 = spread.p99;
    }
    std::lock_guard lock(m_error_mutex);
    m_rounds.push_back(r);
}

}  // namespace shprt
