// Small built-in scenes for tests, and the exact occlusion of the inner corner: the solid angle
// of a triangle by A. van Oosterom and J. Strackee, "The solid angle of a plane triangle" (IEEE
// Trans. Biomed. Eng. 1983); the cosine-weighted integral over a polygon by Lambert's formula
// (the vector-irradiance contour integral, e.g. Arvo, "Applications of irradiance tensors", 1995).
#include "shprt/scene/builtin.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/leaky_room.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/room.hpp"

#include <array>
#include <cmath>

namespace shprt {
namespace {

constexpr Vec3f kGrey{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo};
constexpr double kCornerSize = 2.0;
constexpr double kCornerCell = 0.1;

Mesh make_plane() {
    MeshBuilder b;
    b.add_rect(Axis::y, 0.0, +1, {-1, 1, -1, 1}, 0.125, kGrey);
    return b.take_mesh("builtin:plane");
}

Mesh make_box_on_plane() {
    MeshBuilder b;
    b.add_rect(Axis::y, 0.0, +1, {-2, 2, -2, 2}, 0.125, kGrey);
    b.add_box({-0.5, 0.0, -0.5}, {0.5, 1.0, 0.5}, 0.25, kGrey, kBoxNoBottom);
    return b.take_mesh("builtin:box_on_plane");
}

Mesh make_sphere() {
    MeshBuilder b;
    b.add_icosphere({0, 0, 0}, 1.0, 3, kGrey);
    return b.take_mesh("builtin:sphere");
}

// Four spheres on a floor, one glossy BRDF each (the floor has none): what per-material BRDFs
// look like (docs/glossy.md). The second is a rough metal: gold's specular colour.
Mesh make_gloss_spheres() {
    MeshBuilder b;
    b.add_rect(Axis::y, 0.0, +1, {-1.75, 1.75, -3.5, 3.5}, 0.125, kGrey);  // (a, b) = (z, x)
    const Brdf brdfs[] = {{BrdfModel::phong, 2},
                          {BrdfModel::ggx, 0.8, Vec3f{1.0f, 0.71f, 0.29f}},
                          {BrdfModel::blinn_phong, 32},
                          {BrdfModel::ggx, 0.5}};
    const Vec3f colours[] = {
        {0.8f, 0.25f, 0.2f}, {0.85f, 0.6f, 0.15f}, {0.25f, 0.6f, 0.3f}, {0.2f, 0.35f, 0.8f}};
    std::vector<std::size_t> first;  // each sphere's first vertex
    for (int i = 0; i < 4; ++i) {
        first.push_back(b.vertex_count());
        b.add_icosphere({-2.4 + 1.6 * i, 0.65, 0}, 0.65, 3, colours[i]);
    }
    Mesh mesh = b.take_mesh("builtin:gloss_spheres");
    mesh.brdfs.assign(std::begin(brdfs), std::end(brdfs));
    mesh.brdf_index.assign(mesh.vertex_count(), Mesh::kNoBrdf);
    first.push_back(mesh.vertex_count());
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t v = first[i]; v < first[i + 1]; ++v) mesh.brdf_index[v] = std::uint32_t(i);
    return mesh;
}

Mesh make_corner() {
    MeshBuilder b;
    const double s = kCornerSize;
    b.add_rect(Axis::y, 0.0, +1, {-s, s, 0, s}, kCornerCell, kGrey);  // (a, b) = (z, x)
    b.add_rect(Axis::x, 0.0, +1, {0, s, -s, s}, kCornerCell, kGrey);  // (a, b) = (y, z)
    return b.take_mesh("builtin:corner");
}

// Solid angle of the triangle (a, b, c) seen from the origin.
double triangle_solid_angle(Vec3d a, Vec3d b, Vec3d c) {
    const double la = length(a), lb = length(b), lc = length(c);
    const double num = std::abs(dot(a, cross(b, c)));
    const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    return 2.0 * std::atan2(num, den);
}

// The low-poly asset per-vertex transfer cannot shadow: a two-triangle floor with a box on it,
// every face one quad of two triangles, laid out in one UV atlas without overlaps (the floor in
// [0, 0.7]², the box's five faces in 0.2-wide tiles along the top and right, 0.05 apart).
Mesh make_quad_box() {
    Mesh m;
    const auto quad = [&m](Vec3f o, Vec3f e1, Vec3f e2, float u0, float v0, float size) {
        const Vec3f n = normalize(cross(e1, e2));
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        const Vec3f corners[4] = {o, o + e1, o + e1 + e2, o + e2};
        const float st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int i = 0; i < 4; ++i) {
            m.positions.push_back(corners[i]);
            m.normals.push_back(n);
            m.albedo.push_back(kGrey);
            m.uvs.push_back({u0 + st[i][0] * size, v0 + st[i][1] * size});
        }
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
    };
    quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 0.0f, 0.0f, 0.7f);          // floor, +Y
    quad({-0.5f, 1, -0.5f}, {0, 0, 1}, {1, 0, 0}, 0.75f, 0.0f, 0.2f);   // top, +Y
    quad({0.5f, 0, -0.5f}, {0, 1, 0}, {0, 0, 1}, 0.75f, 0.25f, 0.2f);   // +X
    quad({-0.5f, 0, -0.5f}, {0, 0, 1}, {0, 1, 0}, 0.75f, 0.5f, 0.2f);   // -X
    quad({-0.5f, 0, 0.5f}, {1, 0, 0}, {0, 1, 0}, 0.75f, 0.75f, 0.2f);   // +Z
    quad({-0.5f, 0, -0.5f}, {0, 1, 0}, {1, 0, 0}, 0.25f, 0.75f, 0.2f);  // -Z
    m.source = "builtin:quad_box";
    return m;
}

}  // namespace

std::vector<std::string> builtin_scene_names() {
    return {"plane", "box_on_plane", "sphere",        "corner",
            "room",  "quad_box",     "gloss_spheres", "leaky_room"};
}

const char* builtin_scene_summary(const std::string& name) {
    if (name == "plane") return "A tessellated 2 m square at y = 0 facing +Y";
    if (name == "box_on_plane") return "A unit box resting on a 4 m square";
    if (name == "sphere") return "The unit sphere (icosphere, 1280 triangles)";
    if (name == "corner") return "An inner 90-degree corner: floor y = 0 and wall x = 0";
    if (name == "room") return "The paper's furnished room (open top; --ceiling closes it)";
    if (name == "quad_box") return "Low poly with UVs: a two-triangle floor and a box on it";
    if (name == "gloss_spheres") return "Four spheres on a floor, each with its own glossy BRDF";
    if (name == "leaky_room")
        return "A room built like real assets: overlapping panels, parts through the floor";
    return "A built-in scene";
}

Mesh make_builtin(const std::string& name) {
    if (name == "plane") return make_plane();
    if (name == "box_on_plane") return make_box_on_plane();
    if (name == "sphere") return make_sphere();
    if (name == "corner") return make_corner();
    if (name == "room") return generate_room(RoomOptions{});
    if (name == "quad_box") return make_quad_box();
    if (name == "gloss_spheres") return make_gloss_spheres();
    if (name == "leaky_room") return generate_leaky_room(LeakyRoomOptions{});
    std::string names;
    for (const auto& n : builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
    fail(ErrorCode::invalid_argument, "unknown built-in scene '{}' (choose from: {})", name, names);
}

CornerOcclusion corner_occlusion(double x, double z) {
    SHPRT_CHECK(x > 0.0 && std::isfinite(x) && std::isfinite(z), invalid_argument,
                "corner_occlusion: the point must lie in front of the wall (x = {} > 0)", x);
    const double s = kCornerSize;
    const Vec3d p{x, 0.0, z};
    const std::array<Vec3d, 4> q = {Vec3d{0, 0, -s} - p, Vec3d{0, s, -s} - p, Vec3d{0, s, s} - p,
                                    Vec3d{0, 0, s} - p};
    const double omega =
        triangle_solid_angle(q[0], q[1], q[2]) + triangle_solid_angle(q[0], q[2], q[3]);
    // Lambert: integral of n.w over the polygon = 1/2 sum_i angle(q_i, q_i+1) n.unit(q_i x q_i+1),
    // up to the sign set by the winding.
    double lambert = 0.0;
    const Vec3d n{0, 1, 0};
    for (std::size_t i = 0; i < q.size(); ++i) {
        const Vec3d a = q[i], b = q[(i + 1) % q.size()];
        const Vec3d c = cross(a, b);
        const double cl = length(c);
        if (cl == 0.0) continue;
        lambert += std::atan2(cl, dot(a, b)) * dot(n, c) / cl;
    }
    lambert = 0.5 * std::abs(lambert);
    return {omega / (2.0 * kPi), lambert / kPi};
}

}  // namespace shprt
