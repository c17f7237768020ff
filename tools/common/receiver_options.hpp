// `shprt bake`'s receiver options: per-texel transfer (--domain texel --resolution W[xH]
// --uv-set N --float32) and adaptive refinement of per-vertex transfer (--refine TOL
// --max-vertices N --max-edge-split-depth D), parsed into the request's ReceiverSet
// (bake/request.hpp), which bakes them.
#pragma once

#include "shprt/bake/request.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace shprt::tools {

struct ReceiverArgs {
    std::string domain = "vertex";
    std::string resolution;  // "W" or "WxH"
    int uv_set = 0;
    bool float32 = false;  // texel domain: store float32 (default float16)
    std::optional<double> refine;
    std::optional<long long> max_vertices;
    std::optional<long long> max_depth;
};

// Adds the options above.
void add_receiver_options(CLI::App& app, ReceiverArgs& args);

// The receivers the options ask for: AllVertices, TexelGrid or RefinedVertices (one-line
// Error(invalid_argument) naming the option for a bad value or options that need another).
ReceiverSet receivers_from(const ReceiverArgs& args);

}  // namespace shprt::tools
