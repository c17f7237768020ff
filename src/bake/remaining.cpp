#include "shprt/bake/remaining.hpp"

#include "shprt/bake/session.hpp"
#include "shprt/core/error.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <memory>

namespace shprt {

std::optional<std::string> resume_unsupported(const BakeOptions& options) {
    if (!kind_row(options.transfer).whole_domain) return std::nullopt;
    return fmt::format(
        "{} transfer cannot be checkpointed or resumed (its bounces need every vertex's rows at "
        "once); bake it without --checkpoint",
        to_string(options.transfer));
}

TransferInfo bake_remaining(const BakeJob& job, const BakeOptions& options,
                            const std::vector<ReceiverSpan>& done) {
    SHPRT_CHECK(job.sink != nullptr && job.occluders != nullptr, invalid_argument,
                "bake: a job needs occluders and a sink");
    if (const auto why = resume_unsupported(options)) fail(ErrorCode::unsupported, "{}", *why);
    SHPRT_CHECK(job.probes == nullptr, unsupported,
                "--checkpoint: a bake with probes cannot be checkpointed yet (its gaps would each "
                "bake the probes); bake without --checkpoint");
    const Receivers& all = job.receivers;
    const std::vector<ReceiverSpan> gaps = remaining_spans(all.first, all.count, done);
    if (gaps.empty()) {
        const TransferInfo description = bake_description(options);
        job.sink->begin(description.layout, all.first, all.count);
        job.sink->finish();
        return description;
    }
    std::size_t left = 0;
    for (const ReceiverSpan& g : gaps) left += g.count;

    // One session for every gap: the set, its tables and the tracer are built once.
    BakeSession session(job, options);
    BakeJob part = job;

    TransferInfo info;
    BakeStats sum;
    std::size_t receivers_before = all.count - left;  // done receivers, then the gaps baked
    for (const ReceiverSpan& gap : gaps) {
        ProgressFn progress;
        if (options.progress) {
            // This gap's report, as one of the whole range: the rays of the receivers done before
            // it are estimated at this gap's rate per receiver.
            progress = [&, gap](const ProgressInfo& p) {
                ProgressInfo whole = p;
                const double per_receiver = double(p.total) / double(gap.count);
                whole.total = static_cast<std::uint64_t>(per_receiver * double(all.count));
                whole.done =
                    p.done + static_cast<std::uint64_t>(per_receiver * double(receivers_before));
                return options.progress(whole);
            };
        }
        part.receivers = all.range(gap.first, gap.count);
        info = session.bake(part, progress);
        receivers_before += gap.count;
        add_stats(sum, info.stats);
    }
    info.stats = sum;
    return info;
}

}  // namespace shprt
