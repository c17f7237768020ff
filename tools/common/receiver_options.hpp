// `shprt bake`'s receiver options: per-texel transfer (--domain texel --resolution W[xH]
// --uv-set N --float32 --unwrap --texel-density T), adaptive refinement of per-vertex transfer
// (--refine TOL --max-vertices N
// --max-edge-split-depth D), a shard of the vertices (--shard I/N) and transfer probes beside
// the receivers (--probes --probe-box --probe-bands), bound into the library's ReceiverChoice
// (bake/request.hpp), whose parsers (parse_receivers, parse_probes) Python shares.
#pragma once

#include "shprt/bake/request.hpp"

#include <CLI/CLI.hpp>

namespace shprt::tools {

struct ReceiverArgs {
    ReceiverChoice choice;
    bool float32 = false;  // texel domain: store float32 (default float16)
};

// Adds the options above.
void add_receiver_options(CLI::App& app, ReceiverArgs& args);

}  // namespace shprt::tools
