// `shprt info FILE [--json]`: validate a .shprt file and describe it (or print its metadata JSON).
// Reading validates everything, so `shprt info` doubles as an integrity check: a truncated or
// corrupt file gives a one-line error and exit code 1.
#include "common/command.hpp"

#include "shprt/io/shprt_file.hpp"

#include <cstdio>
#include <memory>
#include <string>

namespace shprt::tools {
namespace {

struct InfoArgs {
    std::string path;
    bool json = false;
};

void run(const InfoArgs& args) {
    const ShprtFile file = read_shprt_part(args.path);  // a shard's part is described too
    std::string text = args.json ? file.metadata_json : shprt_summary(file);
    if (text.empty() || text.back() != '\n') text += '\n';
    std::fwrite(text.data(), 1, text.size(), stdout);
}

const bool info_registered = register_command(
    {"info", "Check a .shprt file and describe it (K, bands, sampler, timings, ...)", 40,
     [](CLI::App& app) {
         auto args = std::make_shared<InfoArgs>();
         app.add_option("file", args->path, "A .shprt file")->required();
         app.add_flag("--json", args->json, "Print the metadata JSON instead of the summary");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
