// The bake request (bake/request.hpp): the one place that decides which receivers, which output
// and which execution make up a bake, and what does not combine.
#include "shprt/bake/request.hpp"

#include "shprt/bake/bounce_sources.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/bake/remaining.hpp"
#include "shprt/bake/session.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/memory.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/checkpoint.hpp"
#include "shprt/io/shprt_stream.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <memory>

namespace shprt {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

std::string format_bytes(std::uint64_t bytes) {
    const double b = double(bytes);
    if (b >= double(1ull << 30)) return fmt::format("{:.2f} GiB", b / double(1ull << 30));
    if (b >= double(1ull << 20)) return fmt::format("{:.1f} MiB", b / kMiB);
    return fmt::format("{:.0f} KiB", std::ceil(b / 1024.0));
}

bool is_texels(const BakeRequest& r) { return std::holds_alternative<TexelGrid>(r.receivers); }
bool is_refined(const BakeRequest& r) {
    return std::holds_alternative<RefinedVertices>(r.receivers);
}
bool is_shard(const BakeRequest& r) { return std::holds_alternative<VertexShard>(r.receivers); }
bool streamed(const BakeRequest& r) { return r.output && r.output->stream; }

// `kept` as the metadata kept in reproducible files, `extra` merged into the run's extra metadata.
WriteOptions with_metadata(WriteOptions options, const nlohmann::json& kept,
                           const nlohmann::json& extra = nlohmann::json::object()) {
    if (!kept.empty()) options.kept_metadata_json = kept.dump();
    nlohmann::json all = options.extra_metadata_json.empty()
                             ? nlohmann::json::object()
                             : nlohmann::json::parse(options.extra_metadata_json);
    all.update(extra);
    options.extra_metadata_json = all.dump();
    return options;
}

// The memory limit a request's estimates are held against: --max-memory, else the machine's
// available memory (0: none readable).
std::uint64_t memory_limit(const BakeRequest& r) {
    return r.max_memory > 0 ? r.max_memory : available_memory_bytes();
}

// The memory limit the request's estimate `need` is held against (0: none readable), with the
// one-line refusal naming both.
std::uint64_t check_memory(const BakeRequest& r, std::uint64_t need, const char* what,
                           const char* advice) {
    const std::uint64_t limit = memory_limit(r);
    if (limit == 0) return 0;
    SHPRT_CHECK(need <= limit, out_of_memory,
                "{} needs about {} of memory (estimated: {}), more than {}; {}", "this bake",
                format_bytes(need), what,
                r.max_memory > 0 ? "--max-memory " + format_bytes(r.max_memory)
                                 : "the " + format_bytes(limit) + " this machine has available",
                advice);
    return limit;
}

// Writes `transfer` (rows in memory) to the request's file, with `write` as its options.
double write_file(const BakeRequest& r, const Mesh& mesh, TransferSet& transfer,
                  const WriteOptions& write, TransferEncoding fallback) {
    if (r.before_write) r.before_write();
    if (!r.output) return 0;
    const auto start = Clock::now();
    transfer.layout.encoding = r.output->encoding.value_or(fallback);
    write_shprt(r.output->path, mesh, transfer, write);
    return seconds_since(start);
}

// The request's probe grid laid over `mesh` (no matrices yet), or an empty grid.
ProbeGrid request_probes(const BakeRequest& r, const Mesh& mesh) {
    if (!r.probes) return {};
    return probe_grid_layout(*r.probes, mesh, kind_row(r.options.transfer).interreflection);
}

// What the probes add to a bake's peak: their matrices, each worker's buffers (a chunk's W and
// packed matrices, one probe's hits and bounced light) and, interreflected, the bounce sources'
// light they read (3K floats a source).
std::uint64_t probe_bytes(const ProbeGrid& probes, const Mesh& mesh, const BakeOptions& options) {
    if (probes.empty()) return 0;
    const std::uint64_t light = std::uint64_t(bake_bounce_source_count(mesh, options)) * 3 *
                                std::uint64_t(options.K) * sizeof(float);
    const std::uint64_t KK = std::uint64_t(probes.K) * std::uint64_t(probes.K);
    const std::uint64_t S = bake_set_size(options);
    const std::uint64_t per_worker =
        (kProbeChunk * S + kProbeChunk * KK + 3 * S * std::uint64_t(probes.K) + 3 * KK) *
            sizeof(float) +
        S * sizeof(Hit);
    return probes.count() * (std::uint64_t(probes.channels) * KK * sizeof(float) + 1) +
           std::uint64_t(thread_count(options.threads)) * per_worker + light;
}

BakeResult run_texels(const BakeRequest& r, const Mesh& input, const TexelGrid& grid) {
    BakeResult out;
    auto [width, height, uv_set, unwrap] = grid;
    if (unwrap) {  // a new atlas on a copy of the mesh: the mesh baked and written
        out.unwrapped_mesh = input;
        out.unwrap = make_uv_atlas(*out.unwrapped_mesh, *unwrap);
        width = height = out.unwrap->resolution;
        uv_set = 0;
    }
    const Mesh& mesh = out.unwrapped_mesh ? *out.unwrapped_mesh : input;
    BakeOptions options = r.options;
    // The rasteriser's coverage image alone (6 bytes a texel) must fit before anything runs.
    const std::uint64_t image_bytes = std::uint64_t(width) * std::uint64_t(height) * 6;
    check_memory(r, image_bytes, fmt::format("rasterising {}x{} texels", width, height).c_str(),
                 "lower --resolution");
    const TexelSamples texels = rasterize_texels(mesh, width, height, uv_set);
    ProbeGrid probes = request_probes(r, mesh);
    out.estimated_bytes =
        texel_bake_bytes(texels.count(), width, height, bake_description(options).layout,
                         bake_set_size(options), options.threads) +
        estimate_bake_peak_bytes(mesh.triangle_count(), 0, options, false) +
        probe_bytes(probes, mesh, options);
    check_memory(r, out.estimated_bytes,
                 fmt::format("{}x{} texels ({} covered), K={}, the BVH and per-thread buffers",
                             width, height, texels.count(), options.K)
                     .c_str(),
                 "lower --resolution, --samples or --coeffs");
    HostSink sink;
    if (r.before_bake) r.before_bake();
    const auto start = Clock::now();
    out.info = bake(BakeJob{&mesh, texel_receivers(texels), &sink, nullptr, nullptr, nullptr,
                            r.probes ? &probes : nullptr},
                    options);
    out.seconds_bake = seconds_since(start);
    out.transfer.probes = std::move(probes);
    static_cast<TransferInfo&>(out.transfer) = out.info;
    out.transfer.texels = texel_atlas(texels, uv_set);
    out.transfer.coeffs = sink.take_rows();
    sink.take_estimates(out.transfer);
    out.transfer.stats.peak_bytes_host += out.transfer.coeffs.size() * sizeof(float);
    out.receivers = texels.count();
    out.covered_texels = texels.count();
    nlohmann::json kept = {
        {"texel_bake", {{"resolution", {width, height}}, {"covered_texels", texels.count()}}}};
    if (out.unwrap)
        kept["texel_bake"]["unwrap"] = {{"charts", out.unwrap->charts},
                                        {"texels_per_metre", out.unwrap->texels_per_metre},
                                        {"max_stretch", out.unwrap->max_stretch},
                                        {"mean_stretch", out.unwrap->mean_stretch},
                                        {"added_vertices", out.unwrap->added_vertices}};
    const WriteOptions write =
        r.output ? with_metadata(r.output->write, kept,
                                 {{"texel_bake", {{"estimated_bytes", out.estimated_bytes}}}})
                 : WriteOptions{};
    out.seconds_write = write_file(r, mesh, out.transfer, write, TransferEncoding::f16);
    out.info = out.transfer;
    if (r.output) out.transfer.coeffs = {};
    return out;
}

BakeResult run_refined(const BakeRequest& r, const Mesh& mesh, const RefineOptions& refine) {
    BakeResult out;
    if (r.before_bake) r.before_bake();
    const auto start = Clock::now();
    RefineResult result = bake_refined(mesh, r.options, refine);
    out.seconds_bake = seconds_since(start);
    out.receivers = result.mesh.vertex_count();
    const nlohmann::json meta = {
        {"refinement",
         {{"tolerance", refine.tolerance},
          {"measure", "max over 14 clamped-cosine test lights of |E(a) - E(b)| / (2 pi / 3)"},
          {"max_vertices", refine.max_vertices},
          {"max_edge_split_depth", refine.max_depth},
          {"input_vertices", result.input_vertices},
          {"input_triangles", mesh.triangle_count()},
          {"passes", result.passes},
          {"budget_reached", result.budget_reached},
          {"depth_reached", result.depth_reached},
          {"largest_difference", result.largest_difference}}}};
    out.transfer = std::move(result.transfer);
    out.refined_mesh = std::move(result.mesh);
    const WriteOptions write = r.output ? with_metadata(r.output->write, meta) : WriteOptions{};
    out.seconds_write =
        write_file(r, *out.refined_mesh, out.transfer, write, TransferEncoding::f32);
    out.info = out.transfer;
    if (r.output) out.transfer.coeffs = {};
    out.refinement = std::move(result);
    return out;
}

// The request's checkpoint of `job`: a new one, or the one to resume.
CheckpointFile open_checkpoint(const CheckpointRequest& c, const BakeJob& job,
                               const BakeOptions& options) {
    const TransferInfo description = bake_description(options);
    const std::uint64_t fingerprint = checkpoint_fingerprint(*job.occluders, job.receivers.first,
                                                             job.receivers.count, description);
    const std::size_t floats = description.layout.floats_per_receiver();
    const Receivers& rx = job.receivers;
    // A new checkpoint is an output: not a directory, a device or a file the scene read.
    if (!c.resume) check_output_path(c.path);
    return c.resume ? CheckpointFile::resume(c.path, fingerprint, rx.first, rx.count, floats,
                                             c.sync_seconds)
                    : CheckpointFile::create(c.path, fingerprint, rx.first, rx.count, floats,
                                             c.sync_seconds);
}

// bake(job, options) through `file`: the rows it holds are not baked again. A bake that stops
// with rows saved syncs it and says so (CheckpointKept).
TransferInfo bake_checkpointed(CheckpointFile& file, const BakeJob& job,
                               const BakeOptions& options) {
    CheckpointSink sink(*job.sink, file);
    BakeJob checkpointed = job;
    checkpointed.sink = &sink;
    try {
        return bake_remaining(checkpointed, options, file.done());
    } catch (const Error& e) {
        const std::size_t done = file.done_receivers();
        if (done == 0 && e.code() != ErrorCode::cancelled) throw;
        try {
            file.sync();
        } catch (const Error&) {
            // The rows written so far are in the file; what could not be synced is what the
            // failure was about, and a resume drops a damaged tail.
        }
        throw CheckpointKept(e, done, file.count(), file.path());
    }
}

// bake(job, options) in the rounds of an error-bounded bake where it runs on the CPU (the GPU
// bakes its bound in one pass).
TransferInfo bake_in_rounds(const BakeJob& job, const BakeOptions& options) {
    BakeSession session(job, options);
    if (session.backend() != Device::cpu) return session.bake(job);
    return session.bake_in_rounds(*job.sink, options.progress);
}

BakeResult run_vertices(const BakeRequest& r, const Mesh& mesh) {
    BakeResult out;
    WriteOptions write;
    const Receivers receivers = request_receivers(r, mesh, write);
    out.first = receivers.first;
    out.receivers = receivers.count;
    BakeOptions options = r.options;
    BakeOutput output(r, mesh, receivers, write);
    ProbeGrid probes = request_probes(r, mesh);
    const BakeJob job{&mesh,
                      receivers,
                      &output.sink(),
                      nullptr,
                      nullptr,
                      output.direct(),
                      r.probes ? &probes : nullptr};
    out.estimated_bytes =
        estimate_bake_peak_bytes(mesh.triangle_count(), receivers.count, options, !streamed(r),
                                 bake_bounce_source_count(mesh, options)) +
        probe_bytes(probes, mesh, options);
    // BakeRequest::error_rounds: not for a shard (its rounds would keep the whole set's rows), a
    // stream (rows in memory are what it avoids), probes (baked with each pass) or the
    // interreflected kind (a whole-domain stage of its own). Nor where the rounds' rows would not
    // fit beside the rest: they are for the display, never a reason to refuse a bake that fits
    // in one pass.
    const std::uint64_t round_bytes = round_rows_bytes(receivers.count, options);
    const std::uint64_t limit = memory_limit(r);
    const bool rounds = r.error_rounds && options.target_error > 0 && !streamed(r) &&
                        !is_shard(r) && !r.probes && !r.checkpoint &&
                        !kind_row(options.transfer).whole_domain &&
                        (limit == 0 || out.estimated_bytes + round_bytes <= limit);
    if (rounds) out.estimated_bytes += round_bytes;
    // An interreflected bake counts its operator against the limit and spills the rest beside
    // the output.
    options.memory_budget =
        check_memory(r, out.estimated_bytes, "BVH, rows and per-thread buffers",
                     "lower --samples or --coeffs, bake with --stream or in --shard parts");
    if (r.output) {
        const std::string folder = std::filesystem::path(r.output->path).parent_path().string();
        options.spill_directory = folder.empty() ? "." : folder;
    }
    std::optional<CheckpointFile> checkpoint;
    if (r.checkpoint) checkpoint.emplace(open_checkpoint(*r.checkpoint, job, options));
    if (r.before_bake) r.before_bake();
    const auto start = Clock::now();
    const TransferInfo info = checkpoint ? bake_checkpointed(*checkpoint, job, options)
                              : rounds   ? bake_in_rounds(job, options)
                                         : bake(job, options);
    out.seconds_bake = seconds_since(start);
    out.transfer.probes = std::move(probes);
    out.seconds_write = output.finish(info, out);
    if (checkpoint) checkpoint->remove();  // the output is in place
    out.info = info;
    // The rows held in memory for the file are part of the peak, as finish() counted them for the
    // file's own stats: the bake line and `shprt info` state one number (a --stream bake holds
    // no rows, and neither counts them).
    if (!streamed(r)) out.info.stats.peak_bytes_host = out.transfer.stats.peak_bytes_host;
    if (r.output) out.info.layout.encoding = r.output->encoding.value_or(TransferEncoding::f32);
    return out;
}

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

// "I/N" with 0 ≤ I < N: shard I of N.
VertexShard parse_shard(const std::string& text) {
    const std::size_t slash = text.find('/');
    std::int64_t i = -1, n = 0;
    SHPRT_CHECK(slash != std::string::npos &&
                    parse_integer(text.substr(0, slash), i) == IntegerParse::ok &&
                    parse_integer(text.substr(slash + 1), n) == IntegerParse::ok && i >= 0 &&
                    n >= 1 && i < n && n < 1'000'000'000,
                invalid_argument, "--shard '{}': expected I/N with 0 <= I < N (e.g. 0/4)", text);
    return VertexShard{std::size_t(i), std::size_t(n)};
}

}  // namespace

CheckpointKept::CheckpointKept(const Error& cause, std::size_t done_, std::size_t count_,
                               std::string path_)
    : Error(cause.code(), fmt::format("{}; {} of {} receivers are saved in {}", cause.what(), done_,
                                      count_, path_)),
      done(done_),
      count(count_),
      path(std::move(path_)) {}

ReceiverSet parse_receivers(const ReceiverChoice& c) {
    const bool texel = is_texel(parse_receiver_domain(c.domain));
    SHPRT_CHECK(!texel || !c.resolution.empty() || c.texel_density, invalid_argument,
                "--domain texel needs --resolution W or WxH (or --unwrap --texel-density T)");
    SHPRT_CHECK(texel || (c.resolution.empty() && c.uv_set == 0), invalid_argument,
                "--resolution and --uv-set need --domain texel");
    SHPRT_CHECK(texel || !c.unwrap, invalid_argument, "--unwrap needs --domain texel");
    SHPRT_CHECK(c.unwrap || !c.texel_density, invalid_argument,
                "--texel-density needs --unwrap (it sets the scale of a new atlas)");
    SHPRT_CHECK(!(c.texel_density && !c.resolution.empty()), invalid_argument,
                "--texel-density and --resolution: give one (the density chooses the resolution)");
    SHPRT_CHECK(!(texel && c.refine), invalid_argument,
                "--refine refines vertices: it does not go with --domain texel");
    SHPRT_CHECK(c.refine || (!c.max_vertices && !c.max_edge_split_depth), invalid_argument,
                "--max-vertices and --max-edge-split-depth need --refine");
    SHPRT_CHECK(c.shard.empty() || (!texel && !c.refine), invalid_argument,
                "--shard does not go with {}", texel ? "--domain texel" : "--refine");
    if (texel && c.unwrap) {
        SHPRT_CHECK(c.uv_set == 0, invalid_argument,
                    "--uv-set {}: --unwrap makes a new atlas (UV set 0)", c.uv_set);
        UvAtlasOptions atlas;
        atlas.layout = ChartLayout::conformal;
        atlas.max_angle_deg = kUnwrapMaxAngle;
        TexelGrid grid;
        if (c.texel_density) {
            SHPRT_CHECK(*c.texel_density > 0 && std::isfinite(*c.texel_density), invalid_argument,
                        "--texel-density {}: expected texels per metre, > 0", *c.texel_density);
            atlas.texels_per_metre = *c.texel_density;
        } else {
            const auto [width, height] = parse_resolution(c.resolution);
            SHPRT_CHECK(width == height, invalid_argument,
                        "--resolution {}: --unwrap lays out a square atlas (give W)", c.resolution);
            grid.width = grid.height = atlas.resolution = width;
        }
        grid.unwrap = atlas;
        return grid;
    }
    if (texel) {
        const auto [width, height] = parse_resolution(c.resolution);
        SHPRT_CHECK(c.uv_set >= 0, invalid_argument, "--uv-set {}: must be 0 or more", c.uv_set);
        return TexelGrid{width, height, c.uv_set, std::nullopt};
    }
    if (!c.shard.empty()) return parse_shard(c.shard);
    if (!c.refine) return AllVertices{};
    RefinedVertices r;
    SHPRT_CHECK(*c.refine > 0 && std::isfinite(*c.refine), invalid_argument,
                "--refine {}: the tolerance must be a positive fraction (e.g. 0.05)", *c.refine);
    r.refine.tolerance = *c.refine;
    if (c.max_vertices) {
        SHPRT_CHECK(*c.max_vertices >= 1, invalid_argument, "--max-vertices {}: must be positive",
                    *c.max_vertices);
        r.refine.max_vertices = static_cast<std::size_t>(*c.max_vertices);
    }
    if (c.max_edge_split_depth) {
        SHPRT_CHECK(*c.max_edge_split_depth >= 1 && *c.max_edge_split_depth <= 30, invalid_argument,
                    "--max-edge-split-depth {}: must be 1 to 30", *c.max_edge_split_depth);
        r.refine.max_depth = static_cast<int>(*c.max_edge_split_depth);
    }
    return r;
}

BakeOutput::BakeOutput(const BakeRequest& r, const Mesh& mesh, const Receivers& receivers,
                       WriteOptions write)
    : m_request(r), m_mesh(mesh), m_write(std::move(write)) {
    if (!streamed(r)) return;
    TransferInfo description = bake_description(r.options);
    description.layout.encoding = r.output->encoding.value_or(TransferEncoding::f32);
    m_writer = std::make_unique<ShprtStreamWriter>(r.output->path, mesh, description,
                                                   receivers.first, receivers.count, m_write);
}

BakeOutput::~BakeOutput() = default;

TransferSink& BakeOutput::sink() { return m_writer ? m_writer->sink() : m_host; }

TransferSink* BakeOutput::direct() { return m_writer ? nullptr : &m_direct; }

double BakeOutput::finish(const TransferInfo& info, BakeResult& out) {
    if (m_writer) {
        if (m_request.before_write) m_request.before_write();
        const auto start = Clock::now();
        m_writer->commit(info);
        return seconds_since(start);
    }
    static_cast<TransferInfo&>(out.transfer) = info;
    out.transfer.coeffs = m_host.take_rows();
    out.transfer.direct = m_direct.take_rows();
    m_host.take_estimates(out.transfer);
    out.transfer.stats.peak_bytes_host += out.transfer.coeffs.size() * sizeof(float);
    const double seconds =
        write_file(m_request, m_mesh, out.transfer, m_write, TransferEncoding::f32);
    if (m_request.output) out.transfer.coeffs = {}, out.transfer.direct = {};
    return seconds;
}

Receivers request_receivers(const BakeRequest& r, const Mesh& mesh, WriteOptions& write) {
    Receivers receivers = vertex_receivers(mesh);
    write = r.output ? r.output->write : WriteOptions{};
    if (const auto* shard = std::get_if<VertexShard>(&r.receivers)) {
        const std::size_t V = mesh.vertex_count(), i = shard->index, n = shard->count;
        SHPRT_CHECK(n <= V, invalid_argument,
                    "--shard {}/{}: {} shards of {} vertices leave some empty", i, n, n, V);
        receivers = receivers.range(V * i / n, V * (i + 1) / n - V * i / n);
        write = with_metadata(std::move(write), {}, {{"shard", {{"index", i}, {"of", n}}}});
    }
    write.receiver_first = receivers.first;
    return receivers;
}

std::optional<std::string> request_refusal(const BakeRequest& r) {
    const bool interreflected = kind_row(r.options.transfer).whole_domain;
    const bool other_receivers = is_texels(r) || is_refined(r);
    const char* receivers = is_texels(r) ? "--domain texel" : "--refine";
    if (other_receivers && (streamed(r) || r.distributed))
        return fmt::format("{} does not go with {}", streamed(r) ? "--stream" : "--mpi", receivers);
    if (interreflected && is_shard(r))
        return "--shard: interreflected transfer cannot be sharded (its bounces couple every "
               "vertex); bake it in one process";
    if (interreflected && streamed(r))
        return "--stream: interreflected transfer keeps every vertex's rows in memory for its "
               "bounces; bake it without --stream";
    if (interreflected && r.distributed)
        return "--mpi: interreflected transfer cannot be shared between MPI ranks (its bounces "
               "couple every vertex); bake it in one process";
    if (interreflected && other_receivers)
        return fmt::format(
            "{}: interreflected transfer bakes the scene's own vertices (bake "
            "shadowed or unshadowed transfer)",
            receivers);
    if (r.probes) {
        const char* with = is_shard(r)     ? "--shard (a shard holds part of the vertices)"
                           : streamed(r)   ? "--stream (the rows go to the file as they finish)"
                           : is_refined(r) ? "--refine"
                           : r.distributed ? "MPI"
                           : r.checkpoint  ? "--checkpoint or --resume"
                                           : nullptr;
        if (with)
            return fmt::format(
                "--probes does not go with {} yet; bake the probes in a plain "
                "bake of the scene",
                with);
    }
    if (r.options.device == Device::cuda)
        if (const char* why = gpu_target_error_refusal(r.options)) return why;
    if (r.options.target_error > 0 && (r.distributed || r.checkpoint || is_refined(r)))
        return fmt::format(
            "--target-error does not go with {} yet (its per-receiver estimates are not carried "
            "there); bake without it",
            r.distributed  ? "MPI"
            : r.checkpoint ? "--checkpoint or --resume"
                           : "--refine");
    if (r.distributed && is_shard(r))
        return "--shard and MPI: the ranks already share the bake (use one or the other)";
    if (streamed(r) && r.output->path.empty()) return "--stream needs an output file";
    if (r.checkpoint) {
        const char* option = r.checkpoint->resume ? "--resume" : "--checkpoint";
        if (r.distributed)
            return fmt::format("{}: an MPI bake cannot be checkpointed yet; bake without MPI",
                               option);
        if (other_receivers)
            return fmt::format(
                "{}: texel and refined bakes cannot be checkpointed yet; bake "
                "without --checkpoint",
                option);
        if (const auto why = resume_unsupported(r.options))
            return fmt::format("{}: {}", option, *why);
    }
    return std::nullopt;
}

void check(const BakeRequest& r) {
    validate(r.options);
    if (const auto* shard = std::get_if<VertexShard>(&r.receivers))
        SHPRT_CHECK(shard->count >= 1 && shard->index < shard->count, invalid_argument,
                    "--shard {}/{}: expected I/N with 0 <= I < N", shard->index, shard->count);
    if (const auto* grid = std::get_if<TexelGrid>(&r.receivers);
        grid && !(grid->unwrap && grid->unwrap->texels_per_metre > 0))
        SHPRT_CHECK(grid->width >= 1 && grid->height >= 1 && grid->width <= kMaxTexelSide &&
                        grid->height <= kMaxTexelSide && grid->uv_set >= 0,
                    invalid_argument, "--resolution {}x{}: each side must be 1 to {}", grid->width,
                    grid->height, kMaxTexelSide);
    if (r.checkpoint) {
        const CheckpointRequest& c = *r.checkpoint;
        const char* option = c.resume ? "--resume" : "--checkpoint";
        SHPRT_CHECK(std::isfinite(c.sync_seconds) && c.sync_seconds >= 0, invalid_argument,
                    "--checkpoint-every {}: expected seconds, 0 or more", c.sync_seconds);
        SHPRT_CHECK(!r.output || (c.path != r.output->path && !same_file(c.path, r.output->path)),
                    invalid_argument, "{} {}: the checkpoint cannot be the output file", option,
                    c.path);
    }
    if (r.probes)
        SHPRT_CHECK(!kind_row(r.options.transfer).interreflection ||
                        sh_count(r.probes->bands) <= r.options.K,
                    invalid_argument,
                    "--probe-bands {}: interreflected probes read the bake's bounce light in "
                    "their {} coefficients, but the bake has K = {} (give --bands {} or more)",
                    r.probes->bands, sh_count(r.probes->bands), r.options.K, r.probes->bands);
    if (const auto why = request_refusal(r)) fail(ErrorCode::unsupported, "{}", *why);
}

BakeResult run(const BakeRequest& request, const Mesh& mesh) {
    check(request);
    if (const auto* grid = std::get_if<TexelGrid>(&request.receivers))
        return run_texels(request, mesh, *grid);
    if (const auto* refined = std::get_if<RefinedVertices>(&request.receivers))
        return run_refined(request, mesh, refined->refine);
    return run_vertices(request, mesh);
}

}  // namespace shprt
