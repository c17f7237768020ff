// `shprt bake`'s receiver options (receiver_options.hpp).
#include "common/receiver_options.hpp"

namespace shprt::tools {

void add_receiver_options(CLI::App& app, ReceiverArgs& args) {
    app.add_option("--domain", args.choice.domain,
                   "Receivers: vertex (default) or texel (the texel centres of the scene's UV "
                   "atlas; needs --resolution, or --unwrap --texel-density)");
    app.add_option("--resolution", args.choice.resolution, "Texel domain: image size W or WxH");
    app.add_flag("--unwrap", args.choice.unwrap,
                 "Texel domain: make a new UV atlas (conformal charts, packed with gutters) "
                 "instead of the scene's UVs; the file keeps the unwrapped mesh");
    app.add_option("--texel-density", args.choice.texel_density,
                   "Texel domain with --unwrap: texels per metre (chooses the resolution)");
    app.add_option("--uv-set", args.choice.uv_set,
                   "Texel domain: which UV set of the scene (default 0)");
    app.add_flag("--float32", args.float32,
                 "Texel domain: store float32 coefficients (default float16)");
    app.add_option("--refine", args.choice.refine,
                   "Adaptive refinement: split edges whose ends' irradiance under 14 test lights "
                   "differs by more than this fraction of full brightness (e.g. 0.05)");
    app.add_option("--max-vertices", args.choice.max_vertices,
                   "Refinement: stop at this many vertices (default 16x the scene's)");
    app.add_option("--max-edge-split-depth", args.choice.max_edge_split_depth,
                   "Refinement: how many times an edge may be halved (1 to 30, default 6)");
    app.add_option("--probes", args.choice.probes,
                   "Transfer probes beside the receivers, for objects that move: auto (every "
                   "0.5 m over the scene's bounds), auto:SPACING, NX,NY,NZ or NX,NY,NZ:SPACING");
    app.add_option("--probe-box", args.choice.probe_box,
                   "Probes: the grid's box X0,Y0,Z0,X1,Y1,Z1 (default: the scene's bounds)");
    app.add_option("--probe-bands", args.choice.probe_bands,
                   "Probes: SH bands of their matrices (1 to 8, default 3: 9x9)");
    app.add_option("--shard", args.choice.shard,
                   "Bake part I of N (I/N, 0-based) of the vertices, for job arrays; join the "
                   "parts with `shprt merge`");
}

}  // namespace shprt::tools
