// What keeps a long `shprt bake` safe (README, "What is guaranteed"): its memory checked before
// any tracing (--max-memory, else the machine's MemAvailable), and its checkpoint
// (--checkpoint F.ckpt [--checkpoint-every SECONDS], --resume F.ckpt: io/checkpoint.hpp), which
// a SIGINT or SIGTERM flushes before the process says how to resume and exits 130 or 143. The
// request (bake/request.hpp) does both; these options only fill it in.
#pragma once

#include "shprt/bake/request.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace shprt::tools {

struct CheckpointArgs {
    std::string checkpoint, resume;  // paths, or empty
    double checkpoint_every = 30;    // seconds between syncs of the checkpoint to disk
    std::string max_memory;          // a size (parse_byte_size), or empty: MemAvailable
};

// Adds --checkpoint, --checkpoint-every, --resume and --max-memory.
void add_checkpoint_options(CLI::App& app, CheckpointArgs& args);

// The request's checkpoint and memory limit from the options (one-line Error(invalid_argument)
// for a bad --max-memory).
void apply_checkpoint_options(const CheckpointArgs& args, BakeRequest& request);

// The line for a checkpointed bake that stopped with rows saved (`kept`): cancelled by `signal`
// (nullptr: it failed, e.g. on a full disk), what the checkpoint holds, and how to resume.
std::string resume_hint(const CheckpointKept& kept, const char* signal);

}  // namespace shprt::tools
