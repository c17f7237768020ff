// `shprt bake SCENE -o OUT.shprt [options]`: load a scene, bake its transfer (per vertex, a shard
// of the vertices, per texel or on refined vertices), write a .shprt file — in one process or
// across the ranks of an MPI job (under mpirun, or --mpi). Thin: it parses the options into a
// bake request (bake/request.hpp; its refusals come before any work), loads the scene, runs the
// request (dist::run under MPI), draws the progress bar and prints the summary on stdout.
#include "common/command.hpp"
#include "common/option_table.hpp"
#include "common/progress_bar.hpp"

#include "shprt/bake/bake_option_table.hpp"
#include "shprt/bake/bake_summary.hpp"
#include "shprt/bake/request.hpp"
#include "shprt/bake/request_options.hpp"
#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/host.hpp"
#include "shprt/core/interrupt.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/transfer/estimates.hpp"
#if SHPRT_HAS_MPI
#include "shprt/dist/mpi_request.hpp"
#endif

#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace shprt::tools {
namespace {

struct BakeArgs {
    std::string scene, output;
    BakeOptionChoice bake;  // bake/bake_option_table.hpp, shared with `shprt view --bake`
    FileChoice file;        // --half, --stream, --reproducible: bake/request_options.hpp
    bool mpi = false;
    std::size_t mpi_unit = 0;     // 0 = automatic
    ReceiverChoice receivers;     // --domain texel, --refine: bake/request_options.hpp
    CheckpointChoice checkpoint;  // --checkpoint, --resume, --max-memory: the same
};

// For the tests of the signals (tests/cli/test_cli_interrupt.cpp): when the environment variable
// SHPRT_TEST_STOP_AT is `point`, the process stops itself there (SIGSTOP), so that a test can send
// a signal at a known moment and then continue it (SIGCONT). Points: "load" (tools/launcher.cpp:
// the command line's libraries are about to load), "bake" (the bake is about to start, signals
// are requests), "write" (the bake is over, signals are still requests), "writing" (the output is
// about to be written, a signal ends the process).
void test_stop_point(const char* point) {
    const char* wanted = std::getenv("SHPRT_TEST_STOP_AT");
    if (wanted != nullptr && std::strcmp(wanted, point) == 0) ::raise(SIGSTOP);
}

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

// The request the options describe, before the scene is loaded: every refusal the library knows
// is made here, before any work.
BakeRequest request_from(const BakeArgs& args) {
    BakeRequest r;
    r.options = bake_options_from(args.bake, Spelling::command_line);
    r.receivers = parse_receivers(args.receivers);
    const ReceiverChoice& c = args.receivers;
    r.probes = parse_probes(c.probes, c.probe_box, c.probe_bands);
    SHPRT_CHECK(!c.float32 || std::holds_alternative<TexelGrid>(r.receivers), invalid_argument,
                "--float32 needs --domain texel");
    r.output = file_output_from(args.output, args.file, c.float32);
    apply_checkpoint_choice(args.checkpoint, r, Spelling::command_line);
    r.distributed = use_mpi(args);
    check(r);
    return r;
}

// The run's own facts in the file's metadata: the load time, the command line, the ranks.
void add_run_metadata(BakeRequest& r, double seconds_load, int ranks) {
    nlohmann::json extra;
    extra["stats"]["seconds_load"] = seconds_load;
    extra["command_line"] = process_command_line();
    if (ranks > 0) extra["mpi"] = {{"ranks", ranks}};
    r.output->write.extra_metadata_json = extra.dump();
}

#if SHPRT_HAS_MPI
// `mpirun -np P shprt bake ...` (or --mpi): every rank loads the scene, the ranks share the
// receivers (dist/mpi_request.hpp), rank 0 writes the one file and prints; a failure anywhere is
// one line from rank 0, and every rank exits with its status.
void run_mpi(const BakeArgs& args, BakeRequest request) {
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
        if (root) install_interrupt_handler(false);  // SIGTERM: mpirun ending the job
        add_run_metadata(request, seconds_load, session.size());
        dist::DistributedResult result;
        {
            std::optional<ProgressBar> bar;
            if (root) request.options.progress = bar.emplace("bake").callback();
            result = dist::run(session, request, *mesh, args.mpi_unit);
        }
        if (root) {
            std::fputs(
                bake_summary(request, *mesh, result.result, args.output, seconds_load).c_str(),
                stdout);
            std::fputs(rank_loads_summary(result.ranks).c_str(), stdout);
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

void run(const BakeArgs& args) {
    BakeRequest request = request_from(args);
#if SHPRT_HAS_MPI
    if (request.distributed) return run_mpi(args, std::move(request));
#endif
    check_output_is_not_input(args.output, {args.scene});
    check_output_writable(args.output);

    const auto load_start = Clock::now();
    const int uv_set = std::holds_alternative<TexelGrid>(request.receivers)
                           ? std::get<TexelGrid>(request.receivers).uv_set
                           : 0;
    Mesh mesh = load_scene(args.scene, uv_set);
    check_output_path(args.output);  // now also against the files the scene read (a .mtl, ...)
    apply_albedo_choice(args.bake, mesh);
    const double seconds_load = seconds_since(load_start);
    add_run_metadata(request, seconds_load, 0);

    install_interrupt_handler();
    std::optional<ProgressBar> bar;
    request.options.progress = bar.emplace("bake").callback();
    request.error_rounds = true;  // the bar shows each round's stage and error
    request.before_write = [&bar] {
        bar.reset();
        test_stop_point("write");
        end_interruptible();  // a signal from here on: nothing written (core/interrupt.hpp)
        test_stop_point("writing");
    };
    request.before_bake = [] { test_stop_point("bake"); };
    BakeResult result;
    try {
        result = shprt::run(request, mesh);
    } catch (const CheckpointKept& e) {
        bar.reset();
        const bool signalled = e.code() == ErrorCode::cancelled && interrupted();
        const int signal = signalled ? interrupt_signal() : 0;
        print_error(resume_hint(e, signalled ? signal_name(signal) : nullptr).c_str());
        throw ExitQuietly{signalled ? interrupted_exit_code(signal) : 1};
    }
    std::fputs(bake_summary(request, mesh, result, args.output, seconds_load).c_str(), stdout);
}

const bool bake_registered = register_command(
    {"bake", "Bake per-vertex SH transfer of a scene into a .shprt file", 30, [](CLI::App& app) {
         auto args = std::make_shared<BakeArgs>();
         app.add_option("scene", args->scene, "Scene file or builtin:NAME (room, plane, ...)")
             ->required();
         app.add_option("-o,--output", args->output, "Output .shprt file")->required();
         add_table_options(app, bake_option_table(), args->bake);
         add_table_options(app, receiver_option_table(), args->receivers);
         add_table_options(app, file_option_table(), args->file);
         app.add_flag("--mpi", args->mpi,
                      "Bake across the ranks of an MPI job (automatic under mpirun/srun): rank 0 "
                      "writes the file");
         app.add_option("--mpi-unit", args->mpi_unit,
                        "Smallest share of receivers a rank claims at a time (default: automatic, "
                        "enough to keep its threads busy)");
         add_table_options(app, checkpoint_option_table(), args->checkpoint);
         app.get_option("--checkpoint")->excludes(app.get_option("--resume"));
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
