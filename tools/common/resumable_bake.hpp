// What keeps a long `shprt bake` safe (README, "What is guaranteed"): its memory checked before
// any tracing (--max-memory, else the machine's MemAvailable), and its checkpoint
// (--checkpoint F.ckpt [--checkpoint-every SECONDS], --resume F.ckpt: io/checkpoint.hpp), which
// a SIGINT or SIGTERM flushes before the process says how to resume and exits 130 or 143.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/io/checkpoint.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>

namespace shprt::tools {

struct ResumableArgs {
    std::string checkpoint, resume;  // paths, or empty
    double checkpoint_every = 30;    // seconds between syncs of the checkpoint to disk
    std::string max_memory;          // a size (parse_byte_size), or empty: MemAvailable
};

// Adds --checkpoint, --checkpoint-every, --resume and --max-memory.
void add_resumable_options(CLI::App& app, ResumableArgs& args);

// Checks the options against the bake before any work: one-line Error(invalid_argument) for a bad
// --max-memory or --checkpoint-every, Error(unsupported) for a checkpoint of a bake that cannot
// resume (bake/remaining.hpp: resume_unsupported), for the checkpoint file being the output, or
// `other_refusal` when it is not empty (what the caller's own modes rule out, e.g. MPI).
void check_resumable_args(const ResumableArgs& args, const BakeOptions& options,
                          const std::string& output, const std::string& other_refusal = {});

// Refuses (Error(out_of_memory), one line with the estimate) a bake whose estimated peak memory
// (estimate_bake_peak_bytes) exceeds --max-memory, or else the memory the machine has available.
// Returns that budget (0 when the available memory cannot be read): the bake's
// BakeOptions::memory_budget, against which an interreflected bake counts its operator.
std::uint64_t check_bake_memory(const ResumableArgs& args, const BakeJob& job,
                                const BakeOptions& options, bool rows_in_memory);

// bake(job, options), with the checkpoint when one was asked for: a new one, or the one
// --resume names (whose rows are not baked again). On success the checkpoint file is removed by
// remove_checkpoint(), once the output is in place. When a signal cancels the bake, the
// checkpoint is synced and the one line says how many receivers it holds and how to resume
// (ExitQuietly with 128 + the signal).
class ResumableBake {
public:
    ResumableBake(const ResumableArgs& args, const BakeJob& job, const BakeOptions& options);
    ~ResumableBake();
    TransferInfo run();
    void remove_checkpoint();

private:
    BakeJob m_job;
    const BakeOptions& m_options;
    std::optional<CheckpointFile> m_file;
    std::unique_ptr<CheckpointSink> m_sink;
};

}  // namespace shprt::tools
