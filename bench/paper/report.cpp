// `shprt bench paper`, the reports: the markdown table beside the paper's numbers, CSVs, and the
// gnuplot plots (error and time against K, the sampling study, the edge profiles).
#include "paper/paper_study.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/log.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

extern char** environ;

namespace shprt::paper {
namespace {

std::string num(double v, const char* f = "{:.3g}") {
    return std::isnan(v) ? std::string("—") : fmt::format(fmt::runtime(f), v);
}
std::string pct(double v, const char* f = "{:.2f}") { return num(100 * v, f); }
std::string csv(double v) { return std::isnan(v) ? std::string("nan") : fmt::format("{:.9g}", v); }

std::string duration(double s) {
    if (std::isnan(s)) return "—";
    if (s < 60) return fmt::format("{:.2f} s", s);
    if (s < 3600) return fmt::format("{} min {:.0f} s", int(s / 60), s - 60 * int(s / 60));
    return fmt::format("{} h {} min", int(s / 3600), int((s - 3600 * int(s / 3600)) / 60));
}

double rays_per_s(const BakeRun& b) {
    return b.ran && b.stats.seconds_total > 0 ? double(b.stats.rays_cast) / b.stats.seconds_total
                                              : kNaN;
}

std::string mrays(double v) { return std::isnan(v) ? "—" : fmt::format("{:.1f} M", v / 1e6); }

void write_text(const std::string& path, const std::string& text) {
    AtomicFile f(path);
    f.write(text);
    f.commit();
}

std::vector<const KRow*> paper_rows(const Results& r) {
    std::vector<const KRow*> rows;
    for (const KRow& k : r.rows)
        if (k.paper_size) rows.push_back(&k);
    return rows;
}

// One markdown row: a label and one cell per paper-size row.
template <class F>
std::string md_row(const std::string& label, const std::vector<const KRow*>& rows, F cell) {
    std::string s = "| " + label + " |";
    for (const KRow* k : rows) s += fmt::format(" {} |", cell(*k));
    return s + "\n";
}

std::string ringing_table(const Results& r) {
    std::string s =
        "| K | light | RMSE, % of mean | max error, % | negative vertices, % | most negative / "
        "mean | saturation |\n|---:|---|---:|---:|---:|---:|---:|\n";
    for (const KRow& k : r.rows) {
        if (!k.paper_size) continue;
        const std::pair<const char*, const LightScore*> v[] = {
            {"sun", &k.sun_improved},
            {"sun, Hann window", &k.sun_hann},
            {"sun, Lanczos window", &k.sun_lanczos}};
        for (const auto& [name, ls] : v)
            s += fmt::format(
                "| {} | {} | {} | {} | {} | {} | {} |\n", k.K, name, pct(ls->error.relative_rmse()),
                pct(ls->error.relative_max(), "{:.0f}"), pct(ls->ringing.negative_fraction),
                num(ls->ringing.most_negative_relative, "{:.3f}"),
                ls->has_contrast ? num(ls->contrast.saturation, "{:.3f}") : "—");
    }
    return s;
}

std::string all_sizes_table(const Results& r) {
    std::string s =
        "| K | bands | CPU bake | Mrays/s | GPU bake | sky RMSE, % | sun RMSE, % | saturation | "
        "negative, % | edge width, cm | sky / sun RMSE, Sobol, % | frames/s |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const KRow& k : r.rows) {
        int bands = 1;
        while (bands * bands < k.K) ++bands;
        s += fmt::format(
            "| {} | {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", k.K, bands,
            bands * bands == k.K ? "" : " (partial)",
            k.cpu.ran ? duration(k.cpu.stats.seconds_total) : "—",
            k.cpu.ran ? num(rays_per_s(k.cpu) / 1e6, "{:.1f}") : "—",
            k.gpu.ran ? duration(k.gpu.stats.seconds_total) : "—", pct(k.sky.error.relative_rmse()),
            pct(k.sun.error.relative_rmse()),
            k.sun.has_contrast ? num(k.sun.contrast.saturation, "{:.3f}") : "—",
            pct(k.sun.ringing.negative_fraction),
            k.sun.has_edge && k.sun.edge.valid ? num(100 * k.sun.edge.width, "{:.1f}") : "—",
            pct(k.sky_improved.error.relative_rmse()) + " / " +
                pct(k.sun_improved.error.relative_rmse()),
            num(k.fps, "{:.1f}"));
    }
    return s;
}

std::string study_table(const Results& r) {
    if (r.study.empty()) return "";
    std::string s = fmt::format(
        "K = {}; *error* = relative RMSE against the ground truth (SH truncation + sampling "
        "noise), *noise* = relative RMSE against the converged K = {} projection (Sobol, S = "
        "{}): sampling noise alone.\n\n"
        "| sampler | S | sky error, % | sun error, % | sky noise, % | sun noise, % | bake |\n"
        "|---|---:|---:|---:|---:|---:|---:|\n",
        r.study_K, r.study_K, r.study_reference_samples);
    for (const StudyRow& row : r.study)
        s += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", to_string(row.sampler),
                         row.samples, pct(row.sky_error), pct(row.sun_error),
                         pct(row.sky_noise, "{:.3f}"), pct(row.sun_noise, "{:.3f}"),
                         duration(row.seconds));
    return s;
}

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
std::string gnuplot_script(const Results& r) {
    bool has_gpu = false;
    std::string xtics = "set xtics (";
    for (const KRow& k : r.rows) {
        has_gpu = has_gpu || k.gpu.ran;
        xtics += fmt::format("{}{}", &k == &r.rows.front() ? "" : ", ", k.K);
    }
    xtics += ")";
    if (!r.rows.empty())  // a margin, so that the end ticks keep their labels
        xtics += fmt::format("\nset xrange [{}:{}]", 0.9 * r.rows.front().K, 1.1 * r.rows.back().K);
    std::string s =
        R"(# Plots of `shprt bench paper` (written by the bench; rerun: cd DIR && gnuplot plot_paper.gp)
if (!exists("suffix")) suffix = ''
set datafile separator ','
set datafile missing 'nan'
set terminal pngcairo size 800,560 font ',11'
set grid
set key below
set logscale x 2
)" + xtics +
        R"(

set output 'error_vs_K.png'.suffix
set title 'Error of the SH shading against the ground truth (room, per vertex)'
set xlabel 'basis size K (coefficients)'
set ylabel 'RMSE over vertices, % of the mean irradiance'
set logscale y
plot 'paper_table.csv' every ::1 using 1:($14*100) with linespoints lw 2 title 'smooth sky', \
     '' every ::1 using 1:($20*100) with linespoints lw 2 title 'sun 2° + dim sky', \
     '' every ::1 using 1:($44*100) with linespoints lw 2 dt 2 title 'smooth sky, improved (Sobol)', \
     '' every ::1 using 1:($45*100) with linespoints lw 2 dt 2 title 'sun 2°, improved (Sobol)', \
     '' every ::1 using 1:($38*100) with lines lc rgb 'gray' dt 3 title 'ground truth own error (sky)', \
     '' every ::1 using 1:($39*100) with lines lc rgb 'black' dt 3 title 'ground truth own error (sun)'

set output 'time_vs_K.png'.suffix
set title 'Precompute time of the room'
set ylabel 'seconds'
set key inside top left
plot 'paper_table.csv' every ::1 using 1:3 with linespoints lw 2 title 'shprt CPU', \
)" +
        std::string(
            has_gpu ? "     '' every ::1 using 1:9 with linespoints lw 2 title 'shprt GPU', \\\n"
                    : "") +
        R"(     '' every ::1 using 1:40 with linespoints lw 2 dt 2 title 'paper CPU (Athlon64 X2)', \
     '' every ::1 using 1:41 with linespoints lw 2 dt 2 title 'paper GPU (GeForce 8400GS)'

)";
    if (!r.study.empty())
        s += R"(unset logscale
set xtics autofreq
set autoscale x
set logscale xy
set output 'sampling_study.png'.suffix
set title sprintf('Sampling noise against S at K = %d (relative RMSE against the converged projection)', )" +
             std::to_string(r.study_K) + R"()
set xlabel 'directions S'
set ylabel 'noise, % of the mean irradiance'
set key below
plot for [smp in "uniform stratified fibonacci sobol"] 'sampling_study.csv' every ::1 \
       using 2:(strcol(1) eq smp ? column(6)*100 : NaN) with linespoints lw 2 title smp.' (sky)', \
     for [smp in "uniform stratified fibonacci sobol"] '' every ::1 \
       using 2:(strcol(1) eq smp ? column(7)*100 : NaN) with linespoints lw 1 dt 2 title smp.' (sun)'

)";
    if (r.gt_has_edge)
        s += R"(unset logscale
set xtics autofreq
set autoscale x
set output 'edge_profile.png'.suffix
set title 'Irradiance across the back wall''s shadow edge on the floor (sun 2°, mean of 3 lines)'
set xlabel 'distance along the floor, m (lit side at 0)'
set ylabel 'irradiance (luminance)'
set key below
)";
    // Columns: 2 = truth, then the paper's-method profiles, then the improved ones (same
    // colour per K: solid = paper's method, dashed = improved).
    std::vector<int> Ks;
    for (const KRow& k : r.rows)
        if (k.paper_size && k.sun.has_edge) Ks.push_back(k.K);
    std::string plot =
        "plot 'edge_profiles.csv' every ::1 using 1:2 with lines lw 3 lc rgb 'black' "
        "title 'ground truth'";
    for (std::size_t i = 0; i < Ks.size(); ++i)
        plot += fmt::format(", '' every ::1 using 1:{} with lines lw 1.5 lc {} title 'K = {}'",
                            3 + i, i + 1, Ks[i]);
    for (std::size_t i = 0; i < Ks.size(); ++i)
        plot += fmt::format(
            ", '' every ::1 using 1:{} with lines lw 1.5 dt 2 lc {} title 'K = {}, "
            "Sobol'",
            3 + Ks.size() + i, i + 1, Ks[i]);
    if (r.gt_has_edge) s += plot + "\n";
    return s;
}

bool run_gnuplot(const std::string& dir, std::string& why) {
    // gnuplot -e "suffix='.tmp'" plot_paper.gp, in `dir` (the script cds itself: see below).
    const std::string abs = std::filesystem::absolute(dir).string();
    const std::string script = abs + "/plot_paper.gp";  // opened after the cd below
    std::string cd = "cd '";
    for (char c : abs) cd += c == '\'' ? std::string("''") : std::string(1, c);
    cd += "'; suffix='.tmp'";
    const char* argv[] = {"gnuplot", "-e", cd.c_str(), script.c_str(), nullptr};
    pid_t pid = 0;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    const int rc =
        posix_spawnp(&pid, "gnuplot", &actions, nullptr, const_cast<char**>(argv), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
        why = fmt::format("gnuplot not found or not runnable ({})", std::strerror(rc));
        return false;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        why = "gnuplot failed (see its messages above)";
        return false;
    }
    return true;
}

}  // namespace

std::string markdown_table(const Results& r) {
    const std::vector<const KRow*> rows = paper_rows(r);
    std::string s = "| basis size K (coefficients) |";
    std::string rule = "|---|";
    for (const KRow* k : rows) s += fmt::format(" {} |", k->K), rule += "---:|";
    s += "\n" + rule + "\n";
    const auto paper = [](auto member) {
        return [member](const KRow& k) {
            const PaperColumn* p = paper_column(k.K);
            return p ? std::string(p->*member) : std::string("—");
        };
    };
    const std::string threads =
        r.rows.empty() || !r.rows[0].cpu.ran ? std::string("") : r.rows[0].cpu.stats.device_name;
    s += md_row("**display rate, frames/s** — paper", rows, paper(&PaperColumn::fps));
    s += md_row("shprt, frames/s (" + (r.gl_context.empty() ? "not measured" : r.gl_context) + ")",
                rows, [](const KRow& k) { return num(k.fps, "{:.1f}"); });
    s += md_row("**shadow edge aliasing** — paper", rows, paper(&PaperColumn::edge_aliasing));
    s += md_row(
        fmt::format("shprt: shadow-edge width 10–90 %, cm (truth: {} cm)",
                    r.gt_has_edge && r.gt_edge.valid ? num(100 * r.gt_edge.width, "{:.1f}") : "—"),
        rows, [](const KRow& k) {
            return k.sun.has_edge && k.sun.edge.valid ? num(100 * k.sun.edge.width, "{:.1f}")
                                                      : std::string("—");
        });
    s += md_row("shprt: edge overshoot / undershoot, % of the edge step", rows, [](const KRow& k) {
        return k.sun.has_edge && k.sun.edge.valid ? pct(k.sun.edge.overshoot, "{:.0f}") + " / " +
                                                        pct(k.sun.edge.undershoot, "{:.0f}")
                                                  : std::string("—");
    });
    s += md_row("shprt improved (Sobol): edge width, cm / overshoot, %", rows, [](const KRow& k) {
        const EdgeMeasure& e = k.sun_improved.edge;
        return k.sun_improved.has_edge && e.valid
                   ? num(100 * e.width, "{:.1f}") + " / " + pct(e.overshoot, "{:.0f}")
                   : std::string("—");
    });
    s += md_row("**shadow fill** — paper", rows, paper(&PaperColumn::shadow_fill));
    s +=
        md_row("shprt: saturation (shadow contrast ÷ truth's; 1 = right)", rows, [](const KRow& k) {
            return k.sun.has_contrast ? num(k.sun.contrast.saturation, "{:.3f}") : std::string("—");
        });
    s += md_row("shprt: shadow fill error, % of the truth's shadow depth", rows, [](const KRow& k) {
        return k.sun.has_contrast ? pct(k.sun.contrast.shadow_fill_error, "{:.1f}")
                                  : std::string("—");
    });
    s += md_row("shprt improved: saturation / shadow fill error, %", rows, [](const KRow& k) {
        const LightScore& l = k.sun_improved;
        return l.has_contrast ? num(l.contrast.saturation, "{:.3f}") + " / " +
                                    pct(l.contrast.shadow_fill_error, "{:.1f}")
                              : std::string("—");
    });
    s += md_row("**artifacts** — paper", rows, paper(&PaperColumn::artifacts));
    s += md_row(fmt::format("shprt: RMSE (СКО) over vertices, sun, % of mean (truth's own: {} %)",
                            pct(r.gt_sun_noise, "{:.3f}")),
                rows, [](const KRow& k) { return pct(k.sun.error.relative_rmse()); });
    s += md_row("shprt: max error, sun, % of mean", rows,
                [](const KRow& k) { return pct(k.sun.error.relative_max(), "{:.0f}"); });
    s += md_row(fmt::format("shprt: RMSE over vertices, smooth sky, % of mean (truth's own: {} %)",
                            pct(r.gt_sky_noise, "{:.3f}")),
                rows, [](const KRow& k) { return pct(k.sky.error.relative_rmse()); });
    s += md_row("shprt: max error, smooth sky, % of mean", rows,
                [](const KRow& k) { return pct(k.sky.error.relative_max(), "{:.0f}"); });
    s += md_row("shprt: vertices with negative irradiance, sun, %", rows,
                [](const KRow& k) { return pct(k.sun.ringing.negative_fraction); });
    s += md_row("shprt: most negative irradiance ÷ mean, sun", rows,
                [](const KRow& k) { return num(k.sun.ringing.most_negative_relative, "{:.3f}"); });
    s += md_row("shprt: vertices brighter than the brightest true value, sun, %", rows,
                [](const KRow& k) { return pct(k.sun.ringing.overshoot_fraction); });
    s += md_row("shprt improved: RMSE sun / sky, % of mean", rows, [](const KRow& k) {
        return pct(k.sun_improved.error.relative_rmse()) + " / " +
               pct(k.sky_improved.error.relative_rmse());
    });
    s += md_row("shprt improved: negative vertices, sun, %", rows,
                [](const KRow& k) { return pct(k.sun_improved.ringing.negative_fraction); });
    s += md_row("**precompute on CPU** — paper (Athlon64 X2)", rows, paper(&PaperColumn::cpu));
    s += md_row(fmt::format("shprt CPU, total ({}, S = {}, {})", threads, r.options.samples,
                            to_string(r.options.sampler)),
                rows, [](const KRow& k) {
                    return k.cpu.ran ? duration(k.cpu.stats.seconds_total) : std::string("—");
                });
    s += md_row("shprt CPU: BVH + trace + project, s", rows, [](const KRow& k) {
        return k.cpu.ran ? fmt::format("{:.2f} + {:.2f} + {:.2f}", k.cpu.stats.seconds_bvh,
                                       k.cpu.stats.seconds_trace, k.cpu.stats.seconds_project)
                         : std::string("—");
    });
    s += md_row("shprt CPU: rays/s", rows, [](const KRow& k) { return mrays(rays_per_s(k.cpu)); });
    s += md_row("shprt CPU: faster than the paper's CPU by", rows, [](const KRow& k) {
        const PaperColumn* p = paper_column(k.K);
        return k.cpu.ran && p ? fmt::format("{:.0f}×", p->cpu_seconds / k.cpu.stats.seconds_total)
                              : std::string("—");
    });
    s += md_row("shprt improved bake (Sobol, same S)", rows, [](const KRow& k) {
        return k.improved.ran ? duration(k.improved.stats.seconds_total) : std::string("—");
    });
    s += md_row("**precompute on GPU** — paper (GeForce 8400GS)", rows, paper(&PaperColumn::gpu));
    s += md_row("shprt GPU (" + r.gpu + ")", rows, [](const KRow& k) {
        return k.gpu.ran ? duration(k.gpu.stats.seconds_total) + ", " + mrays(rays_per_s(k.gpu)) +
                               "rays/s"
                         : std::string("—");
    });
    return s;
}

void write_reports(Results& r, const Reporter& reporter) {
    const std::string dir = r.options.out_dir;
    const auto put = [&](const std::string& name, const std::string& text) {
        write_text(dir + "/" + name, text);
        r.files.push_back(name);
    };
    put("paper_table.csv", csv_table(r));
    if (!r.study.empty()) put("sampling_study.csv", study_csv(r));
    if (r.gt_has_edge) put("edge_profiles.csv", profiles_csv(r));
    put("plot_paper.gp", gnuplot_script(r));

    std::string why;
    if (run_gnuplot(dir, why)) {
        for (const char* name :
             {"error_vs_K.png", "time_vs_K.png", "sampling_study.png", "edge_profile.png"}) {
            const std::string tmp = dir + "/" + name + ".tmp";
            std::error_code ec;
            if (!std::filesystem::exists(tmp, ec)) continue;
            std::filesystem::rename(tmp, dir + "/" + name, ec);
            if (!ec) r.files.push_back(name);
        }
    } else {
        r.warnings.push_back("plots skipped: " + why);
        if (reporter.warning) reporter.warning("plots skipped: " + why);
    }

    std::string md = "# The paper's table, measured\n\n";
    md += fmt::format(
        "Scene: built-in room, {} vertices, {} triangles. Machine: {} ({}); GPU: {}.\n"
        "Lights: smooth sky {}; sun {} (2° radius, irradiance 3 at normal incidence, plus the "
        "sky at {}×).\nGround truth: direct Monte Carlo without SH, {} cosine-weighted sky + {} "
        "sun-cone directions per vertex, two independent passes averaged ({:.1f} s, {:.0f} M "
        "rays).\nCommand: `{}` ({:.0f} s in all).\n\n",
        r.vertices, r.triangles, r.machine, r.cpu_threads, r.gpu, r.sky_spec, r.sun_spec, 0.15,
        r.gt_sky_samples, r.gt_disc_samples, r.gt_seconds, double(r.gt_rays) / 1e6, r.command,
        r.seconds_total);
    if (!r.rows.empty() && r.rows[0].sun.has_contrast) {
        const ShadowContrast& c = r.rows[0].sun.contrast;
        md += fmt::format(
            "Shadow sets (sun light): {} open floor vertices fully in the sun (true mean E = "
            "{:.3f}), {} fully in shadow (true mean E = {:.3f}).\n\n",
            c.lit_count, c.reference_lit, c.shadow_count, c.reference_shadow);
    }
    md += markdown_table(r);
    md +=
        "\nDefinitions: docs/paper_table.md. Paper rows in bold are copied from the paper "
        "(its quality rows are judgements by eye).\n";
    md += "\n## All basis sizes measured\n\n" + all_sizes_table(r);
    md +=
        "\n## Ringing control: the improved bake under a windowed sun light\n\n" + ringing_table(r);
    if (!r.study.empty()) md += "\n## Sampling study\n\n" + study_table(r);
    if (!r.warnings.empty()) {
        md += "\n## Warnings\n\n";
        for (const auto& w : r.warnings) md += "* " + w + "\n";
    }
    md += "\n## Files\n\n";
    for (const auto& f : r.files) md += "* " + f + "\n";
    put("paper_table.md", md);
}

}  // namespace shprt::paper
