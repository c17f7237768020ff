// `shprt bench paper --quick` runs as a program: it writes the table (markdown and CSV), the
// sampling study, the gnuplot script and, where OpenGL and gnuplot exist, the images and plots;
// the CSV parses, has one row per basis size and plausible values; bad options give a one-line
// error.
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/light/image.hpp"
#include "shprt/render/gl_context.hpp"

#include "cli/cli_test.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace shprt {
namespace {

using test_support::expect_one_line_error;
using test_support::RunResult;

// A CSV with a header: column name → values, one per data row.
struct Csv {
    std::vector<std::string> names;
    std::vector<std::vector<std::string>> rows;
    std::size_t column(const std::string& name) const {
        const auto it = std::find(names.begin(), names.end(), name);
        return it == names.end() ? names.size() : std::size_t(it - names.begin());
    }
    double number(std::size_t row, const std::string& name) const {
        const std::size_t c = column(name);
        if (c >= names.size() || c >= rows[row].size()) return std::nan("");
        return std::strtod(rows[row][c].c_str(), nullptr);
    }
};

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> cells;
    std::istringstream in(line);
    std::string cell;
    while (std::getline(in, cell, ',')) cells.push_back(cell);
    return cells;
}

Csv read_csv(const std::string& path) {
    std::istringstream in(read_file(path));
    Csv csv;
    std::string line;
    std::getline(in, line);
    csv.names = split(line);
    while (std::getline(in, line))
        if (!line.empty()) csv.rows.push_back(split(line));
    return csv;
}

// Every cell a number ("nan" allowed for what was not measured).
bool all_numeric(const Csv& csv, std::size_t first_column) {
    for (const auto& row : csv.rows)
        for (std::size_t c = first_column; c < row.size(); ++c) {
            char* end = nullptr;
            std::strtod(row[c].c_str(), &end);
            if (end == row[c].c_str() || *end != '\0') return false;
        }
    return true;
}

bool have_gl() {
    try {
        HeadlessGlContext context;
        return true;
    } catch (const Error&) {
        return false;
    }
}

bool have_gnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

class CliBench : public test_support::CliTest {};

TEST_F(CliBench, QuickPaperRunWritesTheTable) {
    const fs::path dir = out("paper");
    const RunResult r = shprt("bench paper --quick --device cpu -o '" + dir.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Progress went to stderr, the table to stdout.
    EXPECT_NE(r.err.find("ground truth"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("| basis size K (coefficients) | 32 | 48 | 64 | 128 | 256 |"),
              std::string::npos)
        << r.out;

    // The markdown has the paper's rows and ours side by side.
    const std::string md = read_file((dir / "paper_table.md").string());
    for (const char* needle : {"18.5", "4 h 20 min", "2 h 18 min", "sharp", "unsaturated",
                               "shprt CPU, total", "RMSE (СКО)", "Sampling study"})
        EXPECT_NE(md.find(needle), std::string::npos) << needle;

    // The CSV parses: one row per paper size, every cell numeric, values plausible.
    const Csv csv = read_csv((dir / "paper_table.csv").string());
    ASSERT_GE(csv.names.size(), 40u);
    ASSERT_EQ(csv.rows.size(), 5u);
    EXPECT_TRUE(all_numeric(csv, 0));
    const int Ks[] = {32, 48, 64, 128, 256};
    for (std::size_t i = 0; i < 5; ++i) {
        ASSERT_EQ(csv.rows[i].size(), csv.names.size()) << "row " << i;
        EXPECT_EQ(csv.number(i, "K"), Ks[i]);
        EXPECT_EQ(csv.number(i, "paper_size"), 1);
        EXPECT_GT(csv.number(i, "cpu_seconds"), 0);
        EXPECT_GT(csv.number(i, "rays"), 0);
        EXPECT_TRUE(std::isnan(csv.number(i, "gpu_seconds")));  // --device cpu
        for (const char* e : {"sky_rel_rmse", "sun_rel_rmse", "sky_improved_rel_rmse"}) {
            const double v = csv.number(i, e);
            EXPECT_TRUE(v > 0 && v < 10) << e << " = " << v;
        }
        const double neg = csv.number(i, "sun_negative_fraction");
        EXPECT_TRUE(neg >= 0 && neg <= 1) << neg;
        EXPECT_EQ(csv.number(i, "paper_fps"), 18.5);
    }
    EXPECT_EQ(csv.number(0, "paper_cpu_s"), 38);
    EXPECT_EQ(csv.number(4, "paper_gpu_s"), 2 * 3600 + 18 * 60);

    // The sampling study: four samplers × two S in quick mode.
    const Csv study = read_csv((dir / "sampling_study.csv").string());
    EXPECT_EQ(study.rows.size(), 8u);
    EXPECT_TRUE(all_numeric(study, 1));
    EXPECT_TRUE(fs::exists(dir / "plot_paper.gp"));

    if (have_gl()) {
        const Image grid = load_image((dir / "grid_room.png").string());
        EXPECT_GT(grid.width, grid.height);
        EXPECT_TRUE(fs::exists(dir / "grid_edge.png"));
        EXPECT_TRUE(fs::exists(dir / "edge_profiles.csv"));
        EXPECT_FALSE(std::isnan(csv.number(0, "fps")));
        EXPECT_GT(csv.number(0, "truth_edge_width_m"), 0);
    }
    if (have_gnuplot()) {
        for (const char* plot :
             {"error_vs_K.png", "time_vs_K.png", "sampling_study.png", "edge_profile.png"})
            EXPECT_TRUE(fs::exists(dir / plot)) << plot;
    }
    // No temporary files are left behind.
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(CliBench, BadOptionsAreOneLineErrors) {
    const std::pair<const char*, const char*> cases[] = {
        {"--device gpu", "--device 'gpu'"},   {"--samples 0", "--samples 0"},
        {"--triangles 5", "--triangles 5"},   {"--sampler halton", "'halton'"},
        {"--gt-samples 1", "--gt-samples 1"},
    };
    for (const auto& [option, needle] : cases) {
        SCOPED_TRACE(option);
        expect_one_line_error(
            shprt("bench paper " + std::string(option) + " --quick -o '" + out("bad") + "'"),
            needle);
        EXPECT_TRUE(out_dir_empty()) << "a failed run writes nothing";
    }
}

TEST_F(CliBench, CudaWithoutAGpuIsAnError) {
    // Only meaningful where there is no GPU; where there is one, the run would succeed.
    const RunResult probe =
        shprt("bench paper --quick --device cuda --no-study --no-images -o '" + out("cuda") + "'");
    if (probe.exit_code == 0) GTEST_SKIP() << "a CUDA device is present";
    expect_one_line_error(probe, "--device cuda");
}

}  // namespace
}  // namespace shprt
