// `shprt scene` run as a program (SHPRT_CLI_PATH): generated PLY files load back to the same
// mesh, `info` and `list` print what they should, and bad requests exit non-zero with one line on
// stderr and no output file left behind.
#include "shprt/core/file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/room.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace shprt {
namespace {

namespace fs = std::filesystem;

struct CliRun {
    int status;
    std::string out, err;
};

class CliScene : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / fmt::format("shprt_cli_scene_{}", ::getpid());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    CliRun run(const std::string& args) const {
        const std::string out = path("stdout.txt"), err = path("stderr.txt");
        const std::string command =
            fmt::format("'{}' {} > '{}' 2> '{}'", SHPRT_CLI_PATH, args, out, err);
        const int raw = std::system(command.c_str());
        CliRun r;
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
        r.out = read_file(out);
        r.err = read_file(err);
        return r;
    }

    // Only the captured stdout/stderr files: no output, no temporary file.
    std::size_t files_left() const {
        std::size_t n = 0;
        for (const auto& e : fs::directory_iterator(m_dir)) {
            const std::string name = e.path().filename().string();
            if (name != "stdout.txt" && name != "stderr.txt") ++n;
        }
        return n;
    }

    void expect_failure(const CliRun& r, const std::string& what) const {
        EXPECT_NE(r.status, 0);
        EXPECT_EQ(r.status, 1) << "a shprt::Error exits with 1: " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(r.err.rfind("shprt: error: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
        EXPECT_EQ(files_left(), 0u);
    }

    fs::path m_dir;
};

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST_F(CliScene, RoomPlyLoadsBackToTheGeneratedMesh) {
    const std::string out = path("room.ply");
    const CliRun r = run(fmt::format("scene room -o '{}' --triangles 5000", out));
    ASSERT_EQ(r.status, 0) << r.err;
    const Mesh expected = generate_room({5000, false});
    EXPECT_NE(r.out.find(fmt::format("{} triangles", expected.triangle_count())), std::string::npos)
        << r.out;
    const Mesh loaded = load_scene(out);
    EXPECT_TRUE(same_bits(loaded.positions, expected.positions));
    EXPECT_TRUE(same_bits(loaded.normals, expected.normals));
    EXPECT_TRUE(same_bits(loaded.triangles, expected.triangles));
    ASSERT_EQ(loaded.albedo.size(), expected.albedo.size());
    constexpr float kSrgbByteTol = 0.01f;  // albedo travels as 8-bit sRGB
    for (std::size_t v = 0; v < loaded.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(loaded.albedo[v][c], expected.albedo[v][c], kSrgbByteTol);

    const CliRun info = run(fmt::format("scene info '{}'", out));
    ASSERT_EQ(info.status, 0) << info.err;
    EXPECT_NE(info.out.find(fmt::format("{} vertices, {} triangles", expected.vertex_count(),
                                        expected.triangle_count())),
              std::string::npos)
        << info.out;
    EXPECT_NE(info.out.find("bounds: [-3.2, 0, -2.7] .. [3.2, 2.7, 2.7]"), std::string::npos)
        << info.out;
}

TEST_F(CliScene, CeilingAndOtherBuiltins) {
    const std::string room = path("closed.ply");
    ASSERT_EQ(run(fmt::format("scene room --ceiling --triangles 3000 -o '{}'", room)).status, 0);
    EXPECT_EQ(mesh_bounds(load_scene(room)).hi.y, kRoomCeilingTop);
    for (const std::string& name : builtin_scene_names()) {
        if (name == "room") continue;
        const std::string out = path(name + ".ply");
        const CliRun r = run(fmt::format("scene {} -o '{}'", name, out));
        ASSERT_EQ(r.status, 0) << name << ": " << r.err;
        EXPECT_EQ(load_scene(out).triangle_count(), make_builtin(name).triangle_count()) << name;
    }
}

TEST_F(CliScene, ListAndInfoOfBuiltins) {
    const CliRun list = run("scene list");
    ASSERT_EQ(list.status, 0);
    for (const std::string& name : builtin_scene_names())
        EXPECT_NE(list.out.find(name), std::string::npos) << list.out;
    const CliRun info = run("scene info builtin:sphere");
    ASSERT_EQ(info.status, 0) << info.err;
    EXPECT_NE(info.out.find("642 vertices, 1280 triangles"), std::string::npos) << info.out;
}

TEST_F(CliScene, BadRequestsFailCleanly) {
    expect_failure(run(fmt::format("scene info '{}'", path("missing.obj"))),
                   path("missing.obj") + ": no such file");
    expect_failure(run("scene info builtin:teapot"), "unknown built-in scene 'teapot'");
    expect_failure(run(fmt::format("scene room --triangles 10 -o '{}'", path("small.ply"))),
                   "10 triangles requested");
    expect_failure(run(fmt::format("scene plane -o '{}'", path("plane.obj"))), "PLY");
    expect_failure(run(fmt::format("scene room -o '{}'", path("no/such/dir/room.ply"))),
                   "cannot write");
    // Argument errors are CLI11's: non-zero, and nothing written.
    EXPECT_NE(run("scene").status, 0);
    EXPECT_NE(run(fmt::format("scene teapot -o '{}'", path("t.ply"))).status, 0);
    EXPECT_NE(run(fmt::format("scene sphere --triangles 5 -o '{}'", path("s.ply"))).status, 0);
    EXPECT_NE(run("scene room").status, 0);  // -o is required
    EXPECT_EQ(files_left(), 0u);
}

}  // namespace
}  // namespace shprt
