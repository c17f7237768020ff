// Built-in scenes, usable as "builtin:NAME" wherever a scene file is accepted. All are in metres,
// +Y up, with albedo kDefaultAlbedo (0.8 grey) except the rooms, and exact unit normals.
//
//   plane         the square x, z in [-1, 1] at y = 0 facing +Y, a 16 x 16 grid of cells
//                 (289 vertices, 512 triangles).
//   box_on_plane  the square x, z in [-2, 2] at y = 0 (32 x 32 cells of 0.125 m) and on it the box
//                 [-0.5, 0.5] x [0, 1] x [-0.5, 0.5] without its bottom face (4 x 4 cells per
//                 face, split vertices at the edges, flat normals).
//   sphere        the unit sphere at the origin: an icosphere of level 3 (642 vertices, 1280
//                 triangles), outward normals equal to the positions.
//   corner        an inner 90-degree corner: the floor x in [0, 2], z in [-2, 2] at y = 0 facing
//                 +Y, and the wall x = 0, y in [0, 2], z in [-2, 2] facing +X, each a grid of
//                 0.1 m cells (20 x 40). The wall is one-sided: nothing but it occludes a floor
//                 vertex, and corner_occlusion() gives the exact occluded fractions. Probe
//                 vertex: the floor vertex at kCornerProbe = (0.1, 0, 0), one cell from the wall.
//   room          generate_room() with default options (about 20 000 triangles, open top).
//   quad_box      low poly, with UVs: the floor x, z in [-2, 2] at y = 0 as two triangles, and the
//                 box [-0.5, 0.5] x [0, 1] x [-0.5, 0.5] without its bottom, each face two
//                 triangles (24 vertices, 12 triangles); one UV atlas without overlaps (floor in
//                 [0, 0.7]^2, the faces in 0.2-wide tiles). Per-vertex transfer shows no shadow
//                 on its floor; per-texel transfer does (docs/texels.md).
//   gloss_spheres four coloured spheres of radius 0.65 (icospheres of level 3) on a grey floor
//                 x in [-3.5, 3.5], z in [-1.75, 1.75]; each sphere's material gives a glossy
//                 BRDF (Mesh::brdfs: phong:2, ggx:0.8, blinn:32, ggx:0.5, left to right), the
//                 floor none (docs/glossy.md, "Per-material BRDFs").
//   leaky_room    generate_leaky_room() with default options (708 triangles): a room built like
//                 real assets, its walls, floor slabs and furniture overlapping, interpenetrating
//                 and reaching below the floor, for tests of values read at ray hits.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"

#include <string>
#include <vector>

namespace shprt {

// The names make_builtin accepts, in a fixed order.
std::vector<std::string> builtin_scene_names();
// One line saying what the built-in scene `name` is (`shprt scene list`).
const char* builtin_scene_summary(const std::string& name);

// Builds a built-in scene by name (without the "builtin:" prefix); Mesh::source is
// "builtin:NAME". Throws Error(invalid_argument) listing the valid names for an unknown one.
Mesh make_builtin(const std::string& name);

// How much of the upper hemisphere the wall of builtin:corner hides from the floor point
// (x, 0, z), x > 0, computed analytically (the wall is the rectangle {0} x [0, 2] x [-2, 2]):
//   solid_angle: the wall's solid angle / 2 pi (the occluded fraction of uniformly distributed
//                upper-hemisphere directions; Van Oosterom and Strackee 1983);
//   cosine:      the point-to-rectangle form factor, (1/pi) * integral over the wall of
//                cos(theta) d(omega) with theta from +Y (the occluded fraction of the unshadowed
//                irradiance under a constant sky; Lambert's polygon formula).
// Both tend to 1/2 as x -> 0 with the wall infinitely large.
struct CornerOcclusion {
    double solid_angle;
    double cosine;
};
CornerOcclusion corner_occlusion(double x, double z);

constexpr Vec3f kCornerProbe{0.1f, 0.0f, 0.0f};

}  // namespace shprt
