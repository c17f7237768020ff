// One bake across MPI ranks (dist/mpi_bake.hpp): the session, collective error agreement, the
// work units (guided self-scheduling: C. D. Polychronopoulos, D. J. Kuck, "Guided
// self-scheduling: a practical scheduling scheme for parallel supercomputers", IEEE Trans.
// Computers 36(12), 1987), a one-sided fetch-and-add counter to claim them, and the gather of
// rows into rank 0's sink.
#include "shprt/dist/mpi_bake.hpp"

#include "shprt/bake/gpu.hpp"
#include "shprt/bake/session.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/job.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <mpi.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <vector>

namespace shprt::dist {
namespace {

// Point-to-point tags of the bake protocol (MPI_COMM_WORLD).
constexpr int kTagUnit = 1;   // worker → 0: [u64 unit index], then at once kTagRows:
constexpr int kTagRows = 5;   // worker → 0: the unit's rows, float32 (received in place)
constexpr int kTagDone = 2;   // worker → 0, after its rows: [u8 failed][RankLoad][BakeStats]
constexpr int kTagStop = 3;   // 0 → worker, exactly one: [u8 cancel] (0: no more units)
constexpr int kTagError = 4;  // failing rank → 0 in agree(): [i32 code][message]

// The largest message of rows: MPI counts are int, and a unit's rows sit in memory a few times.
constexpr std::size_t kMaxUnitBytes = std::size_t(64) << 20;

int as_count(std::size_t bytes) {
    SHPRT_CHECK(bytes <= std::size_t(INT32_MAX), invalid_argument,
                "an MPI message of {} bytes is too large", bytes);
    return static_cast<int>(bytes);
}

// BakeStats as bytes, for messages: the numbers, then the device name.
template <typename T>
void put(std::vector<char>& out, const T& value) {
    const auto* p = reinterpret_cast<const char*>(&value);
    out.insert(out.end(), p, p + sizeof(T));
}
template <typename T>
T take(const std::vector<char>& in, std::size_t& at) {
    SHPRT_CHECK(at + sizeof(T) <= in.size(), format, "a truncated MPI message ({} bytes)",
                in.size());
    T value;
    std::memcpy(&value, in.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
}
void pack(std::vector<char>& out, const BakeStats& s) {
    put(out, s.seconds_bvh);
    put(out, s.seconds_trace);
    put(out, s.seconds_project);
    put(out, s.seconds_total);
    put(out, s.rays_cast);
    put(out, s.peak_bytes_host);
    put(out, s.peak_bytes_device);
    out.insert(out.end(), s.device_name.begin(), s.device_name.end());
}
BakeStats unpack(const std::vector<char>& in, std::size_t at) {
    BakeStats s;
    s.seconds_bvh = take<double>(in, at);
    s.seconds_trace = take<double>(in, at);
    s.seconds_project = take<double>(in, at);
    s.seconds_total = take<double>(in, at);
    s.rays_cast = take<std::uint64_t>(in, at);
    s.peak_bytes_host = take<std::uint64_t>(in, at);
    s.peak_bytes_device = take<std::uint64_t>(in, at);
    s.device_name.assign(in.begin() + std::ptrdiff_t(at), in.end());
    return s;
}

// Receives the message that MPI_Probe/Iprobe found (`status`) into a byte buffer.
std::vector<char> receive(const MPI_Status& status) {
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    std::vector<char> buffer(static_cast<std::size_t>(bytes));
    MPI_Recv(buffer.data(), bytes, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    return buffer;
}

// The unit counter: one 64-bit integer on rank 0 that every rank fetch-and-adds (passive target,
// one lock_all epoch for the bake's duration).
class UnitCounter {
public:
    UnitCounter(int rank) {
        const MPI_Aint bytes = rank == 0 ? sizeof(std::uint64_t) : 0;
        MPI_Win_allocate(bytes, sizeof(std::uint64_t), MPI_INFO_NULL, MPI_COMM_WORLD, &m_base,
                         &m_window);
        if (rank == 0) *m_base = 0;
        MPI_Barrier(MPI_COMM_WORLD);  // the counter is 0 before anyone claims
        MPI_Win_lock_all(0, m_window);
    }
    ~UnitCounter() {
        MPI_Win_unlock_all(m_window);
        MPI_Win_free(&m_window);
    }
    UnitCounter(const UnitCounter&) = delete;
    UnitCounter& operator=(const UnitCounter&) = delete;

    // The next unit's index (≥ the unit count once they are all claimed).
    std::uint64_t claim() { return apply(1, MPI_SUM); }
    // No unit is claimed from now on (rank 0, when the bake stops early).
    void exhaust(std::uint64_t units) { apply(units, MPI_REPLACE); }

private:
    std::uint64_t apply(std::uint64_t operand, MPI_Op op) {
        std::uint64_t previous = 0;
        MPI_Fetch_and_op(&operand, &previous, MPI_UINT64_T, 0, 0, op, m_window);
        MPI_Win_flush(0, m_window);
        return previous;
    }

    std::uint64_t* m_base = nullptr;
    MPI_Win m_window = MPI_WIN_NULL;
};

// Rank 0's own units go straight to the bake's sink (in place where it offers host rows); begin
// and finish belong to the whole bake, not to a unit.
class UnitToSink final : public TransferSink {
public:
    explicit UnitToSink(TransferSink& target) : m_target(target) {}
    void begin(const TransferLayout&, std::size_t, std::size_t) override {}
    float* host_rows(std::size_t first, std::size_t count) override {
        return m_target.host_rows(first, count);
    }
    void write(std::size_t first, std::size_t count, const float* rows) override {
        m_target.write(first, count, rows);
    }

private:
    TransferSink& m_target;
};

// A worker's unit, baked in place into the buffer it is sent from: [u64 unit index][rows].
class UnitMessage final : public TransferSink {
public:
    UnitMessage(std::uint64_t unit, const TransferLayout& layout, std::size_t first,
                std::size_t count)
        : m_first(first),
          m_layout(layout),
          m_buffer(sizeof(std::uint64_t) + layout.floats(count) * sizeof(float)) {
        std::memcpy(m_buffer.data(), &unit, sizeof(unit));
    }
    void begin(const TransferLayout&, std::size_t, std::size_t) override {}
    float* host_rows(std::size_t first, std::size_t) override { return rows() + offset(first); }
    void write(std::size_t first, std::size_t count, const float* rows_in) override {
        float* to = rows() + offset(first);
        if (rows_in != to) std::copy_n(rows_in, m_layout.floats(count), to);
    }
    std::vector<char>& buffer() { return m_buffer; }

private:
    float* rows() { return reinterpret_cast<float*>(m_buffer.data() + sizeof(std::uint64_t)); }
    std::size_t offset(std::size_t first) const { return m_layout.floats(first - m_first); }

    std::size_t m_first;
    TransferLayout m_layout;
    std::vector<char> m_buffer;
};

// What every rank prepares before the units: the backend, and the bake session that all of the
// rank's units run on (bake/session.hpp: the direction set, its tables and, for a CPU bake of
// shadowed transfer, one tracer).
struct Prepared {
    BakeOptions options;
    std::unique_ptr<BakeSession> session;
};

void prepare(const MpiSession& session, const BakeJob& job, const BakeOptions& options,
             const DistOptions& dist, Prepared& p) {
    p.options = options;
    p.options.progress = nullptr;
    if (job.directions) p.options.samples = static_cast<std::uint32_t>(job.directions->size());
    validate(p.options);
    SHPRT_CHECK(dist.units_in_flight >= 1, invalid_argument, "units in flight = {}: at least one",
                dist.units_in_flight);
    SHPRT_CHECK(job.occluders != nullptr && job.receivers.count >= 1, invalid_argument,
                "a distributed bake needs occluders and at least one receiver");
    SHPRT_CHECK(session.rank() != 0 || job.sink != nullptr, invalid_argument,
                "rank 0 of a distributed bake needs a sink for the rows");
    if (p.options.device != Device::cpu) {  // rank → GPU by local rank
        const int devices = query_gpu(0).device_count;
        if (devices > 0) p.options.device_index = session.local_rank() % devices;
    }
    p.options.device = resolve_device(p.options.device, p.options.device_index);
    p.session = std::make_unique<BakeSession>(job, p.options);
}

// One unit's bake on this rank.
TransferInfo bake_unit(const BakeJob& job, const Prepared& p, const WorkUnit& unit,
                       TransferSink& sink, ProgressFn progress) {
    BakeJob unit_job = job;
    unit_job.receivers = job.receivers.range(job.receivers.first + unit.first, unit.count);
    unit_job.sink = &sink;
    return p.session->bake(unit_job, std::move(progress));
}

void count_unit(RankLoad& load, const WorkUnit& unit, const TransferInfo& info) {
    ++load.units;
    load.receivers += unit.count;
    load.seconds += info.stats.seconds_total;
}

bool is_cancel(const std::exception_ptr& e) {
    try {
        std::rethrow_exception(e);
    } catch (const Error& error) {
        return error.code() == ErrorCode::cancelled;
    } catch (...) {
        return false;
    }
}

// What a rank's part of the bake ended with.
struct RankOutcome {
    BakeStats stats;
    RankLoad load;
    std::vector<RankLoad> loads;  // rank 0: every rank's, by rank
    std::exception_ptr failure;
    bool user_cancelled = false;       // rank 0: its progress callback said stop
    std::uint64_t receivers_done = 0;  // rank 0: rows in the sink
    std::uint64_t bytes_gathered = 0;  // rank 0: rows received from the others...
    double seconds_gathered = 0;       // ...and the seconds they took
    double seconds_wall = 0;           // rank 0: first claim to the last row
};

// What every rank's part of the bake works from.
struct RankContext {
    const MpiSession& session;
    const BakeJob& job;
    const Prepared& p;
    const DistOptions& dist;
    const std::vector<WorkUnit>& units;
    UnitCounter& counter;
    TransferLayout layout;
};

// Rank 0: bakes its units, receives the others' rows into the sink, stops everyone on a failure.
struct Coordinator : RankContext {
    RankOutcome out{};  // failure: this rank's own (its bake, its sink)
    bool stopping = false;
    std::vector<bool> stop_sent{};
    int workers_done = 0;

    void send_stop(int rank, bool cancel) {
        if (stop_sent[std::size_t(rank)]) return;
        stop_sent[std::size_t(rank)] = true;
        const char flag = cancel ? 1 : 0;
        MPI_Send(&flag, 1, MPI_BYTE, rank, kTagStop, MPI_COMM_WORLD);
    }
    void stop_everyone() {
        if (stopping) return;
        stopping = true;
        counter.exhaust(units.size());
        for (int r = 1; r < session.size(); ++r) send_stop(r, true);
    }
    void fail_here(std::exception_ptr e) {
        if (!out.failure) out.failure = std::move(e);
        stop_everyone();
    }

    std::vector<float> scratch{};  // rows for a sink without host memory, or to drop

    // The rows of unit `index` that follow its index from `source`: straight into the sink's
    // host memory where it has some (no copy), else through `scratch`; dropped after a failure.
    // The message is always received (a sender must never wait forever), then checked.
    void receive_rows(int source, std::uint64_t index) {
        MPI_Status status;
        MPI_Probe(source, kTagRows, MPI_COMM_WORLD, &status);
        int sent = 0;
        MPI_Get_count(&status, MPI_FLOAT, &sent);
        const bool known = index < units.size();
        const std::size_t first = known ? job.receivers.first + units[index].first : 0;
        const std::size_t count = known ? units[index].count : 0;
        const bool fits = known && std::size_t(sent) == layout.floats(count);
        float* rows = fits && !out.failure ? job.sink->host_rows(first, count) : nullptr;
        if (rows == nullptr) {
            if (scratch.size() < std::size_t(sent)) scratch.resize(std::size_t(sent));
            rows = scratch.data();
        }
        MPI_Recv(rows, sent, MPI_FLOAT, source, kTagRows, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        SHPRT_CHECK(known, format, "rank {} sent unit {} of {}", source, index, units.size());
        SHPRT_CHECK(fits, format, "rank {} sent {} floats for unit {} ({} expected)", source, sent,
                    index, layout.floats(count));
        if (out.failure) return;
        job.sink->write(first, count, rows);
        out.receivers_done += count;
        out.bytes_gathered += std::size_t(sent) * sizeof(float);
    }

    void handle(const MPI_Status& status) {
        const auto start = Clock::now();
        std::vector<char> message = receive(status);
        if (status.MPI_TAG == kTagDone) {
            ++workers_done;
            std::size_t at = 1;
            RankLoad& load = out.loads[std::size_t(status.MPI_SOURCE)];
            load.units = take<std::uint64_t>(message, at);
            load.receivers = take<std::uint64_t>(message, at);
            load.seconds = take<double>(message, at);
            add_stats(out.stats, unpack(message, at));
            if (!message.empty() && message[0] != 0) stop_everyone();  // that worker failed
            return;
        }
        if (status.MPI_TAG != kTagUnit) return;
        try {
            std::size_t at = 0;
            receive_rows(status.MPI_SOURCE, take<std::uint64_t>(message, at));
            out.seconds_gathered += seconds_since(start);
        } catch (...) {
            fail_here(std::current_exception());
        }
    }
    void drain() {
        for (;;) {
            int pending = 0;
            MPI_Status status;
            MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &pending, &status);
            if (!pending) return;
            handle(status);
        }
    }
    bool report() {
        if (dist.progress && !out.user_cancelled &&
            !dist.progress({"bake", out.receivers_done, job.receivers.count, "receivers"})) {
            out.user_cancelled = true;
            stop_everyone();
        }
        return !stopping;
    }

    void run() {
        stop_sent.assign(std::size_t(session.size()), false);
        out.loads.assign(std::size_t(session.size()), RankLoad{});
        try {
            job.sink->begin(layout, job.receivers.first, job.receivers.count);
        } catch (...) {
            fail_here(std::current_exception());
        }
        UnitToSink sink(*job.sink);
        const auto start = Clock::now();
        while (!stopping) {
            const std::uint64_t index = counter.claim();
            if (index >= units.size()) break;
            try {
                const TransferInfo info = bake_unit(job, p, units[index], sink, [this](auto&) {
                    drain();
                    return report();
                });
                add_stats(out.stats, info.stats);
                count_unit(out.load, units[index], info);
                out.receivers_done += units[index].count;
                drain();
                report();
            } catch (...) {
                if (!(stopping && is_cancel(std::current_exception())))
                    fail_here(std::current_exception());
            }
        }
        for (int r = 1; r < session.size(); ++r) send_stop(r, false);  // no more units
        while (workers_done < session.size() - 1) {
            MPI_Status status;
            MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
            handle(status);
            report();
        }
        out.seconds_wall = seconds_since(start);
        if (!out.failure && !stopping) {
            try {
                job.sink->finish();
            } catch (...) {
                out.failure = std::current_exception();
            }
        }
    }
};

// Every other rank: claims units until none is left or rank 0 says stop, sends their rows.
struct Worker : RankContext {
    explicit Worker(const RankContext& context) : RankContext(context) {}

    RankOutcome out;
    std::optional<bool> stop;  // rank 0's stop message, once received: cancel (true) or finish

    struct InFlight {  // a unit's message: its index, then its rows, from one buffer
        std::vector<char> buffer;
        MPI_Request requests[2] = {MPI_REQUEST_NULL, MPI_REQUEST_NULL};
    };
    std::deque<InFlight> in_flight;

    void poll_stop(bool wait) {
        if (stop) return;
        int pending = 0;
        if (wait) {
            MPI_Probe(0, kTagStop, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            pending = 1;
        } else {
            MPI_Iprobe(0, kTagStop, MPI_COMM_WORLD, &pending, MPI_STATUS_IGNORE);
        }
        if (!pending) return;
        char flag = 0;
        MPI_Recv(&flag, 1, MPI_BYTE, 0, kTagStop, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        stop = flag != 0;
    }
    // Frees the sends that completed; with `limit`, waits until fewer than `limit` are left.
    void reap(std::size_t limit) {
        while (!in_flight.empty()) {
            int done = 0;
            MPI_Testall(2, in_flight.front().requests, &done, MPI_STATUSES_IGNORE);
            if (!done && in_flight.size() < limit) return;
            if (!done) MPI_Waitall(2, in_flight.front().requests, MPI_STATUSES_IGNORE);
            in_flight.pop_front();
        }
    }
    bool cancelled() const { return stop.value_or(false); }

    void run() {
        const auto limit = static_cast<std::size_t>(dist.units_in_flight);
        while (!stop) {
            poll_stop(false);
            if (stop) break;
            const std::uint64_t index = counter.claim();
            if (index >= units.size()) break;
            reap(limit);
            const WorkUnit& unit = units[index];
            UnitMessage message(index, layout, job.receivers.first + unit.first, unit.count);
            try {
                const TransferInfo info = bake_unit(job, p, unit, message, [this](auto&) {
                    reap(std::numeric_limits<std::size_t>::max());
                    poll_stop(false);
                    return !cancelled();
                });
                add_stats(out.stats, info.stats);
                count_unit(out.load, unit, info);
            } catch (...) {
                if (!(cancelled() && is_cancel(std::current_exception())))
                    out.failure = std::current_exception();
                break;
            }
            InFlight send{std::move(message.buffer())};
            const std::size_t header = sizeof(std::uint64_t);
            MPI_Isend(send.buffer.data(), int(header), MPI_BYTE, 0, kTagUnit, MPI_COMM_WORLD,
                      &send.requests[0]);
            MPI_Isend(send.buffer.data() + header,
                      as_count((send.buffer.size() - header) / sizeof(float)), MPI_FLOAT, 0,
                      kTagRows, MPI_COMM_WORLD, &send.requests[1]);
            in_flight.push_back(std::move(send));
        }
        reap(1);  // every row has arrived, then DONE (a failure stops the others at once)...
        std::vector<char> done{static_cast<char>(out.failure ? 1 : 0)};
        put(done, std::uint64_t(out.load.units));
        put(done, std::uint64_t(out.load.receivers));
        put(done, out.load.seconds);
        pack(done, out.stats);
        MPI_Send(done.data(), as_count(done.size()), MPI_BYTE, 0, kTagDone, MPI_COMM_WORLD);
        poll_stop(true);  // ...and rank 0's one stop message is received before the window goes
    }
};

}  // namespace

bool launched_by_mpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE",
                             "MPI_LOCALNRANKS", "MV2_COMM_WORLD_SIZE"})
        if (std::getenv(name) != nullptr) return true;
    return false;
}

namespace {
// The node's shared words of core/job.hpp (one MpiSession a process).
MPI_Win g_ended_window = MPI_WIN_NULL;
}  // namespace

MpiSession::MpiSession() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    SHPRT_CHECK(!initialised, unsupported, "MPI is already initialised (one MpiSession a process)");
    int provided = 0;
    SHPRT_CHECK(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) == MPI_SUCCESS,
                unsupported, "MPI failed to start (MPI_Init_thread)");
    if (provided < MPI_THREAD_FUNNELED) {
        MPI_Finalize();
        fail(ErrorCode::unsupported, "this MPI library gives no thread support (funneled needed)");
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m_size);
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, m_rank, MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &m_local_rank);
    // The processes of the ranks on this machine, for the signal handlers (core/job.hpp): a rank
    // that mpirun ends because another died can say which one did. Each has a word in a window of
    // memory the node's ranks share, where its handler records a signal it ends by.
    int node_size = 1;
    MPI_Comm_size(node, &node_size);
    const int mine[2] = {m_rank, static_cast<int>(::getpid())};
    std::vector<int> pairs(2 * std::size_t(node_size));
    MPI_Allgather(mine, 2, MPI_INT, pairs.data(), 2, MPI_INT, node);
    int* words = nullptr;
    if (MPI_Win_allocate_shared(MPI_Aint(sizeof(int)), int(sizeof(int)), MPI_INFO_NULL, node,
                                &words, &g_ended_window) != MPI_SUCCESS)
        g_ended_window = MPI_WIN_NULL;
    std::vector<JobRank> ranks(static_cast<std::size_t>(m_size));
    for (int i = 0; i < node_size; ++i) {
        const int rank = pairs[2 * std::size_t(i)];
        if (rank < 0 || rank >= m_size) continue;
        JobRank& r = ranks[std::size_t(rank)];
        r.pid = pairs[2 * std::size_t(i) + 1];
        MPI_Aint size = 0;
        int unit = 0;
        int* word = nullptr;
        if (g_ended_window != MPI_WIN_NULL &&
            MPI_Win_shared_query(g_ended_window, i, &size, &unit, &word) == MPI_SUCCESS &&
            size >= MPI_Aint(sizeof(int)))
            r.ended = word;
    }
    if (words != nullptr) *words = 0;
    MPI_Barrier(node);  // every word is 0 before any rank may read one
    set_job_ranks(m_rank, ranks);
    MPI_Comm_free(&node);
}

MpiSession::~MpiSession() {
    set_job_ranks(-1, {});  // from here a rank that finished may end before the others
    if (g_ended_window != MPI_WIN_NULL) MPI_Win_free(&g_ended_window);
    MPI_Finalize();
}

void MpiSession::barrier() const { MPI_Barrier(MPI_COMM_WORLD); }

void MpiSession::agree(const std::function<void()>& step) const {
    int code = -1;
    std::string message;
    try {
        step();
    } catch (const Error& e) {
        code = static_cast<int>(e.code());
        message = e.what();
    } catch (const std::bad_alloc&) {
        code = static_cast<int>(ErrorCode::out_of_memory);
        message = "out of memory";
    } catch (const std::exception& e) {
        code = static_cast<int>(ErrorCode::invalid_argument);
        message = e.what();
    }
    const int mine = code >= 0 ? m_rank : m_size;
    int lowest = m_size;
    MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (lowest == m_size) return;
    if (lowest != 0 && m_rank == lowest) {
        std::vector<char> out;
        put(out, code);
        out.insert(out.end(), message.begin(), message.end());
        MPI_Send(out.data(), as_count(out.size()), MPI_BYTE, 0, kTagError, MPI_COMM_WORLD);
    }
    if (lowest != 0 && m_rank == 0) {
        MPI_Status status;
        MPI_Probe(lowest, kTagError, MPI_COMM_WORLD, &status);
        const std::vector<char> in = receive(status);
        std::size_t at = 0;
        code = take<int>(in, at);
        message = fmt::format("rank {}: {}", lowest, std::string(in.begin() + 4, in.end()));
    }
    MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (m_rank == 0) throw Error(static_cast<ErrorCode>(code), message);
    throw PeerFailed(static_cast<ErrorCode>(code), fmt::format("rank {} failed", lowest));
}

void check_same_scene(const MpiSession& session, const Mesh& mesh) {
    const std::uint64_t hash = mesh_hash(mesh);
    std::vector<std::uint64_t> hashes(session.rank() == 0 ? std::size_t(session.size()) : 0);
    MPI_Gather(&hash, 1, MPI_UINT64_T, hashes.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    session.agree([&] {
        for (std::size_t r = 1; r < hashes.size(); ++r)
            SHPRT_CHECK(hashes[r] == hashes[0], invalid_argument,
                        "rank {} loaded a different scene from rank 0's {} (scene hash {} instead "
                        "of {})",
                        r, mesh.source, format_mesh_hash(hashes[r]), format_mesh_hash(hashes[0]));
    });
}

std::vector<WorkUnit> plan_units(std::size_t count, int ranks, std::size_t min_unit,
                                 std::size_t max_unit) {
    SHPRT_CHECK(ranks >= 1 && min_unit >= 1 && max_unit >= 1, invalid_argument,
                "plan_units: {} ranks, units of {} to {} receivers", ranks, min_unit, max_unit);
    const std::size_t share = 2 * std::size_t(ranks);
    std::vector<WorkUnit> units;
    for (std::size_t first = 0; first < count;) {
        const std::size_t remaining = count - first;
        std::size_t n = std::max(min_unit, (remaining + share - 1) / share);
        n = std::min({n, max_unit, remaining});
        units.push_back({first, n});
        first += n;
    }
    return units;
}

DistributedBake bake_distributed(const MpiSession& session, const BakeJob& job,
                                 const BakeOptions& options, const DistOptions& dist) {
    Prepared p;
    session.agree([&] {
        SHPRT_CHECK(!kind_row(options.transfer).whole_domain, unsupported,
                    "{} transfer cannot be shared between MPI ranks (its bounces couple every "
                    "vertex): bake it in one process",
                    to_string(options.transfer));
        prepare(session, job, options, dist, p);
    });

    TransferInfo info = bake_description(p.options);
    info.layout.domain = job.receivers.domain;
    info.samples = static_cast<int>(p.session->options().samples);
    const std::size_t row_bytes = info.layout.floats_per_receiver() * sizeof(float);
    const std::size_t max_unit = std::max<std::size_t>(1, kMaxUnitBytes / row_bytes);
    std::size_t min_unit = dist.min_unit;
    if (min_unit == 0) {
        const int threads = thread_count(p.options.threads);
        const std::size_t chunk =
            auto_chunk_receivers(job.receivers.count, p.session->options().samples);
        min_unit = std::max<std::size_t>(256, chunk * std::size_t(std::max(4, 2 * threads)));
    }
    const std::vector<WorkUnit> units =
        plan_units(job.receivers.count, session.size(), std::min(min_unit, max_unit), max_unit);

    RankOutcome out;
    {
        UnitCounter counter(session.rank());
        const RankContext context{session, job, p, dist, units, counter, info.layout};
        if (session.rank() == 0) {
            Coordinator c{context};
            c.run();
            out = std::move(c.out);
        } else {
            Worker w(context);
            w.run();
            out = std::move(w.out);
        }
    }  // the counter's window is freed collectively: every rank is past its loop
    BakeStats& stats = out.stats;
    session.agree([&] {
        if (out.failure) std::rethrow_exception(out.failure);
        SHPRT_CHECK(!out.user_cancelled, cancelled, "bake cancelled after {} of {} receivers",
                    out.receivers_done, job.receivers.count);
    });

    // Every rank returns the combined stats (rank 0 has them; workers sent theirs with DONE).
    DistributedBake result;
    std::vector<char> packed;
    if (session.rank() == 0) {
        stats.device_name = fmt::format("{} rank{}: {}", session.size(),
                                        session.size() == 1 ? "" : "s", stats.device_name);
        pack(packed, stats);
        result.ranks = std::move(out.loads);
        result.ranks[0] = out.load;
        result.bytes_gathered = out.bytes_gathered;
        result.seconds_gathered = out.seconds_gathered;
        result.seconds_wall = out.seconds_wall;
    }
    int bytes = static_cast<int>(packed.size());
    MPI_Bcast(&bytes, 1, MPI_INT, 0, MPI_COMM_WORLD);
    packed.resize(std::size_t(bytes));
    MPI_Bcast(packed.data(), bytes, MPI_BYTE, 0, MPI_COMM_WORLD);
    info.stats = unpack(packed, 0);
    result.info = std::move(info);
    return result;
}

}  // namespace shprt::dist
