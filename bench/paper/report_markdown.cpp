// The report stage of the paper study, markdown (report.hpp): paper_table.md, with the main table
// beside the paper's numbers (markdown_table, also printed by `shprt bench paper`).
#include "paper/lights.hpp"
#include "paper/report.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace shprt::paper {

using namespace report;  // the cell formats

namespace {

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

namespace report {

std::string paper_table_md(const Results& r) {
    std::string md = "# The paper's table, measured\n\n";
    md += fmt::format(
        "Scene: built-in room, {} vertices, {} triangles. Machine: {} ({}); GPU: {}.\n"
        "Lights: smooth sky {}; sun {} (2° radius, irradiance 3 at normal incidence, plus the "
        "sky at {}×).\nGround truth: direct Monte Carlo without SH, {} cosine-weighted sky + {} "
        "sun-cone directions per vertex, two independent passes averaged ({:.1f} s, {:.0f} M "
        "rays).\nCommand: `{}` ({:.0f} s in all).\n\n",
        r.vertices, r.triangles, r.machine, r.cpu_threads, r.gpu, r.sky_spec, r.sun_spec,
        kSunSkyScale, r.gt_sky_samples, r.gt_disc_samples, r.gt_seconds, double(r.gt_rays) / 1e6,
        r.command, r.seconds_total);
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
    return md;
}

}  // namespace report
}  // namespace shprt::paper
