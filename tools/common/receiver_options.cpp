// `shprt bake` with texel or refined-vertex receivers (receiver_options.hpp). Thin: checks,
// calls texel_receivers / bake / bake_refined and write_shprt, prints.
#include "common/receiver_options.hpp"

#include "common/signals.hpp"

#include "common/progress_bar.hpp"

#include "shprt/bake/refine.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/memory.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/core/timer.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

namespace shprt::tools {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

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

// `kept` as the metadata kept in reproducible files, `extra` merged into the extra metadata.
WriteOptions with_metadata(WriteOptions options, const nlohmann::json& kept,
                           const nlohmann::json& extra = nlohmann::json::object()) {
    // Deterministic facts stay in --reproducible files; the rest joins the run's extra metadata.
    options.kept_metadata_json = kept.dump();
    nlohmann::json all = options.extra_metadata_json.empty()
                             ? nlohmann::json::object()
                             : nlohmann::json::parse(options.extra_metadata_json);
    all.update(extra);
    options.extra_metadata_json = all.dump();
    return options;
}

void print_bake_line(const char* what, std::size_t receivers, const TransferInfo& t, double seconds,
                     const std::string& output) {
    const BakeStats& s = t.stats;
    std::printf(
        "baked %zu %s, K=%d, S=%d (%s, %s): trace %.3f s, project %.3f s, total %.3f s; %.0f "
        "receivers/s, %.1f Mrays/s, peak %.1f MiB, %s -> %s\n",
        receivers, what, t.layout.K, t.samples, to_string(t.kind), to_string(t.sampler),
        s.seconds_trace, s.seconds_project, seconds,
        seconds > 0 ? double(receivers) / seconds : 0.0,
        s.seconds_trace > 0 ? double(s.rays_cast) / s.seconds_trace * 1e-6 : 0.0,
        double(s.peak_bytes_host) / kMiB, s.device_name.c_str(), output.c_str());
}

void bake_texels(const ReceiverArgs& args, const Mesh& mesh, BakeOptions options,
                 const std::string& output, WriteOptions write_options) {
    const auto [width, height] = parse_resolution(args.resolution);
    // The rasteriser's coverage image alone (6 bytes a texel) must fit before anything runs.
    const std::uint64_t image_bytes = std::uint64_t(width) * std::uint64_t(height) * 6;
    const std::uint64_t free_bytes = available_memory_bytes();
    SHPRT_CHECK(free_bytes == 0 || image_bytes <= free_bytes, out_of_memory,
                "{}: rasterising {}x{} texels needs about {:.1f} MiB but {:.1f} MiB are "
                "available; lower --resolution",
                mesh.source, width, height, double(image_bytes) / kMiB, double(free_bytes) / kMiB);
    const TexelSamples texels = rasterize_texels(mesh, width, height, args.uv_set);
    // Refuse what cannot fit, before tracing.
    TransferInfo description = bake_description(options);
    const std::uint64_t need = texel_bake_bytes(texels.count(), width, height, description.layout,
                                                options.samples, options.threads);
    const std::uint64_t have = available_memory_bytes();
    SHPRT_CHECK(have == 0 || need <= have, out_of_memory,
                "{}: a {}x{} texel bake ({} texels, K={}) needs about {:.1f} MiB but {:.1f} MiB "
                "are available; lower --resolution or K",
                mesh.source, width, height, texels.count(), options.K, double(need) / kMiB,
                double(have) / kMiB);
    HostSink sink;
    const auto start = Clock::now();
    TransferInfo info;
    {
        ProgressBar bar("bake");
        options.progress = bar.callback();
        info = bake(BakeJob{&mesh, texel_receivers(texels), &sink, nullptr, nullptr, nullptr},
                    options);
    }
    const double seconds = seconds_since(start);
    TransferSet transfer;
    static_cast<TransferInfo&>(transfer) = info;
    transfer.texels = texel_atlas(texels, args.uv_set);
    transfer.coeffs = sink.take_rows();
    transfer.stats.peak_bytes_host += transfer.coeffs.size() * sizeof(float);
    transfer.layout.encoding = args.float32 ? TransferEncoding::f32 : TransferEncoding::f16;
    const std::uint64_t covered = texels.count();
    end_interruptible();  // a signal from here on: nothing written (common/signals.hpp)
    write_shprt(
        output, mesh, transfer,
        with_metadata(
            std::move(write_options),
            {{"texel_bake", {{"resolution", {width, height}}, {"covered_texels", texels.count()}}}},
            {{"texel_bake", {{"estimated_bytes", need}}}}));
    std::printf("texels: %dx%d, %llu covered (%.1f%%), UV set %d, %s\n", width, height,
                static_cast<unsigned long long>(covered),
                100.0 * double(covered) / (double(width) * double(height)), args.uv_set,
                to_string(transfer.layout.encoding));
    print_bake_line("texels", covered, info, seconds, output);
}

void bake_refine(const ReceiverArgs& args, const Mesh& mesh, BakeOptions options,
                 const std::string& output, bool half, WriteOptions write_options) {
    RefineOptions refine;
    refine.tolerance = *args.refine;
    if (args.max_vertices) refine.max_vertices = static_cast<std::size_t>(*args.max_vertices);
    if (args.max_depth) refine.max_depth = static_cast<int>(*args.max_depth);
    const auto start = Clock::now();
    RefineResult r;
    {
        ProgressBar bar("bake");
        options.progress = bar.callback();
        r = bake_refined(mesh, options, refine);
    }
    const double seconds = seconds_since(start);
    if (half) r.transfer.layout.encoding = TransferEncoding::f16;
    const std::size_t V = r.mesh.vertex_count();
    if (r.budget_reached)
        log_warn(
            "refinement stopped at --max-vertices {}: {} edges still differ by more than {} "
            "(largest {:.3g})",
            V, r.edges_over, refine.tolerance, r.largest_difference);
    else if (r.depth_reached)
        log_warn(
            "refinement stopped at --max-edge-split-depth {}: {} edges still differ by more "
            "than {} (largest {:.3g})",
            refine.max_depth, r.edges_over, refine.tolerance, r.largest_difference);
    const nlohmann::json meta = {
        {"refinement",
         {{"tolerance", refine.tolerance},
          {"measure", "max over 14 clamped-cosine test lights of |E(a) - E(b)| / (2 pi / 3)"},
          {"max_vertices", refine.max_vertices},
          {"max_edge_split_depth", refine.max_depth},
          {"input_vertices", r.input_vertices},
          {"input_triangles", mesh.triangle_count()},
          {"passes", r.passes},
          {"budget_reached", r.budget_reached},
          {"depth_reached", r.depth_reached},
          {"largest_difference", r.largest_difference}}}};
    end_interruptible();  // a signal from here on: nothing written (common/signals.hpp)
    write_shprt(output, r.mesh, r.transfer, with_metadata(std::move(write_options), meta));
    std::printf(
        "refined: %zu -> %zu vertices, %zu -> %zu triangles in %d pass%s; largest edge "
        "difference %.3g (tolerance %g)\n",
        r.input_vertices, V, mesh.triangle_count(), r.mesh.triangle_count(), r.passes,
        r.passes == 1 ? "" : "es", r.largest_difference, refine.tolerance);
    print_bake_line("vertices", V, r.transfer, seconds, output);
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

void check_receiver_options(const ReceiverArgs& a, const std::string& incompatible) {
    const ReceiverDomain domain = parse_receiver_domain(a.domain);
    const bool texel = domain == ReceiverDomain::texel;
    SHPRT_CHECK(!texel || !a.resolution.empty(), invalid_argument,
                "--domain texel needs --resolution W or WxH");
    SHPRT_CHECK(texel || (a.resolution.empty() && a.uv_set == 0 && !a.float32), invalid_argument,
                "--resolution, --uv-set and --float32 need --domain texel");
    if (texel) parse_resolution(a.resolution);
    SHPRT_CHECK(!(texel && a.refine), invalid_argument,
                "--refine refines vertices: it does not go with --domain texel");
    SHPRT_CHECK(a.refine || (!a.max_vertices && !a.max_depth), invalid_argument,
                "--max-vertices and --max-edge-split-depth need --refine");
    if (a.refine)
        SHPRT_CHECK(*a.refine > 0 && std::isfinite(*a.refine), invalid_argument,
                    "--refine {}: the tolerance must be a positive fraction (e.g. 0.05)",
                    *a.refine);
    if (a.max_vertices)
        SHPRT_CHECK(*a.max_vertices >= 1, invalid_argument, "--max-vertices {}: must be positive",
                    *a.max_vertices);
    if (a.max_depth)
        SHPRT_CHECK(*a.max_depth >= 1 && *a.max_depth <= 30, invalid_argument,
                    "--max-edge-split-depth {}: must be 1 to 30", *a.max_depth);
    SHPRT_CHECK(!a.requested() || incompatible.empty(), invalid_argument, "{} does not go with {}",
                incompatible, texel ? "--domain texel" : "--refine");
}

void bake_other_receivers(const ReceiverArgs& args, const Mesh& mesh, BakeOptions options,
                          const std::string& output, bool half, WriteOptions write_options) {
    if (parse_receiver_domain(args.domain) == ReceiverDomain::texel)
        bake_texels(args, mesh, std::move(options), output, std::move(write_options));
    else
        bake_refine(args, mesh, std::move(options), output, half, std::move(write_options));
}

}  // namespace shprt::tools
