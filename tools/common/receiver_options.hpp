// `shprt bake`'s receiver options: per-texel transfer (--domain texel --resolution W[xH]
// --uv-set N) and adaptive refinement of per-vertex transfer (--refine TOL --max-vertices N
// --max-edge-split-depth D). Kept apart from cmd_bake.cpp: the bake command calls
// bake_other_receivers() when receivers_requested() and is otherwise unchanged.
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/mesh.hpp"

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

    // True when a texel bake or a refinement was asked for.
    bool requested() const { return domain != "vertex" || refine.has_value(); }
};

// Adds the options above.
void add_receiver_options(CLI::App& app, ReceiverArgs& args);

// Checks the options (one-line Error(invalid_argument) naming the option) before any work; also
// the ones that do not go with them (`incompatible` names a given option such as "--shard", or is
// empty).
void check_receiver_options(const ReceiverArgs& args, const std::string& incompatible);

// Bakes `mesh`'s texels or refined vertices with `options` (progress drawn on stderr), writes
// `output` (write_options: the file's extra metadata), prints the summary lines on stdout, and a
// one-line warning on stderr when a budget stopped the refinement.
void bake_other_receivers(const ReceiverArgs& args, const Mesh& mesh, BakeOptions options,
                          const std::string& output, bool half, WriteOptions write_options);

}  // namespace shprt::tools
