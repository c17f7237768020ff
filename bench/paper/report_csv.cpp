// The report stage of the paper study, CSV (report.hpp): the table with every number, the sampling
// study and the edge profiles, for plots and other tools.
#include "paper/report.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace shprt::paper::report {

std::string csv_table(const Results& r) {
    std::string s =
        "K,paper_size,cpu_seconds,cpu_bvh_s,cpu_trace_s,cpu_project_s,rays,cpu_rays_per_s,"
        "gpu_seconds,gpu_rays_per_s,fps,frame_ms,sky_rmse,sky_rel_rmse,sky_max,sky_rel_max,"
        "sky_negative_fraction,sky_most_negative_rel,sun_rmse,sun_rel_rmse,sun_max,sun_rel_max,"
        "sun_negative_fraction,sun_most_negative_rel,sun_overshoot_fraction,sun_saturation,"
        "sun_shadow_fill_error,edge_width_m,edge_overshoot,edge_undershoot,sun_hann_rel_rmse,"
        "sun_hann_negative_fraction,sun_hann_saturation,sun_lanczos_rel_rmse,"
        "sun_lanczos_negative_fraction,sun_lanczos_saturation,truth_edge_width_m,"
        "truth_sky_noise,truth_sun_noise,paper_cpu_s,paper_gpu_s,paper_fps,improved_seconds,"
        "sky_improved_rel_rmse,sun_improved_rel_rmse,sun_improved_negative_fraction,"
        "sun_improved_saturation,sun_improved_shadow_fill_error,improved_edge_width_m,"
        "improved_edge_overshoot\n";
    for (const KRow& k : r.rows) {
        const PaperColumn* p = paper_column(k.K);
        const auto sat = [](const LightScore& l) {
            return l.has_contrast ? l.contrast.saturation : kNaN;
        };
        const bool edge = k.sun.has_edge && k.sun.edge.valid;
        const bool iedge = k.sun_improved.has_edge && k.sun_improved.edge.valid;
        const double vals[] = {
            k.cpu.ran ? k.cpu.stats.seconds_total : kNaN,
            k.cpu.ran ? k.cpu.stats.seconds_bvh : kNaN,
            k.cpu.ran ? k.cpu.stats.seconds_trace : kNaN,
            k.cpu.ran ? k.cpu.stats.seconds_project : kNaN,
            k.cpu.ran ? double(k.cpu.stats.rays_cast) : kNaN,
            rays_per_s(k.cpu),
            k.gpu.ran ? k.gpu.stats.seconds_total : kNaN,
            rays_per_s(k.gpu),
            k.fps,
            k.frame_ms,
            k.sky.error.rmse,
            k.sky.error.relative_rmse(),
            k.sky.error.max_abs,
            k.sky.error.relative_max(),
            k.sky.ringing.negative_fraction,
            k.sky.ringing.most_negative_relative,
            k.sun.error.rmse,
            k.sun.error.relative_rmse(),
            k.sun.error.max_abs,
            k.sun.error.relative_max(),
            k.sun.ringing.negative_fraction,
            k.sun.ringing.most_negative_relative,
            k.sun.ringing.overshoot_fraction,
            sat(k.sun),
            k.sun.has_contrast ? k.sun.contrast.shadow_fill_error : kNaN,
            edge ? k.sun.edge.width : kNaN,
            edge ? k.sun.edge.overshoot : kNaN,
            edge ? k.sun.edge.undershoot : kNaN,
            k.sun_hann.error.relative_rmse(),
            k.sun_hann.ringing.negative_fraction,
            sat(k.sun_hann),
            k.sun_lanczos.error.relative_rmse(),
            k.sun_lanczos.ringing.negative_fraction,
            sat(k.sun_lanczos),
            r.gt_has_edge && r.gt_edge.valid ? r.gt_edge.width : kNaN,
            r.gt_sky_noise,
            r.gt_sun_noise,
            p ? p->cpu_seconds : kNaN,
            p ? p->gpu_seconds : kNaN,
            p ? 18.5 : kNaN,
            k.improved.ran ? k.improved.stats.seconds_total : kNaN,
            k.sky_improved.error.relative_rmse(),
            k.sun_improved.error.relative_rmse(),
            k.sun_improved.ringing.negative_fraction,
            sat(k.sun_improved),
            k.sun_improved.has_contrast ? k.sun_improved.contrast.shadow_fill_error : kNaN,
            iedge ? k.sun_improved.edge.width : kNaN,
            iedge ? k.sun_improved.edge.overshoot : kNaN};
        s += fmt::format("{},{}", k.K, k.paper_size ? 1 : 0);
        for (double v : vals) s += fmt::format(",{}", csv(v));
        s += "\n";
    }
    return s;
}

std::string study_csv(const Results& r) {
    std::string s = "sampler,S,seconds,sky_rel_error,sun_rel_error,sky_rel_noise,sun_rel_noise\n";
    for (const StudyRow& row : r.study)
        s += fmt::format("{},{},{},{},{},{},{}\n", to_string(row.sampler), row.samples,
                         csv(row.seconds), csv(row.sky_error), csv(row.sun_error),
                         csv(row.sky_noise), csv(row.sun_noise));
    return s;
}

std::string profiles_csv(const Results& r) {
    std::string s = "position_m,truth";
    std::vector<const KRow*> rows;
    for (const KRow& k : r.rows)
        if (k.paper_size && k.sun.has_edge) rows.push_back(&k), s += fmt::format(",K{}", k.K);
    for (const KRow* k : rows) s += fmt::format(",K{}_improved", k->K);
    s += "\n";
    for (std::size_t i = 0; i < r.gt_profile.value.size(); ++i) {
        s += fmt::format("{},{}", csv(r.gt_profile.position[i]), csv(r.gt_profile.value[i]));
        const auto at = [i](const Profile& p) { return i < p.value.size() ? p.value[i] : kNaN; };
        for (const KRow* k : rows) s += fmt::format(",{}", csv(at(k->sun_profile)));
        for (const KRow* k : rows) s += fmt::format(",{}", csv(at(k->improved_profile)));
        s += "\n";
    }
    return s;
}

// The gnuplot script (columns of the CSVs above, 1-based). Run from the output directory.
}  // namespace shprt::paper::report
