// The report stage of the paper study, plots (report.hpp): the gnuplot script (error and time
// against K, the sampling study, the edge profiles) and gnuplot run on it when it is installed.
#include "paper/report.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

extern char** environ;

namespace shprt::paper::report {

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

}  // namespace shprt::paper::report
