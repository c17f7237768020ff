// The checkpoint of a bake (`shprt bake --checkpoint F.ckpt`, `--resume F.ckpt`): the rows of
// the chunks that are finished, appended to a file as they finish, so that a bake killed at any
// moment (SIGKILL included) continues from them and ends in the same bits as an uninterrupted
// bake (bake/remaining.hpp, bake_remaining).
//
// The file (little-endian):
//   header, 64 bytes: "SHPRTCKP", u32 version (1), u32 header size (64), u64 fingerprint (what
//     bake this is: checkpoint_fingerprint), u64 first receiver, u64 receiver count, u64 floats
//     per receiver, u64 0, u32 0, u32 CRC-32 of bytes 0..59;
//   records, each a 32-byte head — u32 "CKRC", u32 CRC-32 of the rows, u64 first receiver, u64
//     count, u32 0, u32 CRC-32 of head bytes 0..27 — then count × floats-per-receiver float32.
// The header is written whole and renamed into place (AtomicFile); a record is one write(2). A
// record cut short by a kill, or any damage, ends the file: resuming keeps the records before it
// and cuts the rest off. The file is synced to disk (fdatasync) every `sync_seconds`, which
// bounds what a crash of the machine (not of the process) can lose.
#pragma once

#include "shprt/transfer/sink.hpp"
#include "shprt/transfer/transfer.hpp"

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace shprt {

struct Mesh;

// What identifies a bake: the occluder mesh (mesh_hash), the receiver range [first, first +
// count), and the description (kind, layout, sampler, samples, seed). A checkpoint is resumed
// only by the same bake.
std::uint64_t checkpoint_fingerprint(const Mesh& occluders, std::size_t first, std::size_t count,
                                     const TransferInfo& description);

class CheckpointFile {
public:
    // A new checkpoint for rows of receivers [first, first + count), `floats_per_receiver` floats
    // each. Error(invalid_argument) when `path` exists ("a checkpoint exists: continue it with
    // --resume"), Error(io) when it cannot be written.
    static CheckpointFile create(const std::string& path, std::uint64_t fingerprint,
                                 std::size_t first, std::size_t count,
                                 std::size_t floats_per_receiver, double sync_seconds);
    // An existing checkpoint, to continue: Error(io) when it cannot be read, Error(format) when it
    // is not a checkpoint, Error(invalid_argument) when it belongs to another bake (a different
    // scene, receivers or options). A damaged or cut-off tail is dropped (the file is truncated
    // after the last whole record).
    static CheckpointFile resume(const std::string& path, std::uint64_t fingerprint,
                                 std::size_t first, std::size_t count,
                                 std::size_t floats_per_receiver, double sync_seconds);

    CheckpointFile(CheckpointFile&& other) noexcept;
    CheckpointFile& operator=(CheckpointFile&&) = delete;
    CheckpointFile(const CheckpointFile&) = delete;
    ~CheckpointFile();

    const std::string& path() const { return m_path; }
    std::size_t first() const { return m_first; }
    std::size_t count() const { return m_count; }
    // The receivers whose rows are in the file (those found by resume(), and those appended).
    const std::vector<ReceiverSpan>& done() const { return m_done; }
    std::size_t done_receivers() const;

    // Appends the rows of receivers [first, first + count) as one record; thread-safe. Throws
    // Error(io) when the write fails.
    void append(std::size_t first, std::size_t count, const float* rows);
    // Writes the rows of every record found by resume() to `sink` (write() calls).
    void replay(TransferSink& sink) const;
    // fdatasync now; throws Error(io) when it fails.
    void sync();
    // Closes and removes the file (after the bake's output is in place).
    void remove();

private:
    CheckpointFile() = default;
    struct Record {
        std::uint64_t offset;  // of the rows
        ReceiverSpan span;
    };
    std::string m_path;
    int m_fd = -1;
    std::size_t m_first = 0, m_count = 0, m_floats = 0;
    double m_sync_seconds = 0;
    std::vector<Record> m_found;  // resume(): the records already in the file
    std::vector<ReceiverSpan> m_done;
    mutable std::mutex m_mutex;
    std::chrono::steady_clock::time_point m_last_sync;
};

// A sink that keeps a checkpoint: every write() goes to `inner` and is appended to `file`. The
// first begin() begins `inner` on the checkpoint's whole range and replays the rows the file
// already holds; later begin() calls (a bake_remaining gap each) only check their range.
// finish() reaches `inner` once every receiver of the range is done.
class CheckpointSink final : public TransferSink {
public:
    CheckpointSink(TransferSink& inner, CheckpointFile& file) : m_inner(inner), m_file(file) {}
    void begin(const TransferLayout& layout, std::size_t first, std::size_t count) override;
    float* host_rows(std::size_t first, std::size_t count) override {
        return m_inner.host_rows(first, count);
    }
    void write(std::size_t first, std::size_t count, const float* rows) override;
    void finish() override;

private:
    TransferSink& m_inner;
    CheckpointFile& m_file;
    bool m_begun = false, m_finished = false;
};

}  // namespace shprt
