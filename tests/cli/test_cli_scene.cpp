// `shprt scene` run as a program (SHPRT_CLI_PATH): generated PLY files load back to the same
// mesh, `info` and `list` print what they should, and bad requests exit non-zero with one line on
// stderr and no output file left behind.
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/room.hpp"

#include "cli/cli_test.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstring>
#include <string>
#include <vector>

namespace shprt {
namespace {

using test_support::RunResult;

class CliScene : public test_support::CliTest {
protected:
    // A failure reported as a one-line error that leaves no output and no temporary file.
    void expect_failure(const RunResult& r, const std::string& needle) const {
        test_support::expect_one_line_error(r, needle);
        EXPECT_TRUE(out_dir_empty());
    }
};

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST_F(CliScene, RoomPlyLoadsBackToTheGeneratedMesh) {
    const std::string file = out("room.ply");
    const RunResult r = shprt(fmt::format("scene room -o '{}' --triangles 5000", file));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Mesh expected = generate_room({5000, false});
    EXPECT_NE(r.out.find(fmt::format("{} triangles", expected.triangle_count())), std::string::npos)
        << r.out;
    const Mesh loaded = load_scene(file);
    EXPECT_TRUE(same_bits(loaded.positions, expected.positions));
    EXPECT_TRUE(same_bits(loaded.normals, expected.normals));
    EXPECT_TRUE(same_bits(loaded.triangles, expected.triangles));
    ASSERT_EQ(loaded.uvs.size(), expected.vertex_count());  // the atlas travels as s, t
    EXPECT_EQ(loaded.uvs, expected.uvs);
    ASSERT_EQ(loaded.albedo.size(), expected.albedo.size());
    constexpr float kSrgbByteTol = 0.01f;  // albedo travels as 8-bit sRGB
    for (std::size_t v = 0; v < loaded.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(loaded.albedo[v][c], expected.albedo[v][c], kSrgbByteTol);

    const RunResult info = shprt(fmt::format("scene info '{}'", file));
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find(fmt::format("{} vertices, {} triangles", expected.vertex_count(),
                                        expected.triangle_count())),
              std::string::npos)
        << info.out;
    EXPECT_NE(info.out.find("bounds: [-3.2, 0, -2.7] .. [3.2, 2.7, 2.7]"), std::string::npos)
        << info.out;
}

TEST_F(CliScene, CeilingAndOtherBuiltins) {
    const std::string room = out("closed.ply");
    ASSERT_EQ(shprt(fmt::format("scene room --ceiling --triangles 3000 -o '{}'", room)).exit_code,
              0);
    EXPECT_EQ(mesh_bounds(load_scene(room)).hi.y, kRoomCeilingTop);
    for (const std::string& name : builtin_scene_names()) {
        if (name == "room") continue;
        const std::string file = out(name + ".ply");
        const RunResult r = shprt(fmt::format("scene {} -o '{}'", name, file));
        ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
        EXPECT_EQ(load_scene(file).triangle_count(), make_builtin(name).triangle_count()) << name;
    }
}

TEST_F(CliScene, ListAndInfoOfBuiltins) {
    const RunResult list = shprt("scene list");
    ASSERT_EQ(list.exit_code, 0);
    for (const std::string& name : builtin_scene_names())
        EXPECT_NE(list.out.find(name), std::string::npos) << list.out;
    const RunResult info = shprt("scene info builtin:sphere");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("642 vertices, 1280 triangles"), std::string::npos) << info.out;
}

TEST_F(CliScene, BadRequestsFailCleanly) {
    expect_failure(shprt(fmt::format("scene info '{}'", out("missing.obj"))),
                   out("missing.obj") + ": no such file");
    expect_failure(shprt("scene info builtin:teapot"), "unknown built-in scene 'teapot'");
    expect_failure(shprt(fmt::format("scene room --triangles 10 -o '{}'", out("small.ply"))),
                   "10 triangles requested");
    expect_failure(shprt(fmt::format("scene plane -o '{}'", out("plane.obj"))), "PLY");
    expect_failure(shprt(fmt::format("scene room -o '{}'", out("no/such/dir/room.ply"))),
                   "cannot write");
    // Argument errors are found while parsing: usage errors, and nothing written.
    expect_usage_error(shprt("scene"), "subcommand is required");
    expect_usage_error(shprt(fmt::format("scene teapot -o '{}'", out("t.ply"))),
                       "unknown command 'teapot'");
    expect_usage_error(shprt(fmt::format("scene sphre -o '{}'", out("t.ply"))),
                       "unknown command 'sphre'; did you mean 'sphere'?");
    expect_usage_error(shprt(fmt::format("scene sphere --triangles 5 -o '{}'", out("s.ply"))),
                       "--triangles");
    expect_usage_error(shprt("scene room"), "--output is required");
    EXPECT_TRUE(out_dir_empty());
}

}  // namespace
}  // namespace shprt
