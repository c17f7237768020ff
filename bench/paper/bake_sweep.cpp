// Bake-sweep stage of the paper study (bake_sweep.hpp).
#include "paper/bake_sweep.hpp"

#include "shprt/bake/gpu.hpp"
#include "shprt/core/error.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace shprt::paper {

Devices choose_devices(const Options& o) {
    const GpuInfo gpu = query_gpu();
    Devices d;
    d.cpu = o.device != "cuda";
    d.gpu = o.device == "cuda" || o.device == "both";
    SHPRT_CHECK(!d.gpu || gpu.available, unsupported, "bench paper: --device {}: {}", o.device,
                gpu.reason);
    if (o.device == "auto" && gpu.available) d.gpu = true;
    d.gpu_description = gpu.available ? gpu.name : "no GPU (" + gpu.reason + ")";
    return d;
}

std::vector<int> table_sizes(bool extended) {
    std::vector<int> Ks = {32, 48, 64, 128, 256};
    if (extended)
        for (int n : {4, 5, 6, 7, 8, 10, 12, 14, 16, 20, 24, 28, 32}) Ks.push_back(n * n);
    std::sort(Ks.begin(), Ks.end());
    Ks.erase(std::unique(Ks.begin(), Ks.end()), Ks.end());
    return Ks;
}

BakeOptions bake_options(const Options& o, int K, Device device) {
    BakeOptions b;
    b.K = K;
    b.samples = o.samples;
    b.sampler = o.sampler;
    b.seed = o.seed;
    b.threads = o.threads;
    b.device = device;
    b.direction_frame = DirectionFrame::sphere;  // the paper's method: one set on the sphere
    return b;
}

RowBakes bake_row(const Mesh& mesh, const Options& o, const Devices& devices, KRow& row,
                  const StageLog& stage) {
    const int K = row.K;
    RowBakes out;
    TransferSet& t = out.paper;
    if (devices.cpu) {
        stage.say(fmt::format("K = {}: CPU bake, S = {} ({})", K, o.samples, to_string(o.sampler)));
        BakeOptions b = bake_options(o, K, Device::cpu);
        Task task(stage, "bake");
        b.progress = task.progress();
        t = bake(mesh, b);
        task.end();
        row.cpu = {true, t.stats};
    }
    if (devices.gpu) {
        stage.say(fmt::format("K = {}: GPU bake, S = {}", K, o.samples));
        TransferSet g = bake(mesh, bake_options(o, K, Device::cuda));
        row.gpu = {true, g.stats};
        if (!devices.cpu) t = std::move(g);
    }
    // The improved method: same S, low-discrepancy directions.
    stage.say(fmt::format("K = {}: improved bake, S = {} ({})", K, o.samples,
                          to_string(kImprovedSampler)));
    BakeOptions b = bake_options(o, K, devices.cpu ? Device::cpu : Device::cuda);
    b.sampler = kImprovedSampler;
    Task task(stage, "bake");
    b.progress = task.progress();
    out.improved = bake(mesh, b);
    task.end();
    row.improved = {true, out.improved.stats};
    return out;
}

}  // namespace shprt::paper
