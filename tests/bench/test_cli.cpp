// The benchmarks' shared command line (bench/bench_cli.hpp): the defaults stay when nothing is
// given, each option sets its variable, --K repeats, and a bad value or an unknown option is one
// line "NAME: error: ..." naming the option, with exit code 2.
#include "bench_cli.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace shprt::bench {
namespace {

struct Args {
    int K = 25, samples = 1024, reps = 3, threads = 0;
    std::vector<int> Ks;
    bool table = true, quick = false, a = true, b = true;
    std::size_t chunk = 0;
};

void parse(Args& a, std::vector<std::string> words) {
    words.insert(words.begin(), "bench_test");
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    BenchCli cli("bench_test", "a test");
    cli.K(a.K, 64).samples(a.samples).reps(a.reps).threads(a.threads);
    cli.flag("--no-table", a.table, false, "no table");
    cli.flag("--quick", a.quick, true, "quick");
    cli.flag(
        "--neither", [&a] { a.a = a.b = false; }, "both off");
    cli.option("--chunk", a.chunk, "chunk");
    cli.parse(int(argv.size()), argv.data());
}

TEST(BenchCli, DefaultsStayAndOptionsSetTheirVariables) {
    Args a;
    parse(a, {});
    EXPECT_EQ(a.K, 25);
    EXPECT_EQ(a.samples, 1024);
    EXPECT_EQ(a.reps, 3);
    EXPECT_EQ(a.threads, 0);
    EXPECT_TRUE(a.table);
    EXPECT_FALSE(a.quick);
    parse(a, {"--K", "16", "--samples", "64", "--reps", "1", "--threads", "2", "--no-table",
              "--quick", "--neither", "--chunk", "48"});
    EXPECT_EQ(a.K, 16);
    EXPECT_EQ(a.samples, 64);
    EXPECT_EQ(a.reps, 1);
    EXPECT_EQ(a.threads, 2);
    EXPECT_FALSE(a.table);
    EXPECT_TRUE(a.quick);
    EXPECT_FALSE(a.a);
    EXPECT_FALSE(a.b);
    EXPECT_EQ(a.chunk, 48u);
}

TEST(BenchCli, KRepeats) {
    std::vector<int> Ks;
    std::vector<std::string> words{"bench_test", "--K", "16", "--K", "64"};
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    BenchCli cli("bench_test", "a test");
    cli.Ks(Ks);
    cli.parse(int(argv.size()), argv.data());
    EXPECT_EQ(Ks, (std::vector<int>{16, 64}));
}

TEST(BenchCli, BadValuesAreOneLineAndExitCode2) {
    const auto bad = [](std::vector<std::string> words) {
        Args a;
        parse(a, std::move(words));
    };
    using ::testing::ExitedWithCode;
    EXPECT_EXIT(bad({"--reps", "0"}), ExitedWithCode(2), "^bench_test: error: --reps: .*0");
    EXPECT_EXIT(bad({"--K", "65"}), ExitedWithCode(2), "^bench_test: error: --K: .*65");
    EXPECT_EXIT(bad({"--threads", "-1"}), ExitedWithCode(2), "^bench_test: error: --threads");
    EXPECT_EXIT(bad({"--samples", "many"}), ExitedWithCode(2), "^bench_test: error: --samples");
    EXPECT_EXIT(bad({"--chunk", "x"}), ExitedWithCode(2), "^bench_test: error: .*--chunk = x");
    EXPECT_EXIT(bad({"--frobnicate"}), ExitedWithCode(2), "^bench_test: error: .*--frobnicate");
    EXPECT_EXIT(bad({"--help"}), ExitedWithCode(0), "");
}

}  // namespace
}  // namespace shprt::bench
