// The report stage of the paper study: the files of a run (write_reports and markdown_table are in
// paper_study.hpp). This header is what the report writers share: the number formats of the
// tables, and the text of each file, one writer per file —
//   report_markdown.cpp   paper_table.md: the table beside the paper's, the other tables;
//   report_csv.cpp        paper_table.csv, sampling_study.csv, edge_profiles.csv;
//   report_gnuplot.cpp    plot_paper.gp and running gnuplot on it;
//   report.cpp            write_reports: writes them all into the output directory.
#pragma once

#include "paper/paper_study.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace shprt::paper::report {

// Table cells: "—" for what was not measured (NaN); csv() writes "nan" and 9 digits.
inline std::string num(double v, const char* f = "{:.3g}") {
    return std::isnan(v) ? std::string("—") : fmt::format(fmt::runtime(f), v);
}
inline std::string pct(double v, const char* f = "{:.2f}") { return num(100 * v, f); }
inline std::string csv(double v) {
    return std::isnan(v) ? std::string("nan") : fmt::format("{:.9g}", v);
}

inline std::string duration(double s) {
    if (std::isnan(s)) return "—";
    if (s < 60) return fmt::format("{:.2f} s", s);
    if (s < 3600) return fmt::format("{} min {:.0f} s", int(s / 60), s - 60 * int(s / 60));
    return fmt::format("{} h {} min", int(s / 3600), int((s - 3600 * int(s / 3600)) / 60));
}

inline double rays_per_s(const BakeRun& b) {
    return b.ran && b.stats.seconds_total > 0 ? double(b.stats.rays_cast) / b.stats.seconds_total
                                              : kNaN;
}

inline std::string mrays(double v) {
    return std::isnan(v) ? "—" : fmt::format("{:.1f} M", v / 1e6);
}

// report_markdown.cpp: paper_table.md, listing results.files as they are when it is called.
std::string paper_table_md(const Results& results);

// report_csv.cpp: the CSVs (columns named in their first line).
std::string csv_table(const Results& results);
std::string study_csv(const Results& results);
std::string profiles_csv(const Results& results);

// report_gnuplot.cpp: the gnuplot script, run from the output directory.
std::string gnuplot_script(const Results& results);
// Runs gnuplot on `dir`/plot_paper.gp, writing the PNGs with the suffix .tmp. Returns false and
// says why when gnuplot is missing or fails.
bool run_gnuplot(const std::string& dir, std::string& why);

}  // namespace shprt::paper::report
