// A bake request across MPI ranks (dist/mpi_request.hpp).
#include "shprt/dist/mpi_request.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/timer.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <memory>
#include <optional>

namespace shprt::dist {

DistributedResult run(const MpiSession& session, const BakeRequest& request, const Mesh& mesh,
                      std::size_t min_unit) {
    const bool root = session.rank() == 0;
    session.agree([&] {
        SHPRT_CHECK(request.distributed, invalid_argument,
                    "dist::run: the request is not marked distributed");
        check(request);
    });
    check_same_scene(session, mesh);
    DistributedResult out;
    std::optional<Receivers> receivers;
    std::unique_ptr<BakeOutput> output;
    session.agree([&] {
        WriteOptions write;
        receivers = request_receivers(request, mesh, write);
        if (root) output = std::make_unique<BakeOutput>(request, mesh, *receivers, write);
    });
    DistOptions dist;
    dist.min_unit = min_unit;
    if (root) dist.progress = request.options.progress;
    BakeOptions options = request.options;
    options.progress = {};
    const BakeJob job{&mesh, *receivers, root ? &output->sink() : nullptr, nullptr, nullptr};
    const auto start = Clock::now();
    out.ranks = bake_distributed(session, job, options, dist);
    out.result.seconds_bake = seconds_since(start);
    out.result.info = out.ranks.info;
    out.result.first = receivers->first;
    out.result.receivers = receivers->count;
    session.agree([&] {
        if (root) out.result.seconds_write = output->finish(out.ranks.info, out.result);
    });
    if (request.output)
        out.result.info.layout.encoding = request.output->encoding.value_or(TransferEncoding::f32);
    return out;
}

std::string rank_loads_summary(const DistributedBake& result) {
    std::vector<std::size_t> receivers, units;
    double least = 0, most = 0;
    for (std::size_t r = 0; r < result.ranks.size(); ++r) {
        const RankLoad& load = result.ranks[r];
        receivers.push_back(load.receivers);
        units.push_back(load.units);
        least = r == 0 ? load.seconds : std::min(least, load.seconds);
        most = std::max(most, load.seconds);
    }
    return fmt::format(
        "ranks: receivers {} (units {}), busy {:.3f} s to {:.3f} s of {:.3f} s; gathered {:.3f} "
        "GiB in {:.3f} s\n",
        fmt::join(receivers, " "), fmt::join(units, " "), least, most, result.seconds_wall,
        double(result.bytes_gathered) / double(1u << 30), result.seconds_gathered);
}

}  // namespace shprt::dist
