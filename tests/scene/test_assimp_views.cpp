// Real scenes of Assimp's own corpus (Debian's assimp-testmodels): load_scene must see what
// Assimp sees. Each file is also read with Assimp directly, with aiProcess_Triangulate |
// aiProcess_PreTransformVertices (Assimp applies the node transforms itself and keeps one copy of
// a mesh per instance), and the two views are compared like with like:
//   * vertices: load_scene neither welds nor splits, and copies a mesh per instance, so its count
//     is the sum of Assimp's pre-transformed meshes' vertices;
//   * triangles: load_scene drops degenerate triangles (validate_mesh: a repeated index or zero
//     area in double) and triangulates polygons itself (triangulate_polygon), so its count lies
//     between Assimp's non-degenerate triangles (same test) and all of Assimp's triangles, and the
//     total area is Assimp's to 1e-4 (a non-planar quad cut along its other diagonal has another
//     area: 1.3e-5 of the duck's; one triangle of the duck is about 2.4e-4 of it);
//   * bounds: the axis-aligned box of all vertices, equal to float rounding (the transforms are
//     multiplied in a different order), 1e-5 of the box's diagonal.
// Nothing dropped, nothing left at its local origin. Skips when the corpus is not installed.
#include "shprt/scene/load.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

namespace shprt {
namespace {

const std::string kModels = "/usr/share/assimp/models/";

struct View {
    std::size_t vertices = 0, triangles = 0, all_triangles = 0;
    double area = 0;
    double lo[3], hi[3];
};

View assimp_view(const std::string& path) {
    Assimp::Importer importer;
    const aiScene* scene =
        importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                    aiProcess_ValidateDataStructure);
    if (!scene) ADD_FAILURE() << "Assimp cannot read " << path << ": " << importer.GetErrorString();
    View v;
    std::fill(v.lo, v.lo + 3, std::numeric_limits<double>::infinity());
    std::fill(v.hi, v.hi + 3, -std::numeric_limits<double>::infinity());
    if (!scene) return v;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh& mesh = *scene->mMeshes[m];
        v.vertices += mesh.mNumVertices;
        for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
            const aiVector3D& p = mesh.mVertices[i];
            const double c[3] = {p.x, p.y, p.z};
            for (int k = 0; k < 3; ++k) {
                v.lo[k] = std::min(v.lo[k], c[k]);
                v.hi[k] = std::max(v.hi[k], c[k]);
            }
        }
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            if (face.mNumIndices != 3) continue;  // points and lines: load_scene skips them too
            ++v.all_triangles;
            const unsigned* t = face.mIndices;
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
            // The area test of validate_mesh, in double on the float positions.
            const aiVector3D &a = mesh.mVertices[t[0]], &b = mesh.mVertices[t[1]],
                             &c = mesh.mVertices[t[2]];
            const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
            const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
            const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
            const double n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if (!(n2 > 0.0)) continue;
            ++v.triangles;
            v.area += 0.5 * std::sqrt(n2);
        }
    }
    return v;
}

class AssimpViews : public ::testing::TestWithParam<const char*> {};

TEST_P(AssimpViews, LoadSceneSeesWhatAssimpSees) {
    const std::string path = kModels + GetParam();
    if (!std::filesystem::exists(path))
        GTEST_SKIP() << path << " is missing (scripts/setup installs assimp-testmodels)";
    const View want = assimp_view(path);
    const Mesh mesh = load_scene(path);
    EXPECT_EQ(mesh.vertex_count(), want.vertices) << path;
    EXPECT_GE(mesh.triangle_count(), want.triangles) << path;
    EXPECT_LE(mesh.triangle_count(), want.all_triangles) << path;
    EXPECT_NEAR(mesh_surface_area(mesh), want.area, 1e-4 * want.area) << path;
    ASSERT_GT(want.vertices, 0u);
    const Bounds b = mesh_bounds(mesh);
    const double got_lo[3] = {b.lo.x, b.lo.y, b.lo.z}, got_hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    double diagonal = 0;
    for (int k = 0; k < 3; ++k) diagonal += (want.hi[k] - want.lo[k]) * (want.hi[k] - want.lo[k]);
    const double tolerance = 1e-5 * std::sqrt(diagonal);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(got_lo[k], want.lo[k], tolerance) << path << " axis " << k;
        EXPECT_NEAR(got_hi[k], want.hi[k], tolerance) << path << " axis " << k;
    }
}

INSTANTIATE_TEST_SUITE_P(
    RealScenes, AssimpViews,
    ::testing::Values("glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",    // 80+ nodes
                      "IFC/AC14-FZK-Haus.ifc",                                    // a house
                      "Collada/teapots.DAE", "Collada/teapot_instancenodes.DAE",  // instancing
                      "Collada/duck.dae", "FBX/spider.fbx",
                      "FBX/cubes_with_mirroring_and_pivot.fbx", "3DS/fels.3ds", "3DS/test1.3ds",
                      "OBJ/spider.obj"),
    [](const ::testing::TestParamInfo<const char*>& param) {
        std::string name = param.param;  // "FBX/spider.fbx" -> "FBX_spider"
        name = name.substr(0, name.find_last_of('.'));
        name.erase(0, name.find_last_of('/', name.find_last_of('/') - 1) + 1);
        for (char& c : name)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return name;
    });

}  // namespace
}  // namespace shprt
