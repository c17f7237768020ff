// `shprt bake`'s checkpoint and memory options (checkpoint_options.hpp).
#include "common/checkpoint_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"

#include <fmt/format.h>

namespace shprt::tools {

void add_checkpoint_options(CLI::App& app, CheckpointArgs& args) {
    auto* checkpoint = app.add_option(
        "--checkpoint", args.checkpoint,
        "Keep the finished rows in this file as the bake goes, so that a killed bake can "
        "continue with --resume (removed when the output is written)");
    auto* resume = app.add_option("--resume", args.resume,
                                  "Continue the bake whose checkpoint is this file (same scene "
                                  "and options): the result is the uninterrupted bake's, bit "
                                  "for bit");
    checkpoint->excludes(resume);
    app.add_option("--checkpoint-every", args.checkpoint_every,
                   "Seconds between syncs of the checkpoint to disk (default 30; every finished "
                   "chunk is written at once, which a killed process does not lose)");
    app.add_option("--max-memory", args.max_memory,
                   "Refuse the bake when its estimated peak memory exceeds this size (512M, "
                   "4G, ...; default: the memory the machine has available)");
}

void apply_checkpoint_options(const CheckpointArgs& args, BakeRequest& request) {
    if (!args.max_memory.empty())
        SHPRT_CHECK(parse_byte_size(args.max_memory, request.max_memory) && request.max_memory > 0,
                    invalid_argument,
                    "--max-memory '{}': expected a size such as 512M or 4G (bytes, K, M, G or T)",
                    args.max_memory);
    const bool resume = !args.resume.empty();
    if (args.checkpoint.empty() && !resume) return;
    request.checkpoint =
        CheckpointRequest{resume ? args.resume : args.checkpoint, resume, args.checkpoint_every};
}

std::string resume_hint(const CheckpointKept& kept, const char* signal) {
    if (signal)
        return fmt::format(
            "interrupted by {}; {} of {} receivers are saved in {}: to continue, run the same "
            "command with --resume {} in place of --checkpoint (no output was written)",
            signal, kept.done, kept.count, kept.path, kept.path);
    return fmt::format(
        "{}: to continue once that is fixed, run the same command with --resume {} in place of "
        "--checkpoint (no output was written)",
        kept.what(), kept.path);
}

}  // namespace shprt::tools
