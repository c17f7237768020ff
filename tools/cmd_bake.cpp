// `shprt bake SCENE -o OUT.shprt [options]`: load a scene, bake per-vertex SH transfer, write a
// .shprt file — in one process, a shard of one (--shard I/N), or across the ranks of an MPI job
// (under mpirun, or --mpi). Thin: it checks the options (one-line errors before any work), calls
// load_scene, bake (or dist::bake_distributed) and the writer, draws the progress bar and prints
// a one-line summary on stdout.
#include "common/bake_options.hpp"
#include "common/command.hpp"
#include "common/progress_bar.hpp"
#include "common/receiver_options.hpp"
#include "common/resumable_bake.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/io/shprt_stream.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/sh/basis.hpp"
#if SHPRT_HAS_MPI
#include "shprt/dist/mpi_bake.hpp"
#endif

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

namespace shprt::tools {
namespace {

struct BakeArgs {
    std::string scene, output;
    BakeOptionArgs bake;  // common/bake_options.hpp, shared with `shprt view --bake`
    bool half = false;
    std::string shard;  // "I/N", or empty
    bool stream = false;
    bool reproducible = false;
    bool mpi = false;
    std::size_t mpi_unit = 0;  // 0 = automatic
    ReceiverArgs receivers;    // --domain texel, --refine: common/receiver_options.hpp
    ResumableArgs resumable;   // --checkpoint, --resume, --max-memory (common/resumable_bake.hpp)
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

// Where the bake's rows go and how the file is written: with --stream, the streaming writer
// (laid out before the bake, rows into the file as they finish); otherwise host memory, written
// at the end with write_shprt.
class Output {
public:
    Output(const BakeArgs& args, const Mesh& mesh, const Receivers& receivers,
           const BakeOptions& options, WriteOptions write_options)
        : m_args(args), m_mesh(mesh), m_options(std::move(write_options)) {
        if (!args.stream) return;
        TransferInfo description = bake_description(options);
        if (args.half) description.layout.encoding = TransferEncoding::f16;
        m_writer = std::make_unique<ShprtStreamWriter>(args.output, mesh, description,
                                                       receivers.first, receivers.count, m_options);
    }
    TransferSink& sink() { return m_writer ? m_writer->sink() : m_host; }
    // Where an interreflected bake's direct part goes (written as "transfer_direct").
    std::vector<float>* direct() { return m_writer ? nullptr : &m_direct; }
    // Writes the file; returns the seconds it took.
    double write(const TransferInfo& info) {
        const auto start = Clock::now();
        if (m_writer) {
            m_writer->commit(info);
        } else {
            TransferSet transfer;
            static_cast<TransferInfo&>(transfer) = info;
            transfer.coeffs = m_host.take_rows();
            transfer.direct = std::move(m_direct);
            transfer.stats.peak_bytes_host += transfer.coeffs.size() * sizeof(float);
            if (m_args.half) transfer.layout.encoding = TransferEncoding::f16;
            write_shprt(m_args.output, m_mesh, transfer, m_options);
        }
        return seconds_since(start);
    }

private:
    const BakeArgs& m_args;
    const Mesh& m_mesh;
    WriteOptions m_options;
    std::unique_ptr<ShprtStreamWriter> m_writer;
    HostSink m_host;
    std::vector<float> m_direct;
};

// The rows this process bakes (a shard's range, or every vertex) and the file's metadata.
struct Plan {
    Receivers receivers;
    WriteOptions write_options;
};

Plan plan(const BakeArgs& args, const Mesh& mesh, double seconds_load, int ranks) {
    Plan p;
    p.receivers = vertex_receivers(mesh);
    nlohmann::json extra;
    // A shard bakes receivers [⌊V·I/N⌋, ⌊V·(I+1)/N⌋) of the same bake; `shprt merge` joins them.
    if (!args.shard.empty()) {
        const auto [i, n] = parse_shard(args.shard);
        const std::size_t V = mesh.vertex_count();
        SHPRT_CHECK(n <= V, invalid_argument,
                    "--shard {}: {} shards of {} vertices leave some empty", args.shard, n, V);
        p.receivers = p.receivers.range(V * i / n, V * (i + 1) / n - V * i / n);
        extra["shard"] = {{"index", i}, {"of", n}};
    }
    extra["stats"]["seconds_load"] = seconds_load;
    extra["command_line"] = command_line();
    if (ranks > 0) extra["mpi"] = {{"ranks", ranks}};
    p.write_options.receiver_first = p.receivers.first;
    p.write_options.extra_metadata_json = extra.dump();
    p.write_options.reproducible = args.reproducible;
    return p;
}

void print_summary(const BakeArgs& args, const Plan& plan, const TransferInfo& transfer,
                   double seconds_load, double seconds_write) {
    const BakeStats& s = transfer.stats;
    if (transfer.kind == TransferKind::interreflected) {
        const InterreflectionInfo& ir = transfer.interreflection;
        std::printf(
            "interreflection: %d bounce%s%s (last relative change %.2g), operator %.3f s (nnz(A) "
            "= %llu, %.1f MiB), bounces %.3f s; albedo: %s\n",
            ir.bounces, ir.bounces == 1 ? "" : "s",
            ir.converge ? (ir.converged ? ", converged" : ", NOT converged") : "", ir.last_change,
            s.seconds_operator, static_cast<unsigned long long>(ir.operator_nnz),
            double(ir.operator_bytes) / (1024.0 * 1024.0), s.seconds_bounces,
            ir.albedo_source.c_str());
        if (s.operator_bytes_spilled > 0)
            std::printf(
                "operator: %.1f MiB of A past the memory budget, read memory-mapped from a "
                "temporary file beside the output\n",
                double(s.operator_bytes_spilled) / (1024.0 * 1024.0));
    }
    const double rays_per_second = s.seconds_trace > 0 ? double(s.rays_cast) / s.seconds_trace : 0;
    std::printf(
        "baked %zu vertices, K=%d, S=%d (%s, %s): load %.3f s, bvh %.3f s, trace %.3f s, "
        "project %.3f s, write %.3f s; %.1f Mrays/s, peak %.1f MiB, %s -> %s\n",
        plan.receivers.count, transfer.layout.K, transfer.samples, to_string(transfer.kind),
        to_string(transfer.sampler), seconds_load, s.seconds_bvh, s.seconds_trace,
        s.seconds_project, seconds_write, rays_per_second * 1e-6,
        double(s.peak_bytes_host) / (1024.0 * 1024.0), s.device_name.c_str(), args.output.c_str());
}

#if SHPRT_HAS_MPI
// "ranks: receivers 4096 3968 ... (units 3 3 ...), busy 1.201 s to 1.310 s of 1.402 s;
// gathered 0.05 GiB in 0.081 s": how the balancing and the gather went.
void print_rank_loads(const dist::DistributedBake& result) {
    std::vector<std::size_t> receivers, units;
    double least = 0, most = 0;
    for (std::size_t r = 0; r < result.ranks.size(); ++r) {
        const dist::RankLoad& load = result.ranks[r];
        receivers.push_back(load.receivers);
        units.push_back(load.units);
        least = r == 0 ? load.seconds : std::min(least, load.seconds);
        most = std::max(most, load.seconds);
    }
    std::printf(
        "ranks: receivers %s (units %s), busy %.3f s to %.3f s of %.3f s; gathered %.3f "
        "GiB in %.3f s\n",
        fmt::format("{}", fmt::join(receivers, " ")).c_str(),
        fmt::format("{}", fmt::join(units, " ")).c_str(), least, most, result.seconds_wall,
        double(result.bytes_gathered) / double(1u << 30), result.seconds_gathered);
}

// `mpirun -np P shprt bake ...` (or --mpi): every rank loads the scene, the ranks share the
// receivers (dist/mpi_bake.hpp), rank 0 writes the one file and prints; a failure anywhere is one
// line from rank 0, and every rank exits with its status.
void run_mpi(const BakeArgs& args, BakeOptions options) {
    SHPRT_CHECK(args.shard.empty(), invalid_argument,
                "--shard and MPI: the ranks already share the bake (use one or the other)");
    // The scene is loaded before MPI starts: the importer runs in a forked child, which some MPI
    // transports do not allow once initialised. Its failure is agreed on once MPI runs.
    std::optional<Mesh> mesh;
    std::exception_ptr load_failure;
    const auto load_start = Clock::now();
    try {
        mesh = load_scene(args.scene);
    } catch (...) {
        load_failure = std::current_exception();
    }
    const double seconds_load = seconds_since(load_start);

    dist::MpiSession session;
    const bool root = session.rank() == 0;
    try {
        session.agree([&] {
            if (load_failure) std::rethrow_exception(load_failure);
            if (root) {
                check_output_is_not_input(args.output, {args.scene});
                check_output_writable(args.output);
            }
        });
        dist::check_same_scene(session, *mesh);
        if (root) install_interrupt_handler(false);  // SIGTERM: mpirun ending the job
        std::optional<Plan> p;
        std::unique_ptr<Output> output;
        session.agree([&] {
            p = plan(args, *mesh, seconds_load, session.size());
            if (root)
                output =
                    std::make_unique<Output>(args, *mesh, p->receivers, options, p->write_options);
        });
        dist::DistributedBake result;
        {
            std::optional<ProgressBar> bar;
            dist::DistOptions dist;
            if (root) dist.progress = bar.emplace("bake").callback();
            dist.min_unit = args.mpi_unit;
            BakeJob job{&*mesh, p->receivers, root ? &output->sink() : nullptr, nullptr, nullptr};
            result = dist::bake_distributed(session, job, options, dist);
        }
        const TransferInfo& info = result.info;
        double seconds_write = 0;
        session.agree([&] {
            if (root) seconds_write = output->write(info);
        });
        if (root) {
            print_summary(args, *p, info, seconds_load, seconds_write);
            print_rank_loads(result);
        }
    } catch (const Error& e) {
        // Every rank has the agreed error: rank 0 prints it, and no rank exits before it has (a
        // rank that exits non-zero makes mpirun kill the others).
        if (root) print_error(e.what());
        session.barrier();
        throw ExitQuietly{1};
    }
}
#endif

bool use_mpi(const BakeArgs& args) {
#if SHPRT_HAS_MPI
    return args.mpi || dist::launched_by_mpi();
#else
    SHPRT_CHECK(!args.mpi, unsupported,
                "--mpi: this build has no MPI (install libopenmpi-dev and configure with "
                "SHPRT_MPI=AUTO or ON)");
    return false;
#endif
}

void run(const BakeArgs& args) {
    BakeOptions options = bake_options_from(args.bake);
    check_receiver_options(args.receivers, !args.shard.empty() ? "--shard"
                                           : args.stream       ? "--stream"
                                           : args.mpi          ? "--mpi"
                                                               : "");
    if (options.transfer == TransferKind::interreflected) {
        SHPRT_CHECK(args.shard.empty(), unsupported,
                    "--shard: interreflected transfer cannot be sharded (its bounces couple every "
                    "vertex); bake it in one process");
        SHPRT_CHECK(!args.stream, unsupported,
                    "--stream: interreflected transfer keeps every vertex's rows in memory for "
                    "its bounces; bake it without --stream");
    }
    const bool mpi = use_mpi(args);
    check_resumable_args(args.resumable, options, args.output,
                         mpi ? "an MPI bake cannot be checkpointed yet; bake without MPI"
                         : args.receivers.requested()
                             ? "texel and refined bakes cannot be checkpointed yet; bake "
                               "without --checkpoint"
                             : "");
#if SHPRT_HAS_MPI
    if (mpi) return run_mpi(args, options);
#endif
    check_output_is_not_input(args.output, {args.scene});
    check_output_writable(args.output);

    const auto load_start = Clock::now();
    Mesh mesh = load_scene(args.scene, args.receivers.uv_set);
    apply_albedo_option(args.bake, mesh);
    const double seconds_load = seconds_since(load_start);

    const Plan p = plan(args, mesh, seconds_load, 0);
    if (args.receivers.requested()) {
        install_interrupt_handler();
        return bake_other_receivers(args.receivers, mesh, options, args.output, args.half,
                                    p.write_options);
    }
    install_interrupt_handler();
    Output output(args, mesh, p.receivers, options, p.write_options);
    const BakeJob job{&mesh, p.receivers, &output.sink(), nullptr, nullptr, output.direct()};
    // An interreflected bake spills the part of its operator past the budget next to the output.
    options.memory_budget = check_bake_memory(args.resumable, job, options, !args.stream);
    const std::string folder = std::filesystem::path(args.output).parent_path().string();
    options.spill_directory = folder.empty() ? "." : folder;
    ResumableBake resumable(args.resumable, job, options);
    TransferInfo info;
    {
        ProgressBar bar("bake");
        options.progress = bar.callback();
        test_stop_point("bake");
        info = resumable.run();
    }
    test_stop_point("write");
    end_interruptible();  // a signal from here on: nothing written (common/signals.hpp)
    test_stop_point("writing");
    const double seconds_write = output.write(info);
    resumable.remove_checkpoint();
    print_summary(args, p, info, seconds_load, seconds_write);
}

const bool bake_registered = register_command(
    {"bake", "Bake per-vertex SH transfer of a scene into a .shprt file", 30, [](CLI::App& app) {
         auto args = std::make_shared<BakeArgs>();
         app.add_option("scene", args->scene, "Scene file or builtin:NAME (room, plane, ...)")
             ->required();
         app.add_option("-o,--output", args->output, "Output .shprt file")->required();
         add_bake_options(app, args->bake);
         add_receiver_options(app, args->receivers);
         app.add_flag("--half", args->half, "Store coefficients as float16");
         app.add_flag("--stream", args->stream,
                      "Write coefficients to the file as chunks finish (no V×K array in memory)");
         app.add_option("--shard", args->shard,
                        "Bake part I of N (I/N, 0-based) of the vertices, for job arrays; join "
                        "the parts with `shprt merge`");
         app.add_flag("--reproducible", args->reproducible,
                      "Leave out what differs between runs (times, rays, peak memory, device, "
                      "the command line), so that the same bake gives the same bytes");
         app.add_flag("--mpi", args->mpi,
                      "Bake across the ranks of an MPI job (automatic under mpirun/srun): rank 0 "
                      "writes the file");
         app.add_option("--mpi-unit", args->mpi_unit,
                        "Smallest share of receivers a rank claims at a time (default: automatic, "
                        "enough to keep its threads busy)");
         add_resumable_options(app, args->resumable);
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
