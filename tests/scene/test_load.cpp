// Scene loading: PLY vertex order, OBJ/STL/glTF, normals and colours, node transforms, and bad
// files that must give shprt::Error naming the file.
#include "shprt/core/colour.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/log.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/ply.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

// Assimp 5.2.5's PLY importer leaks its vertex array when a file ends early (truncated.ply);
// that is the library's leak, not ours, so LeakSanitizer (SHPRT_SANITIZE builds) ignores it.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

namespace shprt {
namespace {

namespace fs = std::filesystem;

const std::string kData = std::string(SHPRT_TEST_DATA_DIR) + "/scene/";
constexpr float kNormalTol = 1e-6f;
// One step of 8-bit sRGB is at most 1/255 * 12.92^-1 ... in linear terms near white about 0.009.
constexpr float kSrgbByteTol = 0.01f;

class TempDir {
public:
    TempDir() {
        m_path = fs::temp_directory_path() / ("shprt_scene_test_" + std::to_string(::getpid()) +
                                              "_" + std::to_string(s_counter++));
        fs::create_directories(m_path);
    }
    ~TempDir() { fs::remove_all(m_path); }
    std::string file(const std::string& name) const { return (m_path / name).string(); }

private:
    static inline int s_counter = 0;
    fs::path m_path;
};

Vec3f face_normal(const Mesh& m, std::size_t t) {
    const auto& tri = m.triangles[t];
    const Vec3f a = m.positions[tri[0]], b = m.positions[tri[1]], c = m.positions[tri[2]];
    return normalize(cross(b - a, c - a));
}

// Expects loading `path` to throw shprt::Error whose message names the file and contains `what`.
void expect_load_error(const std::string& path, const std::string& what, ErrorCode code) {
    try {
        load_scene(path);
        ADD_FAILURE() << "loading " << path << " did not throw";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(path), std::string::npos) << msg;
        EXPECT_NE(msg.find(what), std::string::npos) << msg;
        EXPECT_EQ(e.code(), code) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
    }
}

TEST(SceneLoad, PlyRoundTripKeepsVertexOrderIndexByIndex) {
    // Deliberately duplicated (0 and 3, 1 and 4) and unused (5, 6) vertices.
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}, {0, 0, 0}, {1, 0, 0}, {7, 7, 7}, {-3, 2, 1}};
    m.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {1, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}};
    m.albedo = {{0.1f, 0.2f, 0.3f}, {0.5f, 0.5f, 0.5f}, {1, 0, 0}, {0, 1, 0},
                {0, 0, 1},          {0.9f, 0.8f, 0.7f}, {0, 0, 0}};
    m.triangles = {{0, 1, 2}, {3, 2, 4}, {4, 2, 3}};
    m.source = "hand-made";
    TempDir dir;
    const std::string path = dir.file("order.ply");
    write_ply(m, path);
    const Mesh r = load_scene(path);
    ASSERT_EQ(r.vertex_count(), m.vertex_count());
    ASSERT_EQ(r.triangle_count(), m.triangle_count());
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        EXPECT_EQ(r.positions[i], m.positions[i]) << "vertex " << i;  // bit for bit
        EXPECT_EQ(r.normals[i], m.normals[i]) << "vertex " << i;
        EXPECT_EQ(r.source_vertex[i], i);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.albedo[i][c], m.albedo[i][c], kSrgbByteTol);
    }
    for (std::size_t t = 0; t < m.triangle_count(); ++t) EXPECT_EQ(r.triangles[t], m.triangles[t]);
    EXPECT_EQ(r.source, path);
}

TEST(SceneLoad, PlyWithGivenColoursAndACommentReadsBack) {
    // write_ply as `shprt shade` uses it: colours given per vertex (written as given, not from
    // the albedo), an extra comment line, uint indices.
    Mesh m = make_builtin("sphere");
    std::vector<std::array<std::uint8_t, 3>> colours(m.vertex_count());
    for (std::size_t v = 0; v < colours.size(); ++v)
        colours[v] = {std::uint8_t(v), std::uint8_t(255 - v % 256), std::uint8_t(v * 7)};
    TempDir dir;
    const std::string path = dir.file("coloured.ply");
    write_ply(m, path, &colours, "what the colours mean\non one line");
    const std::string bytes = read_file(path);
    const std::string header = bytes.substr(0, bytes.find("end_header\n"));
    EXPECT_NE(header.find("\ncomment what the colours mean?on one line\n"), std::string::npos)
        << header;
    EXPECT_NE(header.find("\nproperty list uchar uint vertex_indices\n"), std::string::npos)
        << header;
    const Mesh r = load_scene(path);
    ASSERT_EQ(r.vertex_count(), m.vertex_count());
    for (std::size_t v = 0; v < colours.size(); ++v)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(r.albedo[v][c], srgb_to_linear(colours[v][c] / 255.0f), 1e-6f)
                << v << "," << c;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) EXPECT_EQ(r.triangles[t], m.triangles[t]);
    colours.pop_back();
    EXPECT_THROW(write_ply(m, dir.file("short.ply"), &colours), Error);
}

TEST(SceneLoad, HandWrittenAsciiPlyKeepsOrderAndDecodesSrgbColours) {
    const std::string path = kData + "order.ply";
    const Mesh m = load_scene(path);
    ASSERT_EQ(m.vertex_count(), 7u);  // vertex 1 is unused and still there
    EXPECT_EQ(m.positions[1], (Vec3f{9, 9, 9}));
    EXPECT_EQ(m.positions[5], (Vec3f{1, 0, 0}));
    EXPECT_EQ(m.positions[2], (Vec3f{1, 0, 0}));  // same position, separate vertex
    ASSERT_EQ(m.triangle_count(), 4u);            // the quad became two triangles
    EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{0, 2, 3}));
    EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{2, 6, 0}));
    EXPECT_EQ(m.triangles[2], (std::array<std::uint32_t, 3>{0, 5, 4}));
    EXPECT_EQ(m.triangles[3], (std::array<std::uint32_t, 3>{0, 4, 6}));
    for (std::size_t i = 0; i < m.vertex_count(); ++i) EXPECT_EQ(m.source_vertex[i], i);
    // 8-bit colours are sRGB: 128 decodes to 0.2158, not 0.502.
    EXPECT_NEAR(m.albedo[3].x, srgb_to_linear(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(m.albedo[3].x, 0.2158f, 1e-3f);
    EXPECT_EQ(m.albedo[0], (Vec3f{1, 0, 0}));
    // Normals were absent: computed per index, so vertex 5 (quad only) faces +Z while vertex 2
    // at the same position also belongs to a triangle facing +Y.
    for (const Vec3f& n : m.normals) EXPECT_NEAR(length(n), 1.0f, kNormalTol);
    EXPECT_NEAR(m.normals[5].z, 1.0f, kNormalTol);
    EXPECT_GT(m.normals[2].y, 0.1f);
    EXPECT_GT(m.normals[2].z, 0.1f);
    EXPECT_EQ(m.normals[1], (Vec3f{0, 1, 0}));  // unused vertex: +Y by convention
}

TEST(SceneLoad, ObjWithoutNormalsGetsFaceNormalsAndDefaultAlbedo) {
    const Mesh m = load_scene(kData + "square_no_normals.obj");
    ASSERT_EQ(m.triangle_count(), 2u);
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const Vec3f fn = face_normal(m, t);
        EXPECT_NEAR(fn.z, 1.0f, kNormalTol);
        for (std::uint32_t v : m.triangles[t]) {
            EXPECT_NEAR(m.normals[v].x, 0.0f, kNormalTol);
            EXPECT_NEAR(m.normals[v].y, 0.0f, kNormalTol);
            EXPECT_NEAR(m.normals[v].z, 1.0f, kNormalTol);
        }
    }
    for (const Vec3f& a : m.albedo)
        EXPECT_EQ(a, (Vec3f{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo}));
    for (const Vec3f& p : m.positions) EXPECT_EQ(p.z, 0.5f);
}

TEST(SceneLoad, ObjMaterialColourAndFileNormals) {
    const Mesh m = load_scene(kData + "red_triangle.obj");
    ASSERT_EQ(m.triangle_count(), 1u);
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        EXPECT_EQ(m.albedo[v], (Vec3f{0.7f, 0.1f, 0.05f}));
        EXPECT_EQ(m.normals[v], (Vec3f{0, 1, 0}));
    }
    EXPECT_NEAR(face_normal(m, 0).y, 1.0f, kNormalTol);
}

TEST(SceneLoad, StlTetrahedronHasOutwardNormals) {
    const Mesh m = load_scene(kData + "tetra.stl");
    ASSERT_EQ(m.triangle_count(), 4u);
    const Vec3f centroid{0.25f, 0.25f, 0.25f};
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const Vec3f fn = face_normal(m, t);
        const Vec3f p = m.positions[m.triangles[t][0]];
        EXPECT_GT(dot(fn, p - centroid), 0.0f) << "triangle " << t << " faces inward";
        for (std::uint32_t v : m.triangles[t]) {
            EXPECT_NEAR(length(m.normals[v]), 1.0f, kNormalTol);
            EXPECT_GT(dot(m.normals[v], fn), 0.99f);
        }
    }
}

TEST(SceneLoad, GltfNodeTransformsInstancesAndBaseColour) {
    const Mesh m = load_scene(kData + "instanced.gltf");
    // One mesh, two instances: scaled by 2 under a node lifted by 2, and mirrored in z at x = 5.
    ASSERT_EQ(m.vertex_count(), 6u);
    ASSERT_EQ(m.triangle_count(), 2u);
    const Vec3f expected[6] = {{0, 2, 0}, {2, 2, 0}, {0, 2, -2}, {5, 0, 0}, {6, 0, 0}, {5, 0, 1}};
    for (int v = 0; v < 6; ++v) {
        EXPECT_EQ(m.positions[v], expected[v]) << "vertex " << v;
        EXPECT_EQ(m.source_vertex[v], static_cast<std::uint32_t>(v % 3));
        EXPECT_NEAR(m.normals[v].y, 1.0f, kNormalTol);
        EXPECT_EQ(m.albedo[v], (Vec3f{0.2f, 0.4f, 0.6f}));
    }
    // The mirrored instance keeps counter-clockwise = front: winding agrees with the normals.
    for (std::size_t t = 0; t < 2; ++t) EXPECT_NEAR(face_normal(m, t).y, 1.0f, kNormalTol);
}

TEST(SceneLoad, MaterialsGiveGlossyBrdfsPerVertex) {
    // OBJ: Ns is a Phong exponent (clamped to check_brdf's range), Ks its specular colour; a
    // material without Ns, none.
    const Mesh obj = load_scene(kData + "glossy_materials.obj");
    ASSERT_EQ(obj.vertex_count(), 9u);
    ASSERT_EQ(obj.brdf_index.size(), 9u);
    ASSERT_EQ(obj.brdfs.size(), 2u);
    EXPECT_EQ(obj.brdfs[0], (Brdf{BrdfModel::phong, 64, Vec3f{1, 1, 1}}));
    EXPECT_EQ(obj.brdfs[1], (Brdf{BrdfModel::phong, kMaxBrdfExponent, Vec3f{0.9f, 0.6f, 0.2f}}));
    for (int v = 0; v < 9; ++v) {
        const std::uint32_t expected = v < 3 ? 0u : v < 6 ? Mesh::kNoBrdf : 1u;
        EXPECT_EQ(obj.brdf_index[v], expected) << "vertex " << v;
    }
    EXPECT_EQ(describe_brdfs(obj),
              "phong:64 (3 vertices), phong:10000:0.9,0.6,0.2 (3 vertices), none (3 vertices)");
    // glTF: the metallic-roughness material's roughness, as GGX; both instances share it. A
    // dielectric (metallic 0): a white specular colour.
    const Mesh gltf = load_scene(kData + "rough_instanced.gltf");
    ASSERT_EQ(gltf.brdfs.size(), 1u);
    EXPECT_EQ(gltf.brdfs[0].model, BrdfModel::ggx);
    EXPECT_NEAR(gltf.brdfs[0].parameter, 0.4, 1e-6);
    EXPECT_EQ(gltf.brdfs[0].specular, (Vec3f{1, 1, 1}));
    // Half metal: the specular colour is halfway from white to the base colour (0.2, 0.4, 0.6).
    {
        std::ifstream in(kData + "rough_instanced.gltf");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::string dielectric = "\"metallicFactor\": 0.0";
        ASSERT_NE(text.find(dielectric), std::string::npos);
        text.replace(text.find(dielectric), dielectric.size(), "\"metallicFactor\": 0.5");
        const TempDir dir;
        std::ofstream(dir.file("half_metal.gltf")) << text;
        const Mesh metal = load_scene(dir.file("half_metal.gltf"));
        ASSERT_EQ(metal.brdfs.size(), 1u);
        const Vec3f c = metal.brdfs[0].specular;
        EXPECT_NEAR(c.x, 0.6f, 1e-6f);
        EXPECT_NEAR(c.y, 0.7f, 1e-6f);
        EXPECT_NEAR(c.z, 0.8f, 1e-6f);
    }
    EXPECT_EQ(gltf.brdf_index, std::vector<std::uint32_t>(6, 0u));
    // No material gives one: both empty (a PLY, and Assimp's placeholder material of an OBJ
    // without a library).
    EXPECT_TRUE(load_scene(kData + "square_no_normals.obj").brdf_index.empty());
    EXPECT_TRUE(load_scene(kData + "order.ply").brdfs.empty());
}

TEST(SceneLoad, ColladaZUpBecomesYUp) {
    // The document's up axis (+Z) maps to +Y through the root node's transform: (x, y, z) in the
    // file lands at (x, z, -y).
    const Mesh m = load_scene(kData + "zup_triangle.dae");
    ASSERT_EQ(m.vertex_count(), 3u);
    EXPECT_EQ(m.positions[0], (Vec3f{0, 1, 0}));
    EXPECT_EQ(m.positions[1], (Vec3f{1, 1, 0}));
    EXPECT_EQ(m.positions[2], (Vec3f{0, 1, -1}));
    for (const Vec3f& n : m.normals) {
        EXPECT_NEAR(n.y, 1.0f, kNormalTol);
    }
    EXPECT_NEAR(face_normal(m, 0).y, 1.0f, kNormalTol);
}

TEST(SceneLoad, BuiltinSpecs) {
    const Mesh m = load_scene("builtin:plane");
    EXPECT_EQ(m.source, "builtin:plane");
    EXPECT_EQ(m.triangle_count(), 512u);
    EXPECT_TRUE(is_builtin_spec("builtin:room"));
    EXPECT_FALSE(is_builtin_spec("room.ply"));
    try {
        load_scene("builtin:teapot");
        ADD_FAILURE() << "no error for an unknown built-in";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        EXPECT_NE(std::string(e.what()).find("teapot"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("box_on_plane"), std::string::npos);
    }
}

TEST(SceneLoad, BadScenesNameTheFileAndTheProblem) {
    expect_load_error(kData + "does_not_exist.obj", "no such file", ErrorCode::io);
    expect_load_error(kData, "directory", ErrorCode::io);
    expect_load_error(kData + "unsupported.foo", "unsupported format", ErrorCode::unsupported);
    expect_load_error(kData + "out_of_range.ply", "out of range", ErrorCode::format);
    expect_load_error(kData + "no_faces.ply", "empty mesh", ErrorCode::format);
    expect_load_error(kData + "no_faces.obj", "empty mesh", ErrorCode::format);
    expect_load_error(kData + "nan.ply", "non-finite", ErrorCode::format);
    expect_load_error(kData + "inf.obj", "non-finite", ErrorCode::format);
}

TEST(SceneLoad, CorruptFilesThrowAndNeverCrash) {
    // cut_header.ply ends inside its header: Assimp alone would never return on it; nor on a
    // header line with more after end_header. Huge element counts must not be allocated.
    expect_load_error(kData + "cut_header.ply", "no end_header", ErrorCode::format);
    expect_load_error(kData + "truncated.ply", "declares more data than", ErrorCode::format);
    expect_load_error(kData + "garbage.ply", "not a PLY file", ErrorCode::format);
    TempDir dir;
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\n";
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const std::string faces = "element face 1\nproperty list uchar int vertex_indices\n";
    const std::pair<std::string, std::string> bad_headers[] = {
        {header + faces + "end_header\x9d" + body, "line 9: unexpected 'end_header?0 0 0'"},
        {header + "element face 4294967295\nproperty list uchar int vertex_indices\nend_header\n" +
             body,
         "declares more data than"},
        {header + "element 999 1\n" + faces + "end_header\n" + body, "bad element line"},
        {header + "property flaot w\n" + faces + "end_header\n" + body, "bad property"},
        {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n3 0 1 2\n",
         "no vertex element"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" + faces +
             "end_header\n" + body,
         "lacks x, y or z"},
        {header + faces + "end_headerX\nend_header\n" + body, "unexpected 'end_headerX'"},
    };
    int k = 0;
    for (const auto& [text, what] : bad_headers) {
        const std::string path = dir.file("bad_header_" + std::to_string(k++) + ".ply");
        std::ofstream(path, std::ios::binary) << text;
        expect_load_error(path, what, ErrorCode::format);
    }
    // The same file with a clean header loads.
    const std::string good = dir.file("good_header.ply");
    std::ofstream(good, std::ios::binary) << header + faces + "end_header\n" + body;
    EXPECT_EQ(load_scene(good).triangle_count(), 1u);
    for (const char* name : {"garbage.glb", "garbage.ply", "truncated.ply"}) {
        const std::string path = kData + name;
        try {
            load_scene(path);
            ADD_FAILURE() << path << " loaded";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        }
    }
    const std::string empty = dir.file("empty.obj");
    std::ofstream(empty).close();
    expect_load_error(empty, "empty file", ErrorCode::format);
    // zup_triangle.dae with one attribute name mangled (count -> c2unt), found by fuzzing:
    // Assimp 5.2.5's Collada reader dereferences the missing attribute and segfaults. It runs in
    // a child process, so this is an error, and this test process lives on.
    expect_load_error(kData + "missing_count.dae", "the importer crashed reading this file",
                      ErrorCode::format);
    EXPECT_EQ(load_scene(kData + "zup_triangle.dae").triangle_count(), 1u) << "and still loads";
}

TEST(SceneLoad, FloatPlyColoursAreLinear) {
    TempDir dir;
    const std::string path = dir.file("float_colours.ply");
    std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nproperty float red\n"
                           "property float green\nproperty float blue\nelement face 1\n"
                           "property list uchar int vertex_indices\nend_header\n"
                           "0 0 0 0.5 0.25 0.125\n1 0 0 0 0 0\n0 1 0 1 1 1\n3 0 1 2\n";
    const Mesh m = load_scene(path);
    EXPECT_EQ(m.albedo[0], (Vec3f{0.5f, 0.25f, 0.125f}));
    EXPECT_EQ(m.albedo[2], (Vec3f{1, 1, 1}));
}

TEST(SceneLoad, NanInBinaryPlyIsRejected) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, std::numeric_limits<float>::quiet_NaN(), 0}};
    m.triangles = {{0, 1, 2}};
    TempDir dir;
    const std::string path = dir.file("nan_binary.ply");
    write_ply(m, path);
    expect_load_error(path, "vertex 2 has a non-finite coordinate", ErrorCode::format);
}

// load_scene(path), with the warnings it logged added to `warnings`.
Mesh load_with_warnings(const std::string& path, std::vector<std::string>& warnings) {
    set_log_sink([&](LogLevel level, std::string_view msg) {
        if (level == LogLevel::warn) warnings.emplace_back(msg);
    });
    try {
        Mesh m = load_scene(path);
        set_log_sink(nullptr);
        return m;
    } catch (...) {
        set_log_sink(nullptr);
        throw;
    }
}

TEST(SceneLoad, DegenerateTrianglesAreDroppedWithAWarning) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}, {2, 0, 0}};
    m.triangles = {{0, 1, 2}, {0, 1, 3}, {2, 2, 1}};  // collinear, repeated index
    TempDir dir;
    const std::string path = dir.file("degenerate.ply");
    write_ply(m, path);
    std::vector<std::string> warnings;
    const Mesh r = load_with_warnings(path, warnings);
    EXPECT_EQ(r.triangle_count(), 1u);
    EXPECT_EQ(r.vertex_count(), 4u);
    // No colours in the file: the default grey, not Assimp's white placeholder material.
    for (const Vec3f& a : r.albedo)
        EXPECT_EQ(a, (Vec3f{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo}));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("dropped 2 degenerate triangles"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find(path), std::string::npos);
}

// A header line that is no PLY keyword is read as a comment, with one warning, as Assimp reads
// it: Blender 2.47 wrote "Created by Blender3D 247 ..." without "comment", and Assimp's own
// corpus holds such a file (PLY/Wuson.ply). A line that begins like end_header stays an error
// (CorruptFilesThrowAndNeverCrash): Assimp never returns on one.
TEST(SceneLoad, PlyHeaderLinesThatAreNoKeywordAreReadAsComments) {
    TempDir dir;
    const std::string path = dir.file("free_text.ply");
    std::ofstream(path, std::ios::binary)
        << "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: \n"
           "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "banana\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
           "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    std::vector<std::string> warnings;
    const Mesh m = load_with_warnings(path, warnings);
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.vertex_count(), 3u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(path + ": PLY header line 3: 'Created by Blender3D"),
              std::string::npos)
        << warnings[0];
    EXPECT_NE(warnings[0].find("read as a comment (2 such lines)"), std::string::npos)
        << warnings[0];

    const std::string wuson = "/usr/share/assimp/models/PLY/Wuson.ply";
    if (!std::filesystem::exists(wuson)) GTEST_SKIP() << wuson << " (assimp-testmodels) missing";
    EXPECT_EQ(load_scene(wuson).triangle_count(), 3732u);
}

}  // namespace
}  // namespace shprt
