// The bake request's options as the front ends take them (core/options.hpp): the receivers
// (ReceiverChoice, request.hpp: `--domain`, `--resolution`, ... `--shard`), the output file's flags
// (FileChoice: `--half`, `--stream`, `--reproducible`) and the checkpoint and
// memory limit (CheckpointChoice: `--checkpoint`, `--resume`, `--checkpoint-every`,
// `--max-memory`), one table each. `shprt bake` registers its options by walking them; Python's
// shprt.bake takes its keywords' defaults from the same structs. The bake options themselves are
// bake_option_table.hpp's.
//
// What keeps a long bake safe (README, "What is guaranteed"): its memory checked before any
// tracing (max_memory, else the machine's MemAvailable), and its checkpoint (io/checkpoint.hpp),
// which a SIGINT or SIGTERM flushes before the shell says how to resume (resume_hint).
#pragma once

#include "shprt/bake/request.hpp"
#include "shprt/core/options.hpp"

#include <string>
#include <vector>

namespace shprt {

// One row per receiver option, in the command line's help order.
const std::vector<OptionRow<ReceiverChoice>>& receiver_option_table();

// The output file's flags (`--half`, `--stream`, `--reproducible`).
struct FileChoice {
    bool half = false, stream = false, reproducible = false;
};
// One row per option, in the command line's help order.
const std::vector<OptionRow<FileChoice>>& file_option_table();
// The file output at `path` the flags describe; `float32` (ReceiverChoice::float32) stores texel
// coefficients as float32 (and wins over `half`).
FileOutput file_output_from(std::string path, const FileChoice& choice, bool float32);

struct CheckpointChoice {
    std::string checkpoint, resume;  // paths, or empty
    double checkpoint_every = 30;    // seconds between syncs of the checkpoint to disk
    std::string max_memory;          // a size (parse_byte_size: 512M, 4G), or empty: MemAvailable
};
// One row per option, in the command line's help order.
const std::vector<OptionRow<CheckpointChoice>>& checkpoint_option_table();

// request.max_memory from `text` (parse_byte_size); one-line Error(invalid_argument) naming the
// option as `spelling` writes it for a text that is not a size > 0. Nothing for an empty text.
void apply_max_memory(const std::string& text, BakeRequest& request, Spelling spelling);
// The request's checkpoint and memory limit from the choice (checkpoint and resume both given is
// the front end's to refuse).
void apply_checkpoint_choice(const CheckpointChoice& choice, BakeRequest& request,
                             Spelling spelling);

// The line for a checkpointed bake that stopped with rows saved (`kept`): cancelled by `signal`
// (nullptr: it failed, e.g. on a full disk), what the checkpoint holds, and how to resume (the
// command line's --resume).
std::string resume_hint(const CheckpointKept& kept, const char* signal);

}  // namespace shprt
