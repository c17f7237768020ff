// How an MPI job ends when one of its ranks dies or mpirun is interrupted (issue 41, item 9): one
// clear line. A rank killed outright makes mpirun end the others with SIGTERM; rank 0 — or, when
// rank 0 is the one that died, the lowest rank left — says which rank ended (core/job.hpp), not
// "interrupted by SIGTERM", and nothing is left behind.
#include "cli/cli_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace shprt {
namespace {

namespace fs = std::filesystem;
using test_support::slurp;

class MpiSignals : public test_support::CliTest {
protected:
    // Starts a 3-rank streamed bake, waits until rows flow, then runs `action` (shell text; $job
    // is mpirun's pid, rank_pid R prints rank R's pid), waits for mpirun and prints its status.
    // Returns the report (the script's own lines) and leaves the job's stdout+stderr in o.
    std::string run_and(const std::string& action) const {
        const std::string target = out("job.shprt");
        const std::string script = fmt::format(
            R"(set -u
{prefix} mpirun -q --oversubscribe --allow-run-as-root -np 3 '{cli}' bake builtin:room \
    --coeffs 16 --samples 16384 --stream -o '{out}' >'{dir}/o' 2>'{dir}/e' &
job=$!
rank_pid() {{
    for p in $(pgrep -f -- "-o {out}"); do
        tr '\0' '\n' </proc/$p/environ 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=$1 && echo $p
    done
}}
for i in $(seq 1 300); do
    ls '{out}'.tmp.* >/dev/null 2>&1 && grep -q 'bake:' '{dir}/e' && break
    sleep 0.1
done
ls '{out}'.tmp.* >/dev/null 2>&1 || {{ echo 'no temporary file appeared'; exit 90; }}
{action}
wait $job
echo "mpirun exit $?"
)",
            fmt::arg("prefix", test_support::without_leak_check()), fmt::arg("cli", SHPRT_CLI_PATH),
            fmt::arg("out", target), fmt::arg("dir", m_dir.string()), fmt::arg("action", action));
        const std::string script_path = (m_dir / "job.sh").string();
        std::ofstream(script_path) << script;
        const int status = std::system(
            ("bash '" + script_path + "' >'" + (m_dir / "k").string() + "' 2>&1").c_str());
        EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(m_dir / "k") << slurp(m_dir / "e");
        return slurp(m_dir / "k");
    }
    // The lines of stderr that start "shprt: error: ".
    std::vector<std::string> error_lines() const {
        std::istringstream in(slurp(m_dir / "e"));
        std::vector<std::string> lines;
        for (std::string line; std::getline(in, line);)
            if (line.rfind("shprt: error: ", 0) == 0) lines.push_back(line);
        return lines;
    }
    bool out_empty() const { return fs::is_empty(m_dir / "out"); }
};

TEST_F(MpiSignals, AKilledRankIsNamedInOneLine) {
    for (const int victim : {1, 0}) {
        SCOPED_TRACE("rank " + std::to_string(victim) + " killed");
        const std::string report =
            run_and(fmt::format("v=$(rank_pid {}); [ -n \"$v\" ] || exit 91; kill -9 $v", victim));
        EXPECT_NE(report.find("mpirun exit "), std::string::npos) << report;
        EXPECT_EQ(report.find("mpirun exit 0"), std::string::npos) << report;
        const std::vector<std::string> lines = error_lines();
        ASSERT_EQ(lines.size(), 1u) << slurp(m_dir / "e");
        EXPECT_NE(
            lines[0].find(fmt::format("rank {} of the MPI job ended (killed or crashed)", victim)),
            std::string::npos)
            << lines[0];
        // Rank 0 killed outright cannot remove its temporary (README: the next run does).
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(m_dir / "out"))
            left.push_back(e.path().filename().string());
        if (victim == 0 && left.size() == 1 && left[0].rfind("job.shprt.tmp.", 0) == 0)
            left.clear();
        EXPECT_TRUE(left.empty()) << ::testing::PrintToString(left);
        fs::remove_all(m_dir / "out");
        fs::create_directories(m_dir / "out");
    }
}

// SIGINT or SIGTERM to mpirun: it passes the signal on as SIGTERM to every rank, and rank 0 says
// the job was interrupted, in one line; nothing is left.
TEST_F(MpiSignals, AnInterruptedJobSaysSoInOneLine) {
    for (const char* signal : {"INT", "TERM"}) {
        SCOPED_TRACE(signal);
        const std::string report = run_and(fmt::format("kill -{} $job", signal));
        EXPECT_EQ(report.find("mpirun exit 0"), std::string::npos) << report;
        const std::vector<std::string> lines = error_lines();
        ASSERT_EQ(lines.size(), 1u) << slurp(m_dir / "e");
        EXPECT_NE(lines[0].find("interrupted by SIG"), std::string::npos) << lines[0];
        EXPECT_TRUE(out_empty());
        fs::remove_all(m_dir / "out");
        fs::create_directories(m_dir / "out");
    }
}

}  // namespace
}  // namespace shprt
