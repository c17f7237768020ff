// A pinhole camera and the matrices OpenGL needs, shared by `shprt render`, `shprt shade` (its
// default eye), the viewer and the tests (which project vertices with exactly the matrices the
// renderer uses).
//
// Conventions: world space is right-handed, +Y up. The camera looks from `eye` toward `target`;
// `fov_y_deg` is the full vertical field of view. Matrices are OpenGL's: column-major float[16],
// clip space z in [−w, w], pixel row 0 at the top of an image (the renderer flips on read-back).
#pragma once

#include "shprt/core/options.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/scene/mesh_ops.hpp"  // Bounds, mesh_bounds

#include <optional>
#include <string>
#include <vector>

namespace shprt {

struct Camera {
    Vec3f eye{0, 0, 5};
    Vec3f target{0, 0, 0};
    Vec3f up{0, 1, 0};
    float fov_y_deg = 60.0f;   // full vertical angle, degrees, in (0, 180)
    float near_plane = 0.01f;  // distances along the view axis, 0 < near < far
    float far_plane = 100.0f;
};

// Column-major 4×4 matrix (m[col * 4 + row]), as glUniformMatrix4fv(..., GL_FALSE, m) expects.
struct Mat4f {
    float m[16];
};

Mat4f operator*(const Mat4f& a, const Mat4f& b);

// World → eye space (gluLookAt). Throws Error(invalid_argument) if eye == target or `up` is
// parallel to the view direction.
Mat4f view_matrix(const Camera& camera);
// Eye → clip space (gluPerspective) for width/height = `aspect`.
Mat4f projection_matrix(const Camera& camera, float aspect);
Mat4f view_projection_matrix(const Camera& camera, float aspect);
// The inverse of a 4×4 matrix, by cofactors in double (camera matrices are well conditioned).
Mat4f inverse(const Mat4f& a);

// The camera `shprt render` uses when none is given. For an enclosure (a room: geometry near all
// four vertical sides of the bounds facing inward) the eye sits inside near a raised corner and
// looks slightly down across the room so its interior is visible; for any other scene it looks at
// the bounding sphere from a raised diagonal direction, at a distance that fits the sphere in the
// vertical and horizontal field of view for `aspect`. Near and far planes enclose the bounds.
Camera default_camera(const Mesh& mesh, float aspect);

// Sets near and far so that the bounds lie between them, with near ≥ far / 1000 (depth
// precision; geometry closer to the eye than that is clipped).
void fit_clip_planes(Camera& camera, const Bounds& bounds);

// The camera at `eye` looking at `target` with vertical field of view `fov_y_deg`: up is +Y, or
// −Z when the view is (within 1e-4 rad) straight up or down, where +Y would be parallel to it;
// near and far fitted to `bounds` (fit_clip_planes). The one way a camera is built from an eye and
// a target: `--camera` (shprt render, shprt view) and the viewer's orbit/fly controller.
// Throws Error(invalid_argument) if eye == target.
Camera look_at_camera(Vec3f eye, Vec3f target, float fov_y_deg, const Bounds& bounds);

// Parses "EX,EY,EZ,TX,TY,TZ" (six finite numbers, core/parse.hpp) into eye and target; throws
// Error(invalid_argument) naming `text`, also when a number is beyond float's range (1e39), when
// eye and target coincide, or when they are so far apart that target - eye overflows float.
void parse_camera(const std::string& text, Camera& camera);
// Parses "X,Y,Z" (three finite numbers within float's range, core/parse.hpp); throws
// Error(invalid_argument) naming `what` and `text`.
Vec3f parse_vec3(const std::string& text, const std::string& what);
// Parses "WxH" (both in [1, 16384]); throws Error(invalid_argument).
void parse_size(const std::string& text, int& width, int& height);

// The camera a front end asks for (`--camera`, `--fov` of shprt render and view): an eye and a
// target "EX,EY,EZ,TX,TY,TZ" (parse_camera), or empty for the default camera; a vertical field of
// view in degrees, or none for the camera's own.
struct CameraChoice {
    std::string camera;
    std::optional<double> fov;
};
// Its rows (core/options.hpp), in the command line's help order.
const std::vector<OptionRow<CameraChoice>>& camera_option_table();
// Checks the choice without a scene (one-line Error(invalid_argument) naming --camera or --fov),
// so that a bad option fails before a file is read.
void check(const CameraChoice& choice);
// The camera of `choice` for `mesh` seen at `aspect`: default_camera(mesh, aspect) without an eye
// and target, else look_at_camera of them with clip planes fitted to the mesh's bounds; the
// field of view, if given, overrides. A camera without a frame is a one-line Error naming
// --camera, or (the default camera of a scene whose positions are too large for single
// precision) Error(format) naming `input`, the file the mesh came from.
Camera camera_from(const CameraChoice& choice, const Mesh& mesh, float aspect,
                   const std::string& input);

// Where world point p lands in a width×height image rendered with `camera`: x right and y down
// in pixels (pixel (i, j) covers [i, i+1) × [j, j+1), so its centre is (i + 0.5, j + 0.5)), and
// the window depth in [0, 1]. Returns false if p is behind the eye or outside the frustum.
bool project_to_pixel(const Camera& camera, int width, int height, Vec3f p, float& x, float& y,
                      float& depth);

// The world-space ray through pixel position (x, y) (same pixel convention): origin at the eye,
// unit direction.
void pixel_ray(const Camera& camera, int width, int height, float x, float y, Vec3f& origin,
               Vec3f& direction);

}  // namespace shprt
