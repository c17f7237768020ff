#include "common/resumable_bake.hpp"

#include "common/command.hpp"
#include "common/signals.hpp"

#include "shprt/bake/interreflect.hpp"
#include "shprt/bake/remaining.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/memory.hpp"
#include "shprt/core/parse.hpp"

#include <fmt/format.h>

#include <cmath>

namespace shprt::tools {
namespace {

std::string format_bytes(std::uint64_t bytes) {
    const double b = double(bytes);
    if (b >= double(1ull << 30)) return fmt::format("{:.2f} GiB", b / double(1ull << 30));
    if (b >= double(1ull << 20)) return fmt::format("{:.1f} MiB", b / double(1ull << 20));
    return fmt::format("{:.0f} KiB", std::ceil(b / 1024.0));
}

const std::string& checkpoint_path(const ResumableArgs& args) {
    return args.resume.empty() ? args.checkpoint : args.resume;
}

}  // namespace

void add_resumable_options(CLI::App& app, ResumableArgs& args) {
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

void check_resumable_args(const ResumableArgs& args, const BakeOptions& options,
                          const std::string& output, const std::string& other_refusal) {
    std::uint64_t bytes = 0;
    SHPRT_CHECK(args.max_memory.empty() || (parse_byte_size(args.max_memory, bytes) && bytes > 0),
                invalid_argument,
                "--max-memory '{}': expected a size such as 512M or 4G (bytes, K, M, G or T)",
                args.max_memory);
    SHPRT_CHECK(std::isfinite(args.checkpoint_every) && args.checkpoint_every >= 0,
                invalid_argument, "--checkpoint-every {}: expected seconds, 0 or more",
                args.checkpoint_every);
    const std::string& path = checkpoint_path(args);
    if (path.empty()) return;
    const char* option = args.resume.empty() ? "--checkpoint" : "--resume";
    SHPRT_CHECK(other_refusal.empty(), unsupported, "{}: {}", option, other_refusal);
    if (const auto why = resume_unsupported(options))
        fail(ErrorCode::unsupported, "{}: {}", option, *why);
    SHPRT_CHECK(path != output && !same_file(path, output), invalid_argument,
                "{} {}: the checkpoint cannot be the output file", option, path);
}

std::uint64_t check_bake_memory(const ResumableArgs& args, const BakeJob& job,
                                const BakeOptions& options, bool rows_in_memory) {
    const std::uint64_t need =
        estimate_bake_peak_bytes(job.occluders->triangle_count(), job.receivers.count, options,
                                 rows_in_memory, bake_bounce_source_count(*job.occluders, options));
    std::uint64_t limit = 0;
    if (!args.max_memory.empty() && parse_byte_size(args.max_memory, limit)) {
        SHPRT_CHECK(need <= limit, out_of_memory,
                    "this bake needs about {} of memory (estimated: BVH, rows and per-thread "
                    "buffers), more than --max-memory {}; lower --samples or --coeffs, bake with "
                    "--stream or in --shard parts",
                    format_bytes(need), args.max_memory);
        return limit;
    }
    limit = available_memory_bytes();
    SHPRT_CHECK(limit == 0 || need <= limit, out_of_memory,
                "this bake needs about {} of memory (estimated: BVH, rows and per-thread "
                "buffers), more than the {} this machine has available; lower --samples or "
                "--coeffs, bake with --stream or in --shard parts",
                format_bytes(need), format_bytes(limit));
    return limit;
}

ResumableBake::ResumableBake(const ResumableArgs& args, const BakeJob& job,
                             const BakeOptions& options)
    : m_job(job), m_options(options) {
    const std::string& path = checkpoint_path(args);
    if (path.empty()) return;
    const TransferInfo description = bake_description(options);
    const std::uint64_t fingerprint = checkpoint_fingerprint(*job.occluders, job.receivers.first,
                                                             job.receivers.count, description);
    const std::size_t floats = description.layout.floats_per_receiver();
    if (args.resume.empty())
        m_file.emplace(CheckpointFile::create(path, fingerprint, job.receivers.first,
                                              job.receivers.count, floats, args.checkpoint_every));
    else
        m_file.emplace(CheckpointFile::resume(path, fingerprint, job.receivers.first,
                                              job.receivers.count, floats, args.checkpoint_every));
    m_sink = std::make_unique<CheckpointSink>(*job.sink, *m_file);
}

ResumableBake::~ResumableBake() = default;

TransferInfo ResumableBake::run() {
    if (!m_file) return bake(m_job, m_options);
    BakeJob job = m_job;
    job.sink = m_sink.get();
    const std::vector<ReceiverSpan> done = m_file->done();
    try {
        return bake_remaining(job, m_options, done);
    } catch (const Error& e) {
        if (e.code() != ErrorCode::cancelled || !interrupted()) throw;
        m_file->sync();
        const int signal = interrupt_signal();
        const std::string line = fmt::format(
            "interrupted by {}; {} of {} receivers are saved in {}: to continue, run the same "
            "command with --resume {} in place of --checkpoint (no output was written)",
            signal_name(signal), m_file->done_receivers(), m_file->count(), m_file->path(),
            m_file->path());
        print_error(line.c_str());
        throw ExitQuietly{interrupted_exit_code(signal)};
    }
}

void ResumableBake::remove_checkpoint() {
    if (m_file) m_file->remove();
}

}  // namespace shprt::tools
