// `shprt merge PART... -o OUT.shprt`: join the parts of a sharded bake (`shprt bake --shard I/N`)
// into one file, checking that they belong together (same scene, options and seed) and cover
// every vertex exactly once. Thin: read_shprt_part, merge_shprt_parts, write_shprt.
#include "common/command.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

struct MergeArgs {
    std::vector<std::string> parts;
    std::string output;
    bool reproducible = false;
};

void run(const MergeArgs& args) {
    check_output_is_not_input(args.output, args.parts);
    check_output_writable(args.output);  // a directory, a device: refused before the work
    std::vector<ShprtFile> parts;
    for (const std::string& path : args.parts) parts.push_back(read_shprt_part(path));
    const ShprtFile whole = merge_shprt_parts(std::move(parts), args.parts);
    WriteOptions options;
    options.reproducible = args.reproducible;
    write_shprt(args.output, whole.mesh, whole.transfer, options);
    std::printf("merged %zu parts: %zu vertices, K=%d, S=%d (%s) -> %s\n", args.parts.size(),
                whole.mesh.vertex_count(), whole.transfer.layout.K, whole.transfer.samples,
                to_string(whole.transfer.sampler), args.output.c_str());
}

const bool merge_registered = register_command(
    {"merge", "Join the parts of a sharded bake (shprt bake --shard I/N) into one .shprt file", 35,
     [](CLI::App& app) {
         auto args = std::make_shared<MergeArgs>();
         app.add_option("parts", args->parts, "The parts (.shprt files), in any order")->required();
         app.add_option("-o,--output", args->output, "Output .shprt file")->required();
         app.add_flag("--reproducible", args->reproducible,
                      "Leave out the stats (times, rays, peak memory, devices), so that the same "
                      "parts give the same bytes");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
