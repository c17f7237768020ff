// `mpirun -np P shprt bake` as a program (Open MPI's mpirun, as CI runs it: --oversubscribe on 2
// cores, --allow-run-as-root): the file is byte for byte the single-process bake's, written at
// once or streamed, with ranks of uneven speed and small units; a failure on any rank is one line
// from rank 0 and no file; a killed rank leaves nothing behind.
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/ply.hpp"

#include "cli/cli_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;
using test_support::expect_one_line_error;
using test_support::RunResult;
using test_support::slurp;

// -q: mpirun's own banner about a failed job stays out of stderr, which then holds shprt's line.
// Under ASan without LeakSanitizer: Open MPI unloads its components before the ranks exit, so
// their leaks have no module to name (test_support::without_leak_check).
std::string mpirun_command() {
    return test_support::without_leak_check() + " mpirun -q --oversubscribe --allow-run-as-root";
}

class MpiBake : public test_support::CliTest {
protected:
    RunResult mpirun(int ranks, const std::string& args) const {
        return shprt(args, {.prefix = fmt::format("{} -np {}", mpirun_command(), ranks)});
    }
    // Files in the output folder other than `keep`: leftovers.
    std::vector<std::string> others(const std::vector<std::string>& keep) const {
        std::vector<std::string> found;
        for (const auto& entry : fs::directory_iterator(m_dir / "out")) {
            const std::string name = entry.path().filename().string();
            if (std::find(keep.begin(), keep.end(), name) == keep.end()) found.push_back(name);
        }
        return found;
    }
};

constexpr const char* kRoom = "bake builtin:room --coeffs 16 --samples 96 --seed 7 --reproducible";

TEST_F(MpiBake, FourRanksWriteTheSingleProcessBytes) {
    const RunResult one = shprt(fmt::format("{} -o '{}'", kRoom, out("one.shprt")));
    ASSERT_EQ(one.exit_code, 0) << one.err;
    const RunResult r =
        mpirun(4, fmt::format("{} --mpi-unit 512 -o '{}'", kRoom, out("four.shprt")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("4 ranks: cpu"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("ranks: receivers "), std::string::npos) << r.out;
    // One summary and one balance line, from rank 0 only.
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2) << r.out;
    EXPECT_TRUE(slurp(out("one.shprt")) == slurp(out("four.shprt")))
        << "the 4-rank file differs from the single-process file";
    EXPECT_EQ(read_shprt(out("four.shprt")).mesh.vertex_count(),
              15795u);  // with the atlas's copies
    // Rank 0's progress counts every rank's receivers.
    EXPECT_NE(r.err.find("bake: 100% (15.8 k of 15.8 k receivers"), std::string::npos) << r.err;
}

// Glossy transfer matrices go through the same sink: two ranks write the single-process bytes.
TEST_F(MpiBake, GlossyMatricesFromTwoRanksEqualTheSingleProcessBytes) {
    const std::string bake =
        "bake builtin:box_on_plane --transfer glossy --bands 3 --samples 64 --reproducible";
    ASSERT_EQ(shprt(fmt::format("{} -o '{}'", bake, out("one.shprt"))).exit_code, 0);
    const RunResult r = mpirun(2, fmt::format("{} --mpi-unit 64 -o '{}'", bake, out("two.shprt")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(slurp(out("one.shprt")) == slurp(out("two.shprt")))
        << "the 2-rank glossy file differs from the single-process file";
    EXPECT_EQ(read_shprt(out("two.shprt")).transfer.layout.shape, TransferShape::symmetric_matrix);
}

// A scene whose cost is uneven along the vertex range: a wide plane far from everything first
// (its rays escape at once), the furnished room after it (its rays walk a deeper BVH and hit).
// Equal static shares would leave the ranks with the plane idle; the units keep them busy and
// the bytes are still the single-process bytes, for shadowed and unshadowed transfer.
TEST_F(MpiBake, AnUnevenCostSceneKeepsTheBytes) {
    // 24 tiles of the plane (~7 k cheap vertices), then the room (~15.6 k dear ones).
    Mesh scene;
    const auto append = [&scene](const Mesh& part, Vec3f shift) {
        const auto offset = static_cast<std::uint32_t>(scene.positions.size());
        for (const Vec3f& p : part.positions) scene.positions.push_back(p + shift);
        scene.normals.insert(scene.normals.end(), part.normals.begin(), part.normals.end());
        for (auto t : part.triangles)
            scene.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    };
    const Mesh plane = make_builtin("plane");
    for (int tile = 0; tile < 24; ++tile) append(plane, Vec3f{100.0f + 2.0f * float(tile), 0, 0});
    append(make_builtin("room"), Vec3f{0, 0, 0});
    scene.source = "uneven";
    write_ply(scene, out("uneven.ply"));
    for (const std::string kind : {"shadowed", "unshadowed"}) {
        const std::string bake = fmt::format(
            "bake '{}' --transfer {} --coeffs 9 --samples 256 --reproducible --mpi-unit 64",
            out("uneven.ply"), kind);
        ASSERT_EQ(shprt(fmt::format("{} -o '{}'", bake, out("one.shprt"))).exit_code, 0);
        const RunResult r = mpirun(4, fmt::format("{} -o '{}'", bake, out("four.shprt")));
        ASSERT_EQ(r.exit_code, 0) << kind << ": " << r.err;
        EXPECT_TRUE(slurp(out("one.shprt")) == slurp(out("four.shprt"))) << kind;
    }
}

TEST_F(MpiBake, StreamedAndHalfFilesEqualTheirSingleProcessBytes) {
    for (const std::string extra : {"--stream", "--stream --half", "--half"}) {
        const std::string one = out("one.shprt"), many = out("many.shprt");
        ASSERT_EQ(shprt(fmt::format("{} {} -o '{}'", kRoom, extra, one)).exit_code, 0);
        const RunResult r = mpirun(3, fmt::format("{} {} -o '{}'", kRoom, extra, many));
        ASSERT_EQ(r.exit_code, 0) << extra << ": " << r.err;
        EXPECT_TRUE(slurp(one) == slurp(many)) << extra << ": the files differ";
    }
}

// Ranks of uneven speed (one with two threads, three with one, on two cores) and small units:
// the fast rank claims more, and the file is still the single-process one.
TEST_F(MpiBake, UnevenRanksBalanceAndKeepTheBytes) {
    const std::string scene =
        "bake builtin:box_on_plane --coeffs 25 --samples 512 --seed 2 "
        "--reproducible --mpi-unit 16";
    ASSERT_EQ(shprt(fmt::format("{} -o '{}'", scene, out("one.shprt"))).exit_code, 0);
    const std::string cli = fmt::format("'{}'", SHPRT_CLI_PATH);
    const std::string command = fmt::format(
        "{} -np 1 {} {} --threads 2 -o '{}' : -np 3 {} {} --threads 1 -o '{}'", mpirun_command(),
        cli, scene, out("uneven.shprt"), cli, scene, out("uneven.shprt"));
    ASSERT_EQ(std::system((command + " >'" + (m_dir / "o").string() + "' 2>&1").c_str()), 0)
        << slurp(m_dir / "o");
    const std::string log = slurp(m_dir / "o");
    EXPECT_NE(log.find("ranks: receivers "), std::string::npos) << log;
    EXPECT_TRUE(slurp(out("one.shprt")) == slurp(out("uneven.shprt")));
}

TEST_F(MpiBake, AFailureOnAnyRankIsOneLineFromRankZeroAndNoFile) {
    // Every rank fails the same way: one line, not four.
    expect_one_line_error(mpirun(4, fmt::format("bake missing.ply -o '{}'", out("x.shprt"))),
                          "missing.ply");
    // Rank 2 loads another scene: rank 0 names it.
    ASSERT_EQ(shprt(fmt::format("scene plane -o '{}'", out("plane.ply"))).exit_code, 0);
    ASSERT_EQ(shprt(fmt::format("scene sphere -o '{}'", out("sphere.ply"))).exit_code, 0);
    const std::string cli = fmt::format("'{}'", SHPRT_CLI_PATH);
    const std::string command =
        fmt::format("{} -np 2 {} bake '{}' -o '{}' : -np 1 {} bake '{}' -o '{}' >'{}' 2>'{}'",
                    mpirun_command(), cli, out("plane.ply"), out("x.shprt"), cli, out("sphere.ply"),
                    out("x.shprt"), (m_dir / "stdout").string(), (m_dir / "stderr").string());
    const int status = std::system(command.c_str());
    const RunResult r{WIFEXITED(status) ? WEXITSTATUS(status) : 128, slurp(m_dir / "stdout"),
                      slurp(m_dir / "stderr")};
    expect_one_line_error(r, "rank 2 loaded a different scene");
    // Rank 0 cannot write the output: found before any work.
    expect_one_line_error(mpirun(2, "bake builtin:plane -o /nonexistent/dir/x.shprt"),
                          "/nonexistent/dir/x.shprt");
    // --shard does not mix with MPI.
    expect_one_line_error(
        mpirun(2, fmt::format("bake builtin:plane --shard 0/2 -o '{}'", out("x.shprt"))),
        "--shard and MPI");
    EXPECT_EQ(others({"plane.ply", "sphere.ply"}), std::vector<std::string>{});
}

// A rank killed in the middle of a streamed bake: mpirun ends the job with a non-zero status,
// rank 0 removes its temporary file on the SIGTERM mpirun sends, and nothing is left.
TEST_F(MpiBake, AKilledRankLeavesNothingBehind) {
    const std::string target = out("killed.shprt");
    const std::string script = fmt::format(
        R"(set -u
{mpirun} -np 3 '{cli}' bake builtin:room --coeffs 16 --samples 16384 --stream -o '{out}' \
    >'{dir}/o' 2>&1 &
job=$!
# Wait until the streamed file's temporary exists and rows flow (rank 0's progress line).
for i in $(seq 1 300); do
    ls '{out}'.tmp.* >/dev/null 2>&1 && grep -q 'bake:' '{dir}/o' && break
    sleep 0.1
done
ls '{out}'.tmp.* >/dev/null 2>&1 || {{ echo 'no temporary file appeared'; exit 90; }}
victim=""
for p in $(pgrep -f -- "-o {out}"); do
    tr '\0' '\n' </proc/$p/environ 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=1 && victim=$p
done
[ -n "$victim" ] || {{ echo 'rank 1 not found'; exit 91; }}
kill -9 "$victim"
wait $job
echo "mpirun exit $?"
)",
        fmt::arg("mpirun", mpirun_command()), fmt::arg("cli", SHPRT_CLI_PATH),
        fmt::arg("out", target), fmt::arg("dir", m_dir.string()));
    const std::string script_path = (m_dir / "kill.sh").string();
    std::ofstream(script_path) << script;
    const int status =
        std::system(("bash '" + script_path + "' >'" + (m_dir / "k").string() + "' 2>&1").c_str());
    const std::string report = slurp(m_dir / "k");
    ASSERT_EQ(WEXITSTATUS(status), 0) << report << slurp(m_dir / "o");
    EXPECT_NE(report.find("mpirun exit "), std::string::npos) << report;
    EXPECT_EQ(report.find("mpirun exit 0"), std::string::npos) << report;
    EXPECT_EQ(others({}), std::vector<std::string>{}) << "left behind after the kill";
}

}  // namespace
}  // namespace shprt
