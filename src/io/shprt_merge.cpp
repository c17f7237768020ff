// Joining the parts of a sharded bake (shprt_file.hpp merge_shprt_parts): `shprt bake --shard
// i/n` writes receivers [⌊V·i/n⌋, ⌊V·(i+1)/n⌋); the rows of a sub-range are exactly those of the
// whole bake (bake.hpp, "Determinism"), so concatenating the parts in receiver order is the whole
// bake, bit for bit.
#include "shprt/core/error.hpp"
#include "shprt/io/hash.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/transfer/sink.hpp"

#include <algorithm>
#include <numeric>

namespace shprt {
namespace {

// The part's description that must agree with the first part's; "" when it does.
std::string difference(const TransferSet& a, const TransferSet& b) {
    if (a.kind != b.kind)
        return fmt::format("transfer {} instead of {}", to_string(b.kind), to_string(a.kind));
    if (!(a.layout == b.layout))
        return fmt::format("layout K = {}, {} channel(s), {} {} instead of K = {}, {}, {} {}",
                           b.layout.K, b.layout.channels, to_string(b.layout.shape),
                           to_string(b.layout.encoding), a.layout.K, a.layout.channels,
                           to_string(a.layout.shape), to_string(a.layout.encoding));
    if (a.sampler != b.sampler || a.samples != b.samples || a.seed != b.seed ||
        a.direction_frame != b.direction_frame || a.target_error != b.target_error)
        return fmt::format("sampling {} ({}) S = {} seed {} instead of {} ({}) S = {} seed {}",
                           to_string(b.sampler), to_string(b.direction_frame), b.samples, b.seed,
                           to_string(a.sampler), to_string(a.direction_frame), a.samples, a.seed);
    if (a.receiver_samples.empty() != b.receiver_samples.empty())
        return "per-receiver sample counts in one part and not the other";
    return {};
}

}  // namespace

ShprtFile merge_shprt_parts(std::vector<ShprtFile> parts, const std::vector<std::string>& names) {
    SHPRT_CHECK(!parts.empty(), invalid_argument, "merge: no parts given");
    SHPRT_CHECK(names.size() == parts.size(), invalid_argument, "merge: {} names for {} parts",
                names.size(), parts.size());
    // Shards have no probes (`shprt bake --probes` refuses --shard): a part with probes is a
    // whole bake's file, and merging would drop or duplicate its grid.
    for (std::size_t i = 0; i < parts.size(); ++i)
        SHPRT_CHECK(parts[i].transfer.probes.empty(), invalid_argument,
                    "{}: has transfer probes, which no part of a sharded bake has (merge the "
                    "parts of `shprt bake --shard`)",
                    names[i]);
    const std::string hash = format_mesh_hash(mesh_hash(parts[0].mesh));
    for (std::size_t i = 1; i < parts.size(); ++i) {
        SHPRT_CHECK(format_mesh_hash(mesh_hash(parts[i].mesh)) == hash, invalid_argument,
                    "{}: a different scene than {} (scene hash {} instead of {})", names[i],
                    names[0], format_mesh_hash(mesh_hash(parts[i].mesh)), hash);
        // Not hashed, so compared here: the whole file gets one part's.
        SHPRT_CHECK(parts[i].mesh.brdfs == parts[0].mesh.brdfs &&
                        parts[i].mesh.brdf_index == parts[0].mesh.brdf_index,
                    invalid_argument, "{}: other material BRDFs than {} ({} against {})", names[i],
                    names[0], describe_brdfs(parts[i].mesh), describe_brdfs(parts[0].mesh));
        const std::string diff = difference(parts[0].transfer, parts[i].transfer);
        SHPRT_CHECK(diff.empty(), invalid_argument, "{}: not a part of the same bake as {}: {}",
                    names[i], names[0], diff);
    }
    // In receiver order; the ranges must tile [0, V): every receiver once (order_spans, the
    // check a checkpoint's records get too), none left out.
    std::vector<ReceiverSpan> spans;
    for (const ShprtFile& p : parts)
        spans.push_back({p.receiver_first, p.transfer.receiver_count()});
    const SpanOrder sorted = order_spans(spans);
    if (sorted.overlap) {
        const auto [a, b] = *sorted.overlap;
        fail(ErrorCode::invalid_argument,
             "{}: receivers [{}, {}) overlap the part before it (which ends at {})", names[b],
             spans[b].first, spans[b].first + spans[b].count, spans[a].first + spans[a].count);
    }
    const std::vector<std::size_t>& order = sorted.order;
    const std::size_t V = parts[0].mesh.vertex_count();
    std::size_t next = 0;
    for (std::size_t i : order) {
        const std::size_t first = parts[i].receiver_first;
        const std::size_t end = first + parts[i].transfer.receiver_count();
        SHPRT_CHECK(first == next, invalid_argument,
                    "merge: receivers [{}, {}) are in no part (the next part, {}, starts at {})",
                    next, first, names[i], first);
        next = end;
    }
    SHPRT_CHECK(next == V, invalid_argument,
                "merge: receivers [{}, {}) are in no part (the scene has {})", next, V, V);

    ShprtFile out;
    out.mesh = std::move(parts[order[0]].mesh);
    static_cast<TransferInfo&>(out.transfer) = parts[order[0]].transfer;
    out.transfer.coeffs.reserve(out.transfer.layout.floats(V));
    BakeStats& st = out.transfer.stats;
    st = BakeStats{};
    for (std::size_t i : order) {
        const TransferSet& t = parts[i].transfer;
        out.transfer.coeffs.insert(out.transfer.coeffs.end(), t.coeffs.begin(), t.coeffs.end());
        out.transfer.receiver_samples.insert(out.transfer.receiver_samples.end(),
                                             t.receiver_samples.begin(), t.receiver_samples.end());
        out.transfer.receiver_error.insert(out.transfer.receiver_error.end(),
                                           t.receiver_error.begin(), t.receiver_error.end());
        add_stats(st, t.stats);
        parts[i].transfer.coeffs = {};  // release as we go
    }
    st.device_name =
        fmt::format("{} part{}: {}", parts.size(), parts.size() == 1 ? "" : "s", st.device_name);
    return out;
}

}  // namespace shprt
