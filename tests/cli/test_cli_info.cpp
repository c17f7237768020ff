// `shprt info` run as a program (SHPRT_CLI_PATH) on files written by the library: the summary
// names K and the vertex count, --json prints the metadata, and a corrupt or missing file gives
// exit status != 0 with exactly one line on stderr.
#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"

#include "cli/cli_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

namespace shprt {
namespace {

namespace fs = std::filesystem;

using test_support::expect_one_line_error;
using test_support::RunResult;

class CliInfo : public test_support::CliTest {
protected:
    void SetUp() override {
        CliTest::SetUp();
        m_file = (m_dir / "grid.shprt").string();
        Mesh mesh;
        for (int i = 0; i < 37; ++i) {  // a fan of 37 vertices, 35 triangles
            mesh.positions.push_back({float(i % 7), 0.0f, float(i / 7)});
            mesh.normals.push_back({0.0f, 1.0f, 0.0f});
            mesh.albedo.push_back({0.5f, 0.5f, 0.5f});
        }
        for (std::uint32_t i = 1; i + 1 < 37; ++i) mesh.triangles.push_back({0, i, i + 1});
        mesh.source = "builtin:cli-test";
        TransferSet t;
        t.layout.K = 48;
        t.coeffs.assign(37 * 48, 0.25f);
        t.samples = 1024;
        t.stats.seconds_total = 0.5;
        t.stats.seconds_trace = 0.25;
        t.stats.rays_cast = 1000000;
        write_shprt(m_file, mesh, t);
    }
    std::string m_file;
};

TEST_F(CliInfo, SummaryNamesKAndVertexCount) {
    const RunResult r = shprt(fmt::format("info '{}'", m_file));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("K = 48"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("7 bands, last band partial"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("vertices     37"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("triangles    35"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("rays/s"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(std::to_string(fs::file_size(m_file)) + " bytes"), std::string::npos)
        << r.out;
    EXPECT_EQ(r.err, "");
}

// The bake's summary line and `shprt info` state one peak memory (issue 40: they said 8.9 and
// 24.3 MiB for the room at K = 256, the line leaving out the rows held for the file). Also with
// --stream, which holds no rows.
TEST_F(CliInfo, PeakMemoryIsTheBakeLinesNumber) {
    for (const char* stream : {"", " --stream"}) {
        const std::string file = (m_dir / "peak.shprt").string();
        const RunResult bake = shprt(
            fmt::format("bake builtin:sphere --coeffs 256 --samples 16 -o '{}'{}", file, stream));
        ASSERT_EQ(bake.exit_code, 0) << bake.err;
        const std::size_t at = bake.out.find("peak ");
        ASSERT_NE(at, std::string::npos) << bake.out;
        const double line_mib = std::stod(bake.out.substr(at + 5));
        const RunResult info = shprt(fmt::format("info --json '{}'", file));
        ASSERT_EQ(info.exit_code, 0) << info.err;
        const double file_bytes = nlohmann::json::parse(info.out)["stats"]["peak_bytes_host"];
        EXPECT_NEAR(line_mib, file_bytes / (1024.0 * 1024.0), 0.051) << stream << ": " << bake.out;
        // The rows (vertices × 256 floats) are in the number unless streamed.
        const ShprtFile f = read_shprt(file);
        const double rows = double(f.transfer.coeffs.size()) * sizeof(float);
        if (*stream == '\0') EXPECT_GT(file_bytes, rows) << bake.out;
    }
}

TEST_F(CliInfo, JsonPrintsTheMetadata) {
    const RunResult r = shprt(fmt::format("info --json '{}'", m_file));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto meta = nlohmann::json::parse(r.out);
    EXPECT_EQ(meta["K"], 48);
    EXPECT_EQ(meta["scene"]["vertices"], 37);
    EXPECT_EQ(meta["sampler"], "uniform");
}

TEST_F(CliInfo, CorruptOrMissingFileGivesOneLineError) {
    std::string bytes = read_file(m_file);
    bytes[bytes.size() - 3] ^= 0x40;  // inside the transfer section
    const std::string corrupt = (m_dir / "corrupt.shprt").string();
    std::ofstream(corrupt, std::ios::binary) << bytes;
    const std::string truncated = (m_dir / "truncated.shprt").string();
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);

    for (const auto& [file, expected] :
         {std::pair{corrupt, std::string("section 'transfer' fails its checksum")},
          std::pair{truncated, std::string("truncated")},
          std::pair{(m_dir / "missing.shprt").string(), std::string("cannot open")}}) {
        const RunResult r = shprt(fmt::format("info '{}'", file));
        expect_one_line_error(r, expected);
        EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
    }
    expect_usage_error(shprt("info"), "file is required");
}

// `shprt info` on one file of every transfer kind (tests/data/shprt_kinds, written by the build
// before the metadata became one field table) prints what it printed then: the .info files beside
// them (SHPRT_UPDATE_GOLDEN=1 rewrites them).
TEST_F(CliInfo, EveryKindSummarisedAsBefore) {
    const fs::path dir = fs::path(SHPRT_TEST_DATA_DIR) / "shprt_kinds";
    const bool update = std::getenv("SHPRT_UPDATE_GOLDEN") != nullptr &&
                        std::string(std::getenv("SHPRT_UPDATE_GOLDEN")) == "1";
    int files = 0;
    for (const char* kind : {"vector", "glossy", "cpca", "interreflected", "texels", "refined",
                             "probes", "probe_cpca", "error_bounded", "part"}) {
        const fs::path file = dir / (std::string(kind) + ".shprt");
        const fs::path golden = dir / (std::string(kind) + ".info");
        const RunResult r = shprt(fmt::format("info '{}'", file.string()));
        ASSERT_EQ(r.exit_code, 0) << kind << ": " << r.err;
        if (update) {
            std::ofstream(golden, std::ios::binary) << r.out;
        } else {
            EXPECT_EQ(r.out, read_file(golden.string())) << kind;
        }
        ++files;
    }
    EXPECT_EQ(files, 10);
}

}  // namespace
}  // namespace shprt
