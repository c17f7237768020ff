// The report stage of the paper study (report.hpp): writes the files of a run.
#include "paper/report.hpp"

#include "shprt/core/file.hpp"

#include <filesystem>
#include <string>
#include <system_error>

namespace shprt::paper {
namespace {

void write_text(const std::string& path, const std::string& text) {
    AtomicFile f(path);
    f.write(text);
    f.commit();
}

}  // namespace

void write_reports(Results& r, const Reporter& reporter) {
    const std::string dir = r.options.out_dir;
    const auto put = [&](const std::string& name, const std::string& text) {
        write_text(dir + "/" + name, text);
        r.files.push_back(name);
    };
    put("paper_table.csv", report::csv_table(r));
    if (!r.study.empty()) put("sampling_study.csv", report::study_csv(r));
    if (r.gt_has_edge) put("edge_profiles.csv", report::profiles_csv(r));
    put("plot_paper.gp", report::gnuplot_script(r));

    std::string why;
    if (report::run_gnuplot(dir, why)) {
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

    put("paper_table.md", report::paper_table_md(r));
}

}  // namespace shprt::paper
