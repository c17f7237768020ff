// `shprt bench paper --quick` runs as a program: it writes the table (markdown and CSV), the
// sampling study, the gnuplot script and, where OpenGL and gnuplot exist, the images and plots;
// the CSV parses, has one row per basis size and plausible values; bad options give a one-line
// error.
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/light/image.hpp"
#include "shprt/render/gl_context.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace shprt {
namespace {

struct RunResult {
    int exit_code;
    std::string out, err;
};

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

class CliBench : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("shprt_cli_bench_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    RunResult shprt(const std::string& args) {
        std::string cmd = "'";
        cmd.append(SHPRT_CLI_PATH).append("' ").append(args);
        cmd.append(" >'").append((m_dir / "stdout").string());
        cmd.append("' 2>'").append((m_dir / "stderr").string()).append("' </dev/null");
        const int status = std::system(cmd.c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : 128,
                read_file((m_dir / "stdout").string()), read_file((m_dir / "stderr").string())};
    }

    fs::path m_dir;
};

TEST_F(CliBench, QuickPaperRunWritesTheTable) {
    const fs::path out = m_dir / "paper";
    const RunResult r = shprt("bench paper --quick --device cpu -o '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Progress went to stderr, the table to stdout.
    EXPECT_NE(r.err.find("ground truth"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("| basis size K (coefficients) | 32 | 48 | 64 | 128 | 256 |"),
              std::string::npos)
        << r.out;

    // The markdown has the paper's rows and ours side by side.
    const std::string md = read_file((out / "paper_table.md").string());
    for (const char* needle : {"18.5", "4 h 20 min", "2 h 18 min", "sharp", "unsaturated",
                               "shprt CPU, total", "RMSE (СКО)", "Sampling study"})
        EXPECT_NE(md.find(needle), std::string::npos) << needle;

    // The CSV parses: one row per paper size, every cell numeric, values plausible.
    const Csv csv = read_csv((out / "paper_table.csv").string());
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
    const Csv study = read_csv((out / "sampling_study.csv").string());
    EXPECT_EQ(study.rows.size(), 8u);
    EXPECT_TRUE(all_numeric(study, 1));
    EXPECT_TRUE(fs::exists(out / "plot_paper.gp"));

    if (have_gl()) {
        const Image grid = load_image((out / "grid_room.png").string());
        EXPECT_GT(grid.width, grid.height);
        EXPECT_TRUE(fs::exists(out / "grid_edge.png"));
        EXPECT_TRUE(fs::exists(out / "edge_profiles.csv"));
        EXPECT_FALSE(std::isnan(csv.number(0, "fps")));
        EXPECT_GT(csv.number(0, "truth_edge_width_m"), 0);
    }
    if (have_gnuplot()) {
        for (const char* plot :
             {"error_vs_K.png", "time_vs_K.png", "sampling_study.png", "edge_profile.png"})
            EXPECT_TRUE(fs::exists(out / plot)) << plot;
    }
    // No temporary files are left behind.
    for (const auto& entry : fs::directory_iterator(out))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(CliBench, BadOptionsAreOneLineErrors) {
    for (const char* args :
         {"bench paper --device gpu", "bench paper --samples 0", "bench paper --triangles 5",
          "bench paper --sampler halton", "bench paper --gt-samples 1"}) {
        const RunResult r =
            shprt(std::string(args) + " --quick -o '" + (m_dir / "bad").string() + "'");
        EXPECT_NE(r.exit_code, 0) << args;
        EXPECT_EQ(r.err.rfind("shprt: error: ", 0), 0u) << args << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
        EXPECT_FALSE(fs::exists(m_dir / "bad" / "paper_table.md")) << args;
    }
}

TEST_F(CliBench, CudaWithoutAGpuIsAnError) {
    // Only meaningful where there is no GPU; where there is one, the run would succeed.
    const RunResult probe = shprt("bench paper --quick --device cuda --no-study --no-images -o '" +
                                  (m_dir / "cuda").string() + "'");
    if (probe.exit_code == 0) GTEST_SKIP() << "a CUDA device is present";
    EXPECT_EQ(probe.err.rfind("shprt: error: ", 0), 0u) << probe.err;
    EXPECT_NE(probe.err.find("--device cuda"), std::string::npos) << probe.err;
}

}  // namespace
}  // namespace shprt
