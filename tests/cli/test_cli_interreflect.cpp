// `shprt bake --transfer interreflected` run as a program: the file holds RGB transfer and its
// direct part (read back by the library: the direct part is the shadowed bake's bits), `info`
// says where the albedo came from and the bounces, `shade --direct` shades T_0 only, and what
// cannot be done (cuda, shards, streaming, options without the kind) is one line on stderr.
#include "shprt/bake/bake.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/bake/interreflect.hpp"
#include "shprt/config.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/load.hpp"

#include "cli/cli_test.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

using test_support::expect_one_line_error;

class CliInterreflect : public test_support::CliTest {};

TEST_F(CliInterreflect, BakeInfoShadeDirect) {
    const std::string file = (m_dir / "box.shprt").string();
    auto r = shprt(
        "bake builtin:box_on_plane --transfer interreflected --bounces 2 --coeffs 9 "
        "--samples 128 --albedo 0.9,0.5,0.25 --reproducible -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("interreflection: 2 bounces"));
    // A fixed count is no convergence test, and the line says so rather than read "not converged".
    EXPECT_THAT(r.out, ::testing::HasSubstr("2 bounces (a fixed count, not tested for convergence; "
                                            "largest relative change by bounce 2: "));

    const ShprtFile f = read_shprt(file);
    EXPECT_EQ(f.transfer.kind, TransferKind::interreflected);
    EXPECT_EQ(f.transfer.layout.channels, 3);
    EXPECT_EQ(f.transfer.interreflection.bounces, 2);
    EXPECT_EQ(f.transfer.interreflection.albedo_source, "--albedo 0.9,0.5,0.25");
    EXPECT_GT(f.transfer.interreflection.operator_nnz, 0u);
    EXPECT_EQ(f.mesh.albedo[0].x, 0.9f);  // the file keeps the albedo the bake used

    // The direct part is the shadowed bake of the same scene, bit for bit.
    BakeOptions o;
    o.K = 9;
    o.samples = 128;
    const TransferSet shadowed = bake(load_scene("builtin:box_on_plane"), o);
    ASSERT_EQ(f.transfer.direct.size(), shadowed.coeffs.size());
    EXPECT_EQ(std::memcmp(f.transfer.direct.data(), shadowed.coeffs.data(),
                          shadowed.coeffs.size() * sizeof(float)),
              0);

    r = shprt("info '" + file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("albedo       --albedo 0.9,0.5,0.25"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("bounces      2"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("a fixed count, not tested for convergence"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("nnz(A) = "));

#if SHPRT_HAS_RENDER  // `shade` comes with the renderer
    const std::string both = (m_dir / "both.csv").string(),
                      direct = (m_dir / "direct.csv").string();
    ASSERT_EQ(shprt("shade '" + file + "' --light constant -o '" + both + "'").exit_code, 0);
    ASSERT_EQ(shprt("shade '" + file + "' --direct --light constant -o '" + direct + "'").exit_code,
              0);
    EXPECT_NE(test_support::slurp(both), test_support::slurp(direct));
    // A CPCA file keeps the direct part: `--direct` shades the same.
    const std::string compressed = (m_dir / "c.shprt").string(),
                      cdirect = (m_dir / "cdirect.csv").string();
    r = shprt("compress '" + file + "' -o '" + compressed + "' --cpca 8,4");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("direct part: kept beside the code (--direct), 36 "
                                            "B/vertex"));
    ASSERT_EQ(shprt("shade '" + compressed + "' --direct --light constant -o '" + cdirect + "'")
                  .exit_code,
              0);
    EXPECT_EQ(test_support::slurp(cdirect), test_support::slurp(direct));
#endif

    // The same bake without --albedo: the builtin scene's own colours, named.
    r = shprt(
        "bake builtin:box_on_plane --transfer interreflected --bounces converged "
        "--coeffs 4 --samples 64 -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out,
                ::testing::ContainsRegex("bounces? \\((NOT )?converged: last relative change"));
    r = shprt("info '" + file + "'");
    EXPECT_THAT(r.out, ::testing::HasSubstr("albedo       builtin scene colours"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("converged"));
}

// The bounce sources from the command line: --indirect-samples and --source-spacing reach the
// bake and the file, `info` names the sources and the receivers that see back faces (many on the
// leaky room, whose parts overlap), and bad values get one line naming the option.
TEST_F(CliInterreflect, BounceSourcesOptionsAndInfo) {
    const std::string file = (m_dir / "leaky.shprt").string();
    auto r = shprt(
        "bake builtin:leaky_room --transfer interreflected --bounces 1 --coeffs 4 --samples 256 "
        "--indirect-samples 32 --source-spacing 0.25 --two-sided --bounce-coeffs 1 -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const ShprtFile f = read_shprt(file);
    const InterreflectionInfo& ir = f.transfer.interreflection;
    EXPECT_EQ(ir.indirect_samples, 32u);
    EXPECT_EQ(ir.bounce_coeffs, 1u);
    EXPECT_FLOAT_EQ(float(ir.source_spacing), 0.25f);
    EXPECT_GT(ir.sources, 2 * f.mesh.vertex_count());  // cells, and back copies
    EXPECT_GT(ir.invalid_sources, 0u);                 // ends of panels inside their neighbours
    EXPECT_GT(ir.receivers_seeing_back_faces, f.mesh.vertex_count() / 10);
    r = shprt("info '" + file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("cells of at most 0.25 m"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("32 directions per receiver"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("K = 4 after one bounce, the first 1 after more"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("see back faces: a leaky or open asset?"));
    EXPECT_THAT(r.out, ::testing::HasSubstr("a back face sends the light of its own side"));

    r = shprt(
        "bake builtin:box_on_plane --transfer interreflected --coeffs 4 --samples 64 "
        "--source-spacing vertices -o '" +
        file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_shprt(file).transfer.interreflection.sources,
              load_scene("builtin:box_on_plane").vertex_count());
    EXPECT_THAT(shprt("info '" + file + "'").out, ::testing::HasSubstr("(the mesh's vertices)"));

    for (const char* bad : {"--source-spacing 0", "--source-spacing -1", "--source-spacing x",
                            "--indirect-samples 0", "--bounce-coeffs 0", "--bounce-coeffs 17"}) {
        r = shprt(std::string("bake builtin:plane --transfer interreflected -o '") + file + "' " +
                  bad);
        expect_one_line_error(r, std::string(bad).substr(0, std::string(bad).find(' ')));
    }
    r = shprt("bake builtin:plane --indirect-samples 8 -o '" + file + "'");
    expect_one_line_error(r, "need --transfer interreflected");
}

// --max-memory just above the estimate of everything but the operator: A does not fit, its blocks
// are spilled beside the output and read back memory-mapped, and the file is byte for byte the
// one baked with A in memory; no temporary file is left.
TEST_F(CliInterreflect, SpilledOperatorWritesTheSameFile) {
    const std::string base =
        "bake builtin:box_on_plane --transfer interreflected --bounces 2 --coeffs 9 --samples 128 "
        "--albedo 0.9,0.5,0.25 --threads 2 --reproducible ";
    const std::string in_memory = (m_dir / "in_memory.shprt").string();
    auto r = shprt(base + "-o '" + in_memory + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("past the memory budget")));

    BakeOptions o;
    o.transfer = TransferKind::interreflected;
    o.K = 9;
    o.samples = 128;
    o.threads = 2;
    const Mesh mesh = load_scene("builtin:box_on_plane");
    const std::uint64_t rest = estimate_bake_peak_bytes(mesh.triangle_count(), mesh.vertex_count(),
                                                        o, true, bake_bounce_source_count(mesh, o));
    const std::filesystem::path spill_dir = m_dir / "spill";
    std::filesystem::create_directories(spill_dir);
    const std::string spilled = (spill_dir / "spilled.shprt").string();
    r = shprt(base + "--max-memory " + std::to_string(rest + 1024) + " -o '" + spilled + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, ::testing::HasSubstr("past the memory budget"));
    EXPECT_EQ(test_support::slurp(spilled), test_support::slurp(in_memory));
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(spill_dir)) {
        ++files;
        EXPECT_EQ(e.path().filename(), "spilled.shprt") << "left behind: " << e.path();
    }
    EXPECT_EQ(files, 1u);

    // Without --reproducible the file's stats keep the bytes spilled, and `info` says so.
    const std::string with_stats = (spill_dir / "stats.shprt").string();
    std::string command = base;
    command.replace(command.find("--reproducible"), 14, "");
    r = shprt(command + "--max-memory " + std::to_string(rest + 1024) + " -o '" + with_stats + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GT(read_shprt(with_stats).transfer.stats.operator_bytes_spilled, 0u);
    r = shprt("info '" + with_stats + "'");
    EXPECT_THAT(r.out, ::testing::HasSubstr("operator spilled"));
}

TEST_F(CliInterreflect, RefusalsAreOneLine) {
    const std::string out = (m_dir / "x.shprt").string();
    const std::string base = "bake builtin:plane --samples 64 --coeffs 4 -o '" + out + "' ";
    if (!shprt::query_gpu().available)  // the GPU path exists; without a GPU, one line
        expect_one_line_error(shprt(base + "--transfer interreflected --device cuda"),
                              "device 'cuda'");
    expect_one_line_error(shprt(base + "--transfer interreflected --shard 0/2"),
                          "cannot be sharded");
    expect_one_line_error(shprt(base + "--transfer interreflected --stream"), "--stream");
    expect_one_line_error(shprt(base + "--bounces 2"), "need --transfer interreflected");
    expect_one_line_error(shprt(base + "--transfer interreflected --bounces lots"),
                          "--bounces 'lots'");
    expect_one_line_error(shprt(base + "--transfer interreflected --tolerance 0.01"),
                          "--tolerance needs --bounces converged");
    expect_one_line_error(shprt(base + "--transfer interreflected --albedo 1.5,0,0"),
                          "--albedo 1.5,0,0");
#if SHPRT_HAS_RENDER
    const std::string plain = (m_dir / "plain.shprt").string();
    ASSERT_EQ(shprt("bake builtin:plane --samples 64 --coeffs 4 -o '" + plain + "'").exit_code, 0);
    expect_one_line_error(shprt("shade '" + plain + "' --direct --light constant -o '" +
                                (m_dir / "a.csv").string() + "'"),
                          "has no direct part");
#endif
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace shprt
