// load_scene keeps a UV set through Assimp (and the forked importer's pipe): an OBJ's `vt`
// coordinates arrive per vertex as Mesh::uvs; a set the file does not have gives none; a set
// outside Assimp's range is an error.
#include "shprt/core/error.hpp"
#include "shprt/scene/load.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

namespace shprt {
namespace {

TEST(LoadUvs, ObjTextureCoordinatesArrivePerVertex) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("shprt_uvs_" + std::to_string(::getpid()) + ".obj"))
                                 .string();
    {
        std::ofstream out(path);
        out << "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
               "vt 0 0\nvt 0.5 0\nvt 0.5 0.25\nvt 0 0.25\n"
               "vn 0 1 0\n"
               "f 1/1/1 3/3/1 2/2/1\nf 1/1/1 4/4/1 3/3/1\n";
    }
    const Mesh mesh = load_scene(path);
    ASSERT_EQ(mesh.uvs.size(), mesh.vertex_count());
    // Each vertex's UV is its position's (x/2, z/4), whatever order the importer chose.
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        EXPECT_FLOAT_EQ(mesh.uvs[v][0], mesh.positions[v].x * 0.5f) << v;
        EXPECT_FLOAT_EQ(mesh.uvs[v][1], mesh.positions[v].z * 0.25f) << v;
    }
    EXPECT_TRUE(load_scene(path, 1).uvs.empty());  // no second set
    EXPECT_THROW(load_scene(path, 8), Error);
    std::filesystem::remove(path);
    EXPECT_TRUE(load_scene("builtin:plane").uvs.empty());
    EXPECT_EQ(load_scene("builtin:quad_box").uvs.size(), 24u);
}

}  // namespace
}  // namespace shprt
