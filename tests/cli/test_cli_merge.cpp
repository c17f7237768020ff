// Sharded and streamed bakes as programs: `shprt bake --shard I/N` parts (written at once or
// streamed with --stream), joined by `shprt merge`, equal the single-process bake bit for bit
// whatever the order of the parts; parts that do not belong
// together, leave a gap or overlap give one line and no output; a part is not a scene to shade.
#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"

#include "cli/cli_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace shprt {
namespace {

using test_support::expect_one_line_error;
using test_support::RunResult;

constexpr const char* kBake = "bake builtin:box_on_plane --coeffs 16 --samples 128 --seed 3";

class CliMerge : public test_support::CliTest {
protected:
    void bake_part(int i, int n, const std::string& extra = "") {
        const RunResult r =
            shprt(fmt::format("{} {} --shard {}/{} -o '{}'", kBake, extra, i, n, part(i, n)));
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    std::string part(int i, int n) const { return out(fmt::format("part_{}_of_{}.shprt", i, n)); }
};

// The error-bounded bake (docs/sampling.md, "Error-bounded bakes"): the same file for one and two
// threads (cmp), and the same rows and per-receiver estimates from two shards merged and from a
// streamed bake (their metadata differ: the parts' stats, the stream's padding).
TEST_F(CliMerge, ErrorBoundedBakeSameBitsForThreadsShardsAndStream) {
    const std::string bake =
        "bake builtin:box_on_plane --coeffs 16 --directions local --target-error 0.03 "
        "--max-samples 512 --reproducible";
    const auto file_bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    for (int threads : {1, 2}) {
        const RunResult r = shprt(fmt::format("{} --threads {} -o '{}'", bake, threads,
                                              out(fmt::format("t{}.shprt", threads))));
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.out.find("error bound: receivers per prefix"), std::string::npos) << r.out;
    }
    EXPECT_EQ(file_bytes(out("t1.shprt")), file_bytes(out("t2.shprt")));
    for (int i : {0, 1})
        ASSERT_EQ(shprt(fmt::format("{} --shard {}/2 -o '{}'", bake, i, part(i, 2))).exit_code, 0);
    ASSERT_EQ(shprt(fmt::format("merge '{}' '{}' -o '{}'", part(1, 2), part(0, 2), out("m.shprt")))
                  .exit_code,
              0);
    ASSERT_EQ(shprt(fmt::format("{} --stream -o '{}'", bake, out("s.shprt"))).exit_code, 0);
    const ShprtFile whole = read_shprt(out("t1.shprt"));
    EXPECT_EQ(whole.transfer.target_error, 0.03);
    ASSERT_EQ(whole.transfer.receiver_samples.size(), 1214u);
    for (const char* name : {"m.shprt", "s.shprt"}) {
        const ShprtFile other = read_shprt(out(name));
        EXPECT_TRUE(other.transfer.coeffs == whole.transfer.coeffs) << name;
        EXPECT_EQ(other.transfer.receiver_samples, whole.transfer.receiver_samples) << name;
        EXPECT_EQ(other.transfer.receiver_error, whole.transfer.receiver_error) << name;
        EXPECT_EQ(other.transfer.target_error, 0.03) << name;
    }
    const RunResult info = shprt(fmt::format("info '{}'", out("m.shprt")));
    EXPECT_NE(info.out.find("samples      receivers per prefix 128: "), std::string::npos)
        << info.out;
    EXPECT_NE(info.out.find("est. error   worst 0.0"), std::string::npos) << info.out;
}

TEST_F(CliMerge, PartsInAnyOrderMergeToTheSingleBakeBitForBit) {
    ASSERT_EQ(shprt(fmt::format("{} -o '{}'", kBake, out("whole.shprt"))).exit_code, 0);
    for (int i : {2, 0, 3, 1}) bake_part(i, 4);
    const ShprtFile p1 = read_shprt_part(part(1, 4));
    EXPECT_TRUE(p1.is_part());
    EXPECT_EQ(p1.receiver_first, 1214u / 4);  // box_on_plane has 1214 vertices
    EXPECT_EQ(p1.transfer.receiver_count(), 1214u * 2 / 4 - 1214u / 4);
    const RunResult info = shprt(fmt::format("info '{}'", part(1, 4)));
    EXPECT_EQ(info.exit_code, 0);
    EXPECT_NE(info.out.find("receivers    [303, 607) of 1214: one part"), std::string::npos)
        << info.out;

    const RunResult r = shprt(fmt::format("merge '{}' '{}' '{}' '{}' -o '{}'", part(3, 4),
                                          part(1, 4), part(0, 4), part(2, 4), out("m.shprt")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("merged 4 parts: 1214 vertices"), std::string::npos) << r.out;
    const ShprtFile whole = read_shprt(out("whole.shprt"));
    const ShprtFile merged = read_shprt(out("m.shprt"));
    EXPECT_FALSE(merged.is_part());
    EXPECT_EQ(merged.transfer.layout, whole.transfer.layout);
    EXPECT_EQ(merged.transfer.seed, 3u);
    EXPECT_TRUE(merged.transfer.coeffs == whole.transfer.coeffs)
        << "the merged parts differ from the single-process bake";
    EXPECT_EQ(merged.mesh.positions, whole.mesh.positions);
    EXPECT_EQ(merged.transfer.stats.rays_cast, whole.transfer.stats.rays_cast);
}

// With --reproducible (no timings, no command line) the merged file is the single bake's file
// byte for byte, as the single bake run twice is.
TEST_F(CliMerge, ReproducibleMergeIsTheSingleBakeByteForByte) {
    ASSERT_EQ(shprt(fmt::format("{} --reproducible -o '{}'", kBake, out("a.shprt"))).exit_code, 0);
    ASSERT_EQ(shprt(fmt::format("{} --reproducible -o '{}'", kBake, out("b.shprt"))).exit_code, 0);
    EXPECT_TRUE(test_support::slurp(out("a.shprt")) == test_support::slurp(out("b.shprt")));
    for (int i : {0, 1, 2}) bake_part(i, 3, "--reproducible");
    const RunResult r = shprt(fmt::format("merge --reproducible '{}' '{}' '{}' -o '{}'", part(2, 3),
                                          part(0, 3), part(1, 3), out("m.shprt")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(test_support::slurp(out("a.shprt")) == test_support::slurp(out("m.shprt")))
        << "the merged parts are not the single bake's bytes";
    // Without the flag the file records the merge's stats, so the bytes differ.
    ASSERT_EQ(shprt(fmt::format("merge '{}' '{}' '{}' -o '{}'", part(2, 3), part(0, 3), part(1, 3),
                                out("n.shprt")))
                  .exit_code,
              0);
    EXPECT_FALSE(test_support::slurp(out("a.shprt")) == test_support::slurp(out("n.shprt")));
}

TEST_F(CliMerge, StreamedBakesAndPartsEqualTheWrittenOnes) {
    ASSERT_EQ(shprt(fmt::format("{} -o '{}'", kBake, out("whole.shprt"))).exit_code, 0);
    const RunResult streamed = shprt(fmt::format("{} --stream -o '{}'", kBake, out("s.shprt")));
    ASSERT_EQ(streamed.exit_code, 0) << streamed.err;
    EXPECT_NE(streamed.out.find("baked 1214 vertices"), std::string::npos) << streamed.out;
    const ShprtFile whole = read_shprt(out("whole.shprt"));
    EXPECT_TRUE(read_shprt(out("s.shprt")).transfer.coeffs == whole.transfer.coeffs);
    // Streamed float16 parts, merged.
    for (int i : {0, 1})
        ASSERT_EQ(
            shprt(fmt::format("{} --stream --half --shard {}/2 -o '{}'", kBake, i, part(i, 2)))
                .exit_code,
            0);
    ASSERT_EQ(shprt(fmt::format("{} --half -o '{}'", kBake, out("half.shprt"))).exit_code, 0);
    ASSERT_EQ(shprt(fmt::format("merge '{}' '{}' -o '{}'", part(1, 2), part(0, 2), out("m.shprt")))
                  .exit_code,
              0);
    const ShprtFile merged = read_shprt(out("m.shprt"));
    EXPECT_EQ(merged.transfer.layout.encoding, TransferEncoding::f16);
    EXPECT_TRUE(merged.transfer.coeffs == read_shprt(out("half.shprt")).transfer.coeffs);
}

TEST_F(CliMerge, PartsThatDoNotTileTheSceneOrDoNotBelongTogetherAreRefused) {
    for (int i : {0, 1, 2}) bake_part(i, 3);
    const auto merge = [&](const std::string& parts) {
        return shprt(fmt::format("merge {} -o '{}'", parts, out("m.shprt")));
    };
    const std::string p0 = "'" + part(0, 3) + "'", p1 = "'" + part(1, 3) + "'",
                      p2 = "'" + part(2, 3) + "'";
    expect_one_line_error(merge(p0 + " " + p2), "are in no part");
    expect_one_line_error(merge(p0 + " " + p1), "receivers [809, 1214) are in no part");
    expect_one_line_error(merge(p0 + " " + p1 + " " + p1 + " " + p2), "overlap");
    // Another seed, another K: not the same bake.
    const std::pair<const char*, const char*> foreign[] = {{"--coeffs 16 --seed 4", "seed 4"},
                                                           {"--coeffs 9 --seed 3", "K = 9"}};
    for (const auto& [options, complaint] : foreign) {
        const std::string other = out("other.shprt");
        ASSERT_EQ(shprt(fmt::format("bake builtin:box_on_plane --samples 128 {} --shard 1/3 -o "
                                    "'{}'",
                                    options, other))
                      .exit_code,
                  0);
        expect_one_line_error(merge(p0 + " '" + other + "' " + p2), complaint);
    }
    EXPECT_FALSE(std::filesystem::exists(out("m.shprt"))) << "no output after a refused merge";
}

TEST_F(CliMerge, APartIsNotAWholeFileAndBadShardsAreUsageErrors) {
    bake_part(1, 2);
    if (SHPRT_HAS_RENDER)  // the commands that shade need the renderer
        expect_one_line_error(shprt(fmt::format("render '{}' -o '{}'", part(1, 2), out("x.png"))),
                              "is part of a sharded bake (receivers [607, 1214) of 1214)");
    EXPECT_THROW(read_shprt(part(1, 2)), Error);
    for (const char* bad : {"2/2", "1", "a/3", "-1/3", "1/0", "1/2/3"})
        expect_one_line_error(
            shprt(fmt::format("{} --shard {} -o '{}'", kBake, bad, out("bad.shprt"))), "--shard");
    expect_one_line_error(shprt(fmt::format("{} --shard 0/5000 -o '{}'", kBake, out("bad.shprt"))),
                          "empty");
    EXPECT_FALSE(std::filesystem::exists(out("bad.shprt")));
}

}  // namespace
}  // namespace shprt
