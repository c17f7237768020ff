// `shprt bake`'s receiver options (receiver_options.hpp).
#include "common/receiver_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"

#include <cmath>

namespace shprt::tools {
namespace {

// "W" (square) or "WxH", each 1..kMaxTexelSide.
std::pair<int, int> parse_resolution(const std::string& text) {
    const std::size_t x = text.find('x');
    std::int64_t w = 0, h = 0;
    const bool ok =
        parse_integer(text.substr(0, x), w) == IntegerParse::ok &&
        (x == std::string::npos ? (h = w, true)
                                : parse_integer(text.substr(x + 1), h) == IntegerParse::ok);
    SHPRT_CHECK(ok && w >= 1 && h >= 1 && w <= kMaxTexelSide && h <= kMaxTexelSide,
                invalid_argument, "--resolution '{}': expected W or WxH, each 1 to {}", text,
                kMaxTexelSide);
    return {int(w), int(h)};
}

}  // namespace

void add_receiver_options(CLI::App& app, ReceiverArgs& args) {
    app.add_option("--domain", args.domain,
                   "Receivers: vertex (default) or texel (the texel centres of the scene's UV "
                   "atlas; needs --resolution)");
    app.add_option("--resolution", args.resolution, "Texel domain: image size W or WxH");
    app.add_option("--uv-set", args.uv_set, "Texel domain: which UV set of the scene (default 0)");
    app.add_flag("--float32", args.float32,
                 "Texel domain: store float32 coefficients (default float16)");
    app.add_option("--refine", args.refine,
                   "Adaptive refinement: split edges whose ends' irradiance under 14 test lights "
                   "differs by more than this fraction of full brightness (e.g. 0.05)");
    app.add_option("--max-vertices", args.max_vertices,
                   "Refinement: stop at this many vertices (default 16x the scene's)");
    app.add_option("--max-edge-split-depth", args.max_depth,
                   "Refinement: how many times an edge may be halved (1 to 30, default 6)");
}

ReceiverSet receivers_from(const ReceiverArgs& a) {
    const bool texel = parse_receiver_domain(a.domain) == ReceiverDomain::texel;
    SHPRT_CHECK(!texel || !a.resolution.empty(), invalid_argument,
                "--domain texel needs --resolution W or WxH");
    SHPRT_CHECK(texel || (a.resolution.empty() && a.uv_set == 0 && !a.float32), invalid_argument,
                "--resolution, --uv-set and --float32 need --domain texel");
    SHPRT_CHECK(!(texel && a.refine), invalid_argument,
                "--refine refines vertices: it does not go with --domain texel");
    SHPRT_CHECK(a.refine || (!a.max_vertices && !a.max_depth), invalid_argument,
                "--max-vertices and --max-edge-split-depth need --refine");
    if (texel) {
        const auto [width, height] = parse_resolution(a.resolution);
        SHPRT_CHECK(a.uv_set >= 0, invalid_argument, "--uv-set {}: must be 0 or more", a.uv_set);
        return TexelGrid{width, height, a.uv_set};
    }
    if (!a.refine) return AllVertices{};
    RefinedVertices r;
    SHPRT_CHECK(*a.refine > 0 && std::isfinite(*a.refine), invalid_argument,
                "--refine {}: the tolerance must be a positive fraction (e.g. 0.05)", *a.refine);
    r.refine.tolerance = *a.refine;
    if (a.max_vertices) {
        SHPRT_CHECK(*a.max_vertices >= 1, invalid_argument, "--max-vertices {}: must be positive",
                    *a.max_vertices);
        r.refine.max_vertices = static_cast<std::size_t>(*a.max_vertices);
    }
    if (a.max_depth) {
        SHPRT_CHECK(*a.max_depth >= 1 && *a.max_depth <= 30, invalid_argument,
                    "--max-edge-split-depth {}: must be 1 to 30", *a.max_depth);
        r.refine.max_depth = static_cast<int>(*a.max_depth);
    }
    return r;
}

}  // namespace shprt::tools
