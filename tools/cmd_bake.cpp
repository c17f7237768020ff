// `shprt bake SCENE -o OUT.shprt [options]`: load a scene, bake per-vertex SH transfer, write a
// .shprt file. Thin: it checks the options (one-line errors before any work), calls load_scene,
// bake and write_shprt, draws the progress bar and prints a one-line summary on stdout.
#include "common/bake_options.hpp"
#include "common/command.hpp"
#include "common/progress_bar.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_stream.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/sh/basis.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

namespace shprt::tools {
namespace {

using Clock = std::chrono::steady_clock;

struct BakeArgs {
    std::string scene, output;
    BakeOptionArgs bake;  // common/bake_options.hpp, shared with `shprt view --bake`
    bool half = false;
    std::string shard;  // "I/N", or empty
    bool stream = false;
};

// "I/N" with 0 ≤ I < N: shard I of N.
std::pair<std::size_t, std::size_t> parse_shard(const std::string& text) {
    const std::size_t slash = text.find('/');
    unsigned long long i = 0, n = 0;
    const auto number = [](const std::string& s, unsigned long long& v) {
        if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 9)
            return false;
        v = std::stoull(s);
        return true;
    };
    SHPRT_CHECK(slash != std::string::npos && number(text.substr(0, slash), i) &&
                    number(text.substr(slash + 1), n) && n >= 1 && i < n,
                invalid_argument, "--shard '{}': expected I/N with 0 <= I < N (e.g. 0/4)", text);
    return {static_cast<std::size_t>(i), static_cast<std::size_t>(n)};
}

double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// The command line as typed (from /proc/self/cmdline), for the file's metadata; empty if
// unavailable.
std::string command_line() {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string out;
    std::size_t begin = 0;
    while (begin < raw.size()) {
        std::size_t end = raw.find('\0', begin);
        if (end == std::string::npos) end = raw.size();
        std::string arg = raw.substr(begin, end - begin);
        if (!out.empty()) out += ' ';
        const bool quote = arg.empty() || arg.find_first_of(" \t\"'\\$") != std::string::npos;
        out += quote ? "'" + arg + "'" : arg;
        begin = end + 1;
    }
    return out;
}

// Fails early, before any work, if OUT cannot be written: a directory, or a place where the
// temporary file cannot be created. The probe's temporary file is removed at once.
void check_output_writable(const std::string& path) {
    std::error_code ec;
    SHPRT_CHECK(!std::filesystem::is_directory(path, ec), io, "cannot write {}: it is a directory",
                path);
    const AtomicFile probe(path);  // throws Error(io) naming the path; removed on destruction
}

void run(const BakeArgs& args) {
    BakeOptions options = bake_options_from(args.bake);
    check_output_is_not_input(args.output, {args.scene});
    check_output_writable(args.output);

    const auto load_start = Clock::now();
    const Mesh mesh = load_scene(args.scene);
    const double seconds_load = seconds_since(load_start);

    // A shard bakes receivers [⌊V·I/N⌋, ⌊V·(I+1)/N⌋) of the same bake; `shprt merge` joins them.
    Receivers receivers = vertex_receivers(mesh);
    nlohmann::json extra;
    if (!args.shard.empty()) {
        const auto [i, n] = parse_shard(args.shard);
        const std::size_t V = mesh.vertex_count();
        SHPRT_CHECK(n <= V, invalid_argument,
                    "--shard {}: {} shards of {} vertices leave some empty", args.shard, n, V);
        receivers = receivers.range(V * i / n, V * (i + 1) / n - V * i / n);
        extra["shard"] = {{"index", i}, {"of", n}};
    }

    install_interrupt_handler();
    extra["stats"]["seconds_load"] = seconds_load;
    extra["command_line"] = command_line();
    WriteOptions write_options;
    write_options.receiver_first = receivers.first;
    write_options.extra_metadata_json = extra.dump();
    TransferSet transfer;
    double seconds_write = 0;
    if (args.stream) {
        // Rows go to the file as chunks finish: no V×K array in memory.
        TransferInfo description = bake_description(options);
        if (args.half) description.layout.encoding = TransferEncoding::f16;
        ShprtStreamWriter writer(args.output, mesh, description, receivers.first, receivers.count,
                                 write_options);
        {
            ProgressBar bar("bake");
            options.progress = bar.callback();
            static_cast<TransferInfo&>(transfer) =
                bake(BakeJob{&mesh, receivers, &writer.sink(), nullptr, nullptr}, options);
        }
        const auto write_start = Clock::now();
        writer.commit(transfer);
        seconds_write = seconds_since(write_start);
    } else {
        {
            ProgressBar bar("bake");
            options.progress = bar.callback();
            transfer = bake(mesh, receivers, options);
        }
        if (args.half) transfer.layout.encoding = TransferEncoding::f16;
        const auto write_start = Clock::now();
        write_shprt(args.output, mesh, transfer, write_options);
        seconds_write = seconds_since(write_start);
    }

    const BakeStats& s = transfer.stats;
    const double rays_per_second = s.seconds_trace > 0 ? double(s.rays_cast) / s.seconds_trace : 0;
    std::printf(
        "baked %zu vertices, K=%d, S=%d (%s, %s): load %.3f s, bvh %.3f s, trace %.3f s, "
        "project %.3f s, write %.3f s; %.1f Mrays/s, peak %.1f MiB, %s -> %s\n",
        receivers.count, transfer.layout.K, transfer.samples, to_string(transfer.kind),
        to_string(transfer.sampler), seconds_load, s.seconds_bvh, s.seconds_trace,
        s.seconds_project, seconds_write, rays_per_second * 1e-6,
        double(s.peak_bytes_host) / (1024.0 * 1024.0), s.device_name.c_str(), args.output.c_str());
}

const bool registered = register_command(
    {"bake", "Bake per-vertex SH transfer of a scene into a .shprt file", 30, [](CLI::App& app) {
         auto args = std::make_shared<BakeArgs>();
         app.add_option("scene", args->scene, "Scene file or builtin:NAME (room, plane, ...)")
             ->required();
         app.add_option("-o,--output", args->output, "Output .shprt file")->required();
         add_bake_options(app, args->bake);
         app.add_flag("--half", args->half, "Store coefficients as float16");
         app.add_flag("--stream", args->stream,
                      "Write coefficients to the file as chunks finish (no V×K array in memory)");
         app.add_option("--shard", args->shard,
                        "Bake part I of N (I/N, 0-based) of the vertices, for job arrays; join "
                        "the parts with `shprt merge`");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
