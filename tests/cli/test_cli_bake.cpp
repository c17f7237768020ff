// `shprt bake` run as a program: a bake of a built-in scene writes a readable file; bad options
// give a one-line error, a non-zero exit code and leave nothing behind.
#include "shprt/bake/bake.hpp"
#include "shprt/bake/session.hpp"
#include "shprt/config.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"

#include "cli/cli_test.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

using shprt::test_support::RunResult;
using shprt::test_support::slurp;

class CliBake : public shprt::test_support::CliTest {};

TEST_F(CliBake, BakesABuiltinSceneIntoAReadableFile) {
    const std::string file = out("box.shprt");
    const RunResult r =
        shprt("bake builtin:box_on_plane -o '" + file + "' --coeffs 9 --samples 64 --seed 5");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(fs::exists(file));
    // One summary line on stdout.
    EXPECT_NE(r.out.find("baked "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("K=9, S=64"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Mrays/s"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    // Not a terminal: plain progress lines, ending at 100 %.
    EXPECT_NE(r.err.find("bake: 100%"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\r'), std::string::npos) << "no in-place redraw off a terminal";

    const shprt::ShprtFile f = shprt::read_shprt(file);
    EXPECT_EQ(f.transfer.layout.K, 9);
    EXPECT_EQ(f.transfer.samples, 64);
    EXPECT_EQ(f.transfer.seed, 5u);
    EXPECT_EQ(f.transfer.kind, shprt::TransferKind::shadowed);
    EXPECT_EQ(f.mesh.vertex_count(), shprt::make_builtin("box_on_plane").vertex_count());
    EXPECT_NE(f.metadata_json.find("seconds_load"), std::string::npos);
    EXPECT_NE(f.metadata_json.find("command_line"), std::string::npos);
    // Only the output file: no temporary left beside it.
    EXPECT_EQ(std::distance(fs::directory_iterator(m_dir / "out"), fs::directory_iterator()), 1);

    // `shprt info` reads it, where this build has the command.
    if (shprt("info --help").exit_code == 0) {
        const RunResult info = shprt("info '" + file + "'");
        EXPECT_EQ(info.exit_code, 0) << info.err;
    }
}

TEST_F(CliBake, ThreadCountDoesNotChangeTheCoefficients) {
    const std::string one = out("one.shprt"), two = out("two.shprt");
    ASSERT_EQ(shprt("bake builtin:box_on_plane -o '" + one +
                    "' --bands 3 --samples 128 "
                    "--threads 1 --transfer shadowed --sampler stratified")
                  .exit_code,
              0);
    ASSERT_EQ(shprt("bake builtin:box_on_plane -o '" + two +
                    "' --bands 3 --samples 128 "
                    "--threads 2 --transfer shadowed --sampler stratified")
                  .exit_code,
              0);
    const shprt::ShprtFile a = shprt::read_shprt(one), b = shprt::read_shprt(two);
    EXPECT_EQ(a.transfer.layout.K, 9);
    EXPECT_EQ(a.transfer.sampler, shprt::SamplerKind::stratified);
    EXPECT_EQ(a.transfer.coeffs, b.transfer.coeffs);
}

// More threads than the machine allows: one shprt warning (not TBB's, nor an empty line), and the
// report names the threads that ran.
TEST_F(CliBake, TooManyThreadsAreClampedWithOneWarning) {
    const int cpus = std::max(1, int(std::thread::hardware_concurrency()));
    const std::string file = out("p.shprt");
    const RunResult r = shprt("bake builtin:plane --samples 16 --threads " +
                              std::to_string(cpus + 3) + " -o '" + file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("TBB Warning"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("\n\n"), std::string::npos) << r.err;
    const std::string warning =
        "shprt: warning: " + std::to_string(cpus + 3) + " threads requested";
    EXPECT_NE(r.err.find(warning), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(warning), r.err.rfind(warning)) << "one warning: " << r.err;
    EXPECT_EQ((r.out + r.err).find("cpu: " + std::to_string(cpus + 3) + " threads"),
              std::string::npos)
        << r.out << r.err;
}

// An error-bounded bake whose cap stops receivers above the target says so once, with the count
// the summary's error bands give ("over E: N"); one that reaches the target everywhere says
// nothing. `shprt info` prints the same bands.
TEST_F(CliBake, ErrorBoundedBakeWarnsOfReceiversTheCapStoppedAboveTheTarget) {
    const std::string bake = "bake builtin:box_on_plane --coeffs 16 --target-error ";
    const RunResult capped = shprt(bake + "0.02 --max-samples 256 -o '" + out("c.shprt") + "'");
    ASSERT_EQ(capped.exit_code, 0) << capped.err;
    const std::size_t at = capped.out.find("over E: ");
    ASSERT_NE(at, std::string::npos) << capped.out;
    const int over = std::stoi(capped.out.substr(at + 8));
    EXPECT_GT(over, 0);
    EXPECT_LT(over, 1214);  // box_on_plane's vertices: some reach 0.02 within 256 samples
    const std::string warning = "shprt: warning: " + std::to_string(over) +
                                " of 1214 receivers stopped at --max-samples 256 with an "
                                "estimated error above --target-error 0.02";
    EXPECT_NE(capped.err.find(warning), std::string::npos) << capped.err;
    EXPECT_EQ(capped.err.find("warning"), capped.err.rfind("warning")) << capped.err;
    const RunResult info = shprt("info '" + out("c.shprt") + "'");
    EXPECT_NE(info.out.find("error bands  receivers ≤ E/4: "), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("over E: " + std::to_string(over) + "\n"), std::string::npos)
        << info.out;

    const RunResult reached = shprt(bake + "0.03 --max-samples 512 -o '" + out("r.shprt") + "'");
    ASSERT_EQ(reached.exit_code, 0) << reached.err;
    EXPECT_NE(reached.out.find("over E: 0\n"), std::string::npos) << reached.out;
    EXPECT_EQ(reached.err.find("warning"), std::string::npos) << reached.err;
}

// An error-bounded bake goes breadth first, in rounds (BakeSession::bake_in_rounds): each round's
// progress line gives the estimated error of every receiver, and it falls; the file holds the rows
// and estimates of the one-pass bake that --stream makes. leaky_room: overlapping panels, parts
// through the floor, interpenetrating furniture.
TEST_F(CliBake, ErrorBoundedBakeShowsTheErrorFallingRoundByRound) {
    const std::string bake =
        "bake builtin:leaky_room --coeffs 16 --target-error 0.01 --max-samples 4096 -o '";
    const RunResult rounds = shprt(bake + out("r.shprt") + "'");
    ASSERT_EQ(rounds.exit_code, 0) << rounds.err;
    // Each round's last line ("… 100% (…)  err 99%: X %…"), in order.
    std::vector<std::pair<std::string, double>> ends;
    std::istringstream lines(rounds.err);
    for (std::string line; std::getline(lines, line);) {
        const std::size_t done = line.find(": 100% ("), err = line.find("err 99%: ");
        if (done == std::string::npos || err == std::string::npos) continue;
        ends.emplace_back(line.substr(0, done), std::stod(line.substr(err + 9)));
    }
    ASSERT_EQ(ends.size(), 3u) << rounds.err;
    EXPECT_EQ(ends[0].first, "shprt: bake");
    EXPECT_EQ(ends[1].first, "shprt: bake: ≤ 1024 samples");
    EXPECT_EQ(ends[2].first, "shprt: bake: ≤ 4096 samples");
    EXPECT_GT(ends[0].second, ends[1].second) << rounds.err;
    EXPECT_GT(ends[1].second, ends[2].second) << rounds.err;

    const RunResult one_pass = shprt(bake + out("s.shprt") + "' --stream");
    ASSERT_EQ(one_pass.exit_code, 0) << one_pass.err;
    EXPECT_EQ(one_pass.err.find("samples: "), std::string::npos) << "--stream: one pass";
    const shprt::ShprtFile a = shprt::read_shprt(out("r.shprt"));
    const shprt::ShprtFile b = shprt::read_shprt(out("s.shprt"));
    EXPECT_EQ(a.transfer.coeffs, b.transfer.coeffs);
    EXPECT_EQ(a.transfer.receiver_samples, b.transfer.receiver_samples);
    EXPECT_EQ(a.transfer.receiver_error, b.transfer.receiver_error);
    EXPECT_EQ(a.transfer.samples, 4096);
}

// The rounds' rows are for the display: where they would not fit beside the rest of the bake under
// --max-memory, the bake goes in one pass (the same file) instead of refusing.
TEST_F(CliBake, ErrorBoundedBakeGoesInOnePassWhereTheRoundsWouldNotFit) {
    const shprt::Mesh mesh = shprt::make_builtin("leaky_room");
    shprt::BakeOptions o;
    o.K = 64;
    o.threads = 2;
    o.target_error = 0.01;
    o.max_samples = 4096;
    const std::uint64_t rest =
        shprt::estimate_bake_peak_bytes(mesh.triangle_count(), mesh.vertex_count(), o, true);
    const std::uint64_t rounds = shprt::round_rows_bytes(mesh.vertex_count(), o);
    const std::string bake =
        "bake builtin:leaky_room --coeffs 64 --threads 2 --target-error 0.01 --max-samples 4096 "
        "--max-memory ";
    const RunResult one =
        shprt(bake + std::to_string(rest + rounds / 2) + " -o '" + out("one.shprt") + "'");
    ASSERT_EQ(one.exit_code, 0) << one.err;
    EXPECT_NE(one.err.find("shprt: bake: 100%"), std::string::npos) << one.err;
    EXPECT_EQ(one.err.find("samples: "), std::string::npos) << "one pass: " << one.err;
    const RunResult in_rounds =
        shprt(bake + std::to_string(rest + rounds) + " -o '" + out("rounds.shprt") + "'");
    ASSERT_EQ(in_rounds.exit_code, 0) << in_rounds.err;
    EXPECT_NE(in_rounds.err.find("shprt: bake: ≤ 1024 samples: 100%"), std::string::npos)
        << in_rounds.err;
    EXPECT_EQ(shprt::read_shprt(out("one.shprt")).transfer.coeffs,
              shprt::read_shprt(out("rounds.shprt")).transfer.coeffs);
    const RunResult refused =
        shprt(bake + std::to_string(rest - 1) + " -o '" + out("no.shprt") + "'");
    EXPECT_NE(refused.exit_code, 0);
    EXPECT_NE(refused.err.find("needs about"), std::string::npos) << refused.err;
    EXPECT_FALSE(fs::exists(out("no.shprt")));
}

// One log level (core/log.hpp) decides both the messages and the progress, and is taken before
// or after the subcommand: -q (warn) keeps the warning and drops the progress, --log-level error
// drops both, -v adds the debug lines. -q with -v or --log-level is a usage error.
TEST_F(CliBake, QuietVerboseAndTheLogLevelAnywhereOnTheLine) {
    const int threads = std::max(1, int(std::thread::hardware_concurrency())) + 3;
    const std::string file = out("p.shprt");
    const std::string bake = "bake builtin:plane --samples 16 --threads " +
                             std::to_string(threads) + " -o '" + file + "'";
    const std::string warning = "shprt: warning: " + std::to_string(threads) + " threads requested";
    RunResult r = shprt(bake);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("shprt: bake: 100%"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(warning), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("debug"), std::string::npos) << r.err;
    for (const std::string& quiet : {"-q " + bake, bake + " -q", bake + " --quiet",
                                     "--log-level warn " + bake, bake + " --log-level warn"}) {
        r = shprt(quiet);
        EXPECT_EQ(r.exit_code, 0) << quiet << ": " << r.err;
        EXPECT_EQ(r.err.rfind(warning, 0), 0u) << quiet << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << quiet << ": " << r.err;
        EXPECT_NE(r.out.find("baked "), std::string::npos) << "results stay: " << r.out;
    }
    r = shprt(bake + " --log-level error");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    for (const std::string& verbose : {bake + " -v", "--verbose " + bake}) {
        r = shprt(verbose);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.err.find("shprt: debug: wrote " + file), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("shprt: bake: 100%"), std::string::npos) << r.err;
    }
    shprt::test_support::expect_usage_error(shprt(bake + " -q -v"), "excludes");
    shprt::test_support::expect_usage_error(shprt("-q " + bake + " --log-level info"), "excludes");
}

// Escape codes only on a terminal that takes them (core/terminal.hpp), checked on a
// pseudo-terminal made by util-linux's script(1): the in-place bar and coloured levels; no colour
// under NO_COLOR; under TERM=dumb plain lines and no escape code at all.
TEST_F(CliBake, EscapeCodesOnlyWhereTheTerminalTakesThem) {
    if (std::system("script --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1)";
    const std::string bake =
        "bake builtin:plane --samples 16 --threads " +
        std::to_string(std::max(1, int(std::thread::hardware_concurrency())) + 3) + " -o '" +
        out("p.shprt") + "'";
    const auto on_a_terminal = [&](const std::string& environment) {
        const std::string log = (m_dir / "terminal").string();
        const std::string command = "env -u NO_COLOR " + environment + " script -qec \"'" +
                                    SHPRT_CLI_PATH + "' " + bake + "\" /dev/null >'" + log +
                                    "' 2>&1 </dev/null";
        EXPECT_EQ(std::system(command.c_str()), 0) << command << "\n" << slurp(log);
        return slurp(log);
    };
    const auto colours = [](const std::string& text) {  // escape codes other than "clear line"
        int n = 0;
        for (std::size_t at = 0; (at = text.find('\x1b', at)) != std::string::npos; ++at)
            n += text.compare(at, 3, "\x1b[K") != 0;
        return n;
    };
    std::string text = on_a_terminal("TERM=xterm");
    if (text.empty()) GTEST_SKIP() << "script(1) gave no terminal here";
    EXPECT_NE(text.find("\rbake ["), std::string::npos) << text;
    EXPECT_NE(text.find("\x1b[K"), std::string::npos) << text;
    EXPECT_GT(colours(text), 0) << "the warning's level is coloured: " << text;
    text = on_a_terminal("TERM=xterm NO_COLOR=1");
    EXPECT_NE(text.find("\x1b[K"), std::string::npos) << text;
    EXPECT_EQ(colours(text), 0) << text;
    EXPECT_NE(text.find("shprt: warning: "), std::string::npos) << text;
    text = on_a_terminal("TERM=dumb");
    EXPECT_EQ(text.find('\x1b'), std::string::npos) << text;
    EXPECT_NE(text.find("shprt: bake: 100%"), std::string::npos) << text;
    EXPECT_NE(text.find("shprt: warning: "), std::string::npos) << text;
}

TEST_F(CliBake, HalfPrecisionFileIsSmaller) {
    const std::string full = out("full.shprt"), half = out("half.shprt");
    ASSERT_EQ(
        shprt("bake builtin:box_on_plane -o '" + full + "' --coeffs 16 --samples 32").exit_code, 0);
    ASSERT_EQ(shprt("bake builtin:box_on_plane -o '" + half +
                    "' --coeffs 16 --samples 32 --half --transfer unshadowed")
                  .exit_code,
              0);
    EXPECT_LT(fs::file_size(half), fs::file_size(full));
    EXPECT_EQ(shprt::read_shprt(half).transfer.kind, shprt::TransferKind::unshadowed);
}

TEST_F(CliBake, ProbesGoIntoTheFileAndInfoAndCompressKeepThem) {
    const std::string file = out("probes.shprt");
    const RunResult r = shprt("bake builtin:box_on_plane -o '" + file +
                              "' --coeffs 9 --samples 64 --probes 3,2,3 --probe-bands 2");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("probes: 3x2x3 = 18"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("probes: 100%"), std::string::npos) << "the probes' own bar: " << r.err;
    const shprt::ShprtFile f = shprt::read_shprt(file);
    EXPECT_EQ(f.transfer.probes.count(), 18u);
    EXPECT_EQ(f.transfer.probes.K, 4);
    if (shprt("info --help").exit_code == 0) {
        const RunResult info = shprt("info '" + file + "'");
        EXPECT_NE(info.out.find("probes       3x2x3 = 18"), std::string::npos) << info.out;
    }
    const std::string small = out("small.shprt");
    ASSERT_EQ(shprt("compress '" + file + "' -o '" + small + "' --cpca 2,4").exit_code, 0);
    EXPECT_TRUE(shprt::read_shprt(small).transfer.probes == f.transfer.probes);
    // Beside texels too.
    const std::string texels = out("texels.shprt");
    ASSERT_EQ(shprt("bake builtin:quad_box --domain texel --resolution 8 --samples 16 --probes "
                    "2,2,2 -o '" +
                    texels + "'")
                  .exit_code,
              0);
    EXPECT_EQ(shprt::read_shprt(texels).transfer.probes.count(), 8u);
}

TEST_F(CliBake, BadOptionsFailWithOneLineAndLeaveNothingBehind) {
    const std::string file = out("bad.shprt");
    const std::string base = "bake builtin:box_on_plane -o '" + file + "' ";
    const std::pair<const char*, const char*> bad[] = {
        {"--coeffs 0", "--coeffs 0: must be 1 to 1024"},
        {"--coeffs 1025", "--coeffs 1025"},
        {"--bands 0", "--bands 0: must be 1 to 32"},
        {"--bands 33", "--bands 33"},
        {"--samples 0 ", "--samples 0: must be"},
        {"--samples -3", "--samples -3"},
        {"--sampler bogus", "unknown sampler 'bogus'"},
        {"--directions tangent", "unknown directions 'tangent' (expected sphere or local)"},
        {"--transfer specular", "unknown transfer kind 'specular'"},
        {"--transfer glossy --bands 9", "glossy transfer: K = 81 is too large"},
        {"--transfer glossy --bounces 2", "--bounces: interreflected glossy transfer"},
        {"--device quantum", "unknown device 'quantum'"},
        {"--threads -1", "--threads -1"},
        {"--bands 2 --coeffs 4", "--bands and --coeffs both given"},
        {"--device cuda --max-device-memory lots", "--max-device-memory 'lots': expected a size"},
        {"--device auto --max-device-memory 0", "--max-device-memory '0'"},
        {"--max-device-memory 1G", "--max-device-memory needs --device cuda or auto"},
        {"--target-error 1.5", "--target-error 1.5: must be 0 (off) or a relative error"},
        {"--target-error -0.1", "--target-error -0.1"},
        {"--target-error 0.01 --max-samples 1000", "--max-samples 1000: must be a power of two"},
        {"--max-samples 1024", "--max-samples needs --target-error"},
        {"--target-error 0.01 --sampler stratified", "has no nested prefixes"},
        {"--target-error 0.01 --transfer glossy", "glossy transfer has no error-bounded bake"},
        {"--target-error 0.01 --device cuda --directions sphere",
         "--target-error on the GPU takes a local direction set"},
        {"--target-error 0.01 --device cuda --transfer interreflected",
         "--target-error with interreflected transfer bakes on the CPU (--device cpu)"},
        {"--target-error 0.01 --refine 0.1", "--target-error does not go with --refine yet"},
    };
    for (const auto& [option, message] : bad) {
        expect_one_line_error(shprt(base + option), message);
        EXPECT_TRUE(out_dir_empty());
    }
}

TEST_F(CliBake, MissingSceneAndUnwritableOutputFailCleanly) {
    const std::string file = out("x.shprt");
    RunResult r = shprt("bake '" + (m_dir / "no_such_scene.ply").string() + "' -o '" + file + "'");
    expect_one_line_error(r, "no_such_scene.ply");
    EXPECT_TRUE(out_dir_empty());

    const std::string unwritable = (m_dir / "no_such_dir" / "x.shprt").string();
    r = shprt("bake builtin:box_on_plane -o '" + unwritable + "' --samples 16");
    expect_one_line_error(r, "no_such_dir");
    EXPECT_FALSE(fs::exists(m_dir / "no_such_dir"));

    // An existing directory as the output.
    r = shprt("bake builtin:box_on_plane -o '" + (m_dir / "out").string() + "' --samples 16");
    expect_one_line_error(r, "it is a directory");
    EXPECT_TRUE(out_dir_empty());
    EXPECT_EQ(std::distance(fs::directory_iterator(m_dir), fs::directory_iterator()), 3)
        << "only out/, stdout and stderr";

    // CUDA: where this build or machine cannot bake on it, an error naming it and no file.
    r = shprt("bake builtin:box_on_plane -o '" + file + "' --samples 16 --device cuda");
    if (r.exit_code != 0) {
        EXPECT_NE(r.err.find("cuda"), std::string::npos) << r.err;
        EXPECT_TRUE(out_dir_empty());
    } else {
        EXPECT_TRUE(fs::exists(file));
    }
}

#if !SHPRT_HAS_MPI
// A build without MPI (SHPRT_MPI=OFF) says so for --mpi, and bakes without it.
TEST_F(CliBake, MpiWithoutMpiInTheBuildIsOneLine) {
    shprt::test_support::expect_one_line_error(
        shprt("bake builtin:plane --mpi -o '" + out("x.shprt") + "'"), "this build has no MPI");
    EXPECT_TRUE(out_dir_empty());
    EXPECT_EQ(
        shprt("bake builtin:plane --coeffs 4 --samples 16 -o '" + out("x.shprt") + "'").exit_code,
        0);
}
#endif

}  // namespace
