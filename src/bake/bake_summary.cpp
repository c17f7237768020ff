// The summary of a finished bake request (bake/bake_summary.hpp): the lines `shprt bake` prints.
#include "shprt/bake/bake_summary.hpp"

#include "shprt/core/log.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/transfer/estimates.hpp"
#include "shprt/transfer/kind_table.hpp"
#include "shprt/transfer/probes.hpp"

#include <fmt/printf.h>

namespace shprt {
namespace {

void add_interreflection(std::string& out, const TransferInfo& transfer) {
    const BakeStats& s = transfer.stats;
    const InterreflectionInfo& ir = transfer.interreflection;
    out += fmt::sprintf(
        "interreflection: %d bounce%s (%s), operator %.3f s (nnz(A) = %llu, %.1f MiB), bounces "
        "%.3f s; albedo: %s\n",
        ir.bounces, ir.bounces == 1 ? "" : "s", describe_convergence(ir).c_str(),
        s.seconds_operator, static_cast<unsigned long long>(ir.operator_nnz),
        double(ir.operator_bytes) / (1024.0 * 1024.0), s.seconds_bounces, ir.albedo_source.c_str());
    if (s.operator_bytes_spilled > 0)
        out += fmt::sprintf(
            "operator: %.1f MiB of A past the memory budget, read memory-mapped from a "
            "temporary file beside the output\n",
            double(s.operator_bytes_spilled) / (1024.0 * 1024.0));
}

// The sampler as the summary lines name it: "sobol", or "sobol, local" for a local set.
std::string sampling_label(const TransferInfo& t) {
    std::string label = to_string(t.sampler);
    if (t.direction_frame == DirectionFrame::local) label += ", local";
    if (t.target_error > 0) label += fmt::format(", at most, to error {:.3g}", t.target_error);
    return label;
}

// An error-bounded bake's estimates: "error bound: receivers per prefix 64: 1200, ... (mean 391);
// estimated error worst ..., 99th percentile ..., mean ...; receivers ≤ E/4: ..., over E: ...".
void add_estimates(std::string& out, const TransferSet& t) {
    const EstimateSummary e = summarize_estimates(t);
    if (e.receivers_per_samples.empty()) return;
    if (const std::size_t over = e.receivers_per_error_band[3]; over > 0)
        log_warn(
            "{} of {} receivers stopped at --max-samples {} with an estimated error above "
            "--target-error {:.3g} (worst {:.3g}); they are sampled as far as that cap allows, as "
            "asked (a larger --max-samples refines them further)",
            over, t.receiver_error.size(), t.samples, t.target_error, e.error.worst);
    out += fmt::sprintf("error bound: receivers per prefix %s; estimated error %s; receivers %s\n",
                        samples_histogram_text(e).c_str(), error_spread_text(e.error).c_str(),
                        error_bands_text(e).c_str());
}

// "baked N texels|vertices, ...": the summary of a texel or refined bake.
void add_bake_line(std::string& out, const char* what, const BakeResult& r,
                   const std::string& output) {
    const TransferInfo& t = r.info;
    const BakeStats& s = t.stats;
    const double seconds = r.seconds_bake;
    out += fmt::sprintf(
        "baked %zu %s, K=%d, S=%d (%s, %s): trace %.3f s, project %.3f s, total %.3f s; %.0f "
        "receivers/s, %.1f Mrays/s, peak %.1f MiB, %s -> %s\n",
        r.receivers, what, t.layout.K, t.samples, to_string(t.kind), sampling_label(t).c_str(),
        s.seconds_trace, s.seconds_project, seconds,
        seconds > 0 ? double(r.receivers) / seconds : 0.0,
        s.seconds_trace > 0 ? double(s.rays_cast) / s.seconds_trace * 1e-6 : 0.0,
        double(s.peak_bytes_host) / (1024.0 * 1024.0), s.device_name.c_str(), output.c_str());
    add_estimates(out, r.transfer);
}

void add_refinement(std::string& out, const RefineResult& r, const RefineOptions& refine,
                    std::size_t input_triangles, const Mesh& refined) {
    const std::size_t V = refined.vertex_count();
    if (r.budget_reached)
        log_warn(
            "refinement stopped at --max-vertices {}: {} edges still differ by more than {} "
            "(largest {:.3g}); the mesh is refined as far as that budget allows, as asked (a "
            "larger --max-vertices refines further)",
            V, r.edges_over, refine.tolerance, r.largest_difference);
    else if (r.depth_reached)
        log_warn(
            "refinement stopped at --max-edge-split-depth {}: {} edges still differ by more "
            "than {} (largest {:.3g}); they are as short as that depth allows, as asked (a "
            "larger --max-edge-split-depth splits further)",
            refine.max_depth, r.edges_over, refine.tolerance, r.largest_difference);
    out += fmt::sprintf(
        "refined: %zu -> %zu vertices, %zu -> %zu triangles in %d pass%s; largest edge "
        "difference %.3g (tolerance %g)\n",
        r.input_vertices, V, input_triangles, refined.triangle_count(), r.passes,
        r.passes == 1 ? "" : "es", r.largest_difference, refine.tolerance);
}

}  // namespace

std::string bake_summary(const BakeRequest& request, const Mesh& mesh, const BakeResult& r,
                         const std::string& output, double seconds_load) {
    std::string out;
    const TransferInfo& transfer = r.info;
    if (!r.transfer.probes.empty())
        out += fmt::sprintf("probes: %s\n", describe_probes(r.transfer.probes).c_str());
    if (const auto* grid = std::get_if<TexelGrid>(&request.receivers)) {
        if (r.unwrap) out += fmt::sprintf("unwrap: %s\n", describe(*r.unwrap).c_str());
        const int width = r.unwrap ? r.unwrap->resolution : grid->width;
        const int height = r.unwrap ? r.unwrap->resolution : grid->height;
        out += fmt::sprintf("texels: %dx%d, %llu covered (%.1f%%), UV set %d, %s\n", width, height,
                            static_cast<unsigned long long>(r.covered_texels),
                            100.0 * double(r.covered_texels) / (double(width) * height),
                            r.unwrap ? 0 : grid->uv_set, to_string(transfer.layout.encoding));
        add_bake_line(out, "texels", r, output);
        return out;
    }
    if (const auto* refined = std::get_if<RefinedVertices>(&request.receivers)) {
        add_refinement(out, r.refinement, refined->refine, mesh.triangle_count(), *r.refined_mesh);
        add_bake_line(out, "vertices", r, output);
        return out;
    }
    if (kind_row(transfer.kind).interreflection) add_interreflection(out, transfer);
    const BakeStats& s = transfer.stats;
    const double rays_per_second = s.seconds_trace > 0 ? double(s.rays_cast) / s.seconds_trace : 0;
    out += fmt::sprintf(
        "baked %zu vertices, K=%d, S=%d (%s, %s): load %.3f s, bvh %.3f s, trace %.3f s, "
        "project %.3f s, write %.3f s; %.1f Mrays/s, peak %.1f MiB, %s -> %s\n",
        r.receivers, transfer.layout.K, transfer.samples, to_string(transfer.kind),
        sampling_label(transfer).c_str(), seconds_load, s.seconds_bvh, s.seconds_trace,
        s.seconds_project, r.seconds_write, rays_per_second * 1e-6,
        double(s.peak_bytes_host) / (1024.0 * 1024.0), s.device_name.c_str(), output.c_str());
    add_estimates(out, r.transfer);
    return out;
}

}  // namespace shprt
