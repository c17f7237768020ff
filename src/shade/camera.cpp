// Pinhole camera, OpenGL matrices (the gluLookAt / gluPerspective conventions) and the default
// framing of a scene.
#include "shprt/shade/camera.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parse.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <vector>

namespace shprt {
namespace {

Vec3f to_f(double x, double y, double z) {
    return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
}

}  // namespace

Mat4f operator*(const Mat4f& a, const Mat4f& b) {
    Mat4f r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            float s = 0;
            for (int k = 0; k < 4; ++k) s += a.m[k * 4 + row] * b.m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

Mat4f view_matrix(const Camera& camera) {
    const Vec3f d = camera.target - camera.eye;
    SHPRT_CHECK(length(d) > 0, invalid_argument, "camera eye and target coincide");
    const Vec3f f = normalize(d);
    const Vec3f side = cross(f, camera.up);
    SHPRT_CHECK(length(side) > 1e-6f * length(camera.up), invalid_argument,
                "camera up vector is parallel to the view direction");
    const Vec3f s = normalize(side);
    const Vec3f u = cross(s, f);
    Mat4f m{};
    // Rows s, u, −f; translation −R·eye (column-major storage).
    m.m[0] = s.x, m.m[4] = s.y, m.m[8] = s.z;
    m.m[1] = u.x, m.m[5] = u.y, m.m[9] = u.z;
    m.m[2] = -f.x, m.m[6] = -f.y, m.m[10] = -f.z;
    m.m[12] = -dot(s, camera.eye);
    m.m[13] = -dot(u, camera.eye);
    m.m[14] = dot(f, camera.eye);
    m.m[15] = 1;
    return m;
}

Mat4f projection_matrix(const Camera& camera, float aspect) {
    SHPRT_CHECK(camera.fov_y_deg > 0 && camera.fov_y_deg < 180, invalid_argument,
                "field of view {} degrees is outside (0, 180)", camera.fov_y_deg);
    SHPRT_CHECK(camera.near_plane > 0 && camera.far_plane > camera.near_plane && aspect > 0,
                invalid_argument, "bad clip planes near {} far {} or aspect {}", camera.near_plane,
                camera.far_plane, aspect);
    const double f = 1.0 / std::tan(camera.fov_y_deg * kPi / 360.0);
    const double n = camera.near_plane, fa = camera.far_plane;
    Mat4f m{};
    m.m[0] = static_cast<float>(f / aspect);
    m.m[5] = static_cast<float>(f);
    m.m[10] = static_cast<float>((fa + n) / (n - fa));
    m.m[11] = -1;
    m.m[14] = static_cast<float>(2 * fa * n / (n - fa));
    return m;
}

Mat4f view_projection_matrix(const Camera& camera, float aspect) {
    return projection_matrix(camera, aspect) * view_matrix(camera);
}

void fit_clip_planes(Camera& camera, const Bounds& b) {
    const Vec3f f = normalize(camera.target - camera.eye);
    double far_d = 0;
    for (int i = 0; i < 8; ++i) {
        const Vec3f corner{(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y,
                           (i & 4) ? b.hi.z : b.lo.z};
        far_d = std::max(far_d, static_cast<double>(dot(corner - camera.eye, f)));
    }
    const double extent = length(b.hi - b.lo);
    far_d = std::max(far_d, 1e-3 * std::max(extent, 1e-6)) * 1.01;
    // Near: the closest the bounds come along the axis, but never below far/1000: with a 24-bit
    // depth buffer that keeps depth steps below 0.2 mm at 5 m in a 10 m scene.
    double near_d = far_d;
    for (int i = 0; i < 8; ++i) {
        const Vec3f corner{(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y,
                           (i & 4) ? b.hi.z : b.lo.z};
        near_d = std::min(near_d, static_cast<double>(dot(corner - camera.eye, f)));
    }
    near_d = std::max(near_d * 0.99, far_d * 1e-3);
    camera.near_plane = static_cast<float>(near_d);
    camera.far_plane = static_cast<float>(far_d);
}

Camera look_at_camera(Vec3f eye, Vec3f target, float fov_y_deg, const Bounds& bounds) {
    SHPRT_CHECK(!(eye == target), invalid_argument,
                "camera eye and target coincide at ({}, {}, {})", eye.x, eye.y, eye.z);
    Camera camera;
    camera.eye = eye;
    camera.target = target;
    camera.fov_y_deg = fov_y_deg;
    // Looking straight up or down: any horizontal up vector will do.
    if (length(cross(normalize(target - eye), camera.up)) < 1e-4f) camera.up = {0, 0, -1};
    fit_clip_planes(camera, bounds);
    return camera;
}

Camera default_camera(const Mesh& mesh, float aspect) {
    SHPRT_CHECK(!mesh.positions.empty(), invalid_argument, "mesh {} has no vertices", mesh.source);
    const Bounds b = mesh_bounds(mesh);
    const Vec3f c = (b.lo + b.hi) * 0.5f;
    const Vec3f e = b.hi - b.lo;
    // An enclosure has inward-facing geometry near all four vertical sides of its bounds.
    bool side_seen[4] = {false, false, false, false};
    const bool has_normals = mesh.normals.size() == mesh.positions.size();
    for (std::size_t v = 0; has_normals && v < mesh.positions.size(); ++v) {
        const Vec3f p = mesh.positions[v], n = mesh.normals[v];
        const float tx = 0.1f * e.x, tz = 0.1f * e.z;
        if (p.x <= b.lo.x + tx && n.x > 0.7f) side_seen[0] = true;
        if (p.x >= b.hi.x - tx && n.x < -0.7f) side_seen[1] = true;
        if (p.z <= b.lo.z + tz && n.z > 0.7f) side_seen[2] = true;
        if (p.z >= b.hi.z - tz && n.z < -0.7f) side_seen[3] = true;
    }
    const bool enclosure = side_seen[0] && side_seen[1] && side_seen[2] && side_seen[3];
    Camera cam;
    if (enclosure) {
        // Inside, near the (+X, +Z) corner, at 75 % of the height, looking across and down.
        cam.eye = {c.x + 0.40f * e.x, b.lo.y + 0.75f * e.y, c.z + 0.40f * e.z};
        cam.target = {c.x - 0.25f * e.x, b.lo.y + 0.15f * e.y, c.z - 0.25f * e.z};
        cam.fov_y_deg = 60.0f;
    } else {
        // Outside, from a raised diagonal, fitting the bounding sphere in both directions.
        const double radius = 0.5 * length(e);
        cam.fov_y_deg = 40.0f;
        const double half_v = cam.fov_y_deg * kPi / 360.0;
        const double half_h = std::atan(std::tan(half_v) * aspect);
        const double dist = std::max(radius, 1e-6) / std::sin(std::min(half_v, half_h)) * 1.02;
        const double yaw = kPi / 4, pitch = 25.0 * kPi / 180.0;
        const Vec3f dir =
            to_f(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
        cam.eye = c + dir * static_cast<float>(dist);
        cam.target = c;
    }
    fit_clip_planes(cam, b);
    return cam;
}

namespace {

// Positions are floats: a finite double beyond float's range (1e39) would become infinite.
void check_float_range(const std::vector<double>& v, const std::string& what,
                       const std::string& text) {
    for (double x : v)
        SHPRT_CHECK(std::abs(x) <= double(std::numeric_limits<float>::max()), invalid_argument,
                    "{} '{}': {} is out of range (at most {:g} in magnitude)", what, text, x,
                    double(std::numeric_limits<float>::max()));
}

}  // namespace

void parse_camera(const std::string& text, Camera& camera) {
    const auto v = parse_numbers(text, 6, "camera EX,EY,EZ,TX,TY,TZ");
    check_float_range(v, "camera", text);
    camera.eye = to_f(v[0], v[1], v[2]);
    camera.target = to_f(v[3], v[4], v[5]);
    SHPRT_CHECK(!(camera.eye == camera.target), invalid_argument,
                "camera '{}': eye and target coincide", text);
    const Vec3f d = camera.target - camera.eye;  // the view direction, finite in float
    SHPRT_CHECK(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z), invalid_argument,
                "camera '{}': eye and target are too far apart", text);
}

Vec3f parse_vec3(const std::string& text, const std::string& what) {
    const auto v = parse_numbers(text, 3, what);
    check_float_range(v, what, text);
    return to_f(v[0], v[1], v[2]);
}

void parse_size(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find_first_of("xX");
    SHPRT_CHECK(x != std::string::npos, invalid_argument, "size '{}': expected WxH, e.g. 1280x720",
                text);
    char* stop = nullptr;
    const std::string ws = text.substr(0, x), hs = text.substr(x + 1);
    const long w = std::strtol(ws.c_str(), &stop, 10);
    const bool w_ok = !ws.empty() && *stop == '\0';
    const long h = std::strtol(hs.c_str(), &stop, 10);
    const bool h_ok = !hs.empty() && *stop == '\0';
    SHPRT_CHECK(w_ok && h_ok && w >= 1 && h >= 1 && w <= 16384 && h <= 16384, invalid_argument,
                "size '{}': expected WxH with both in 1..16384", text);
    width = static_cast<int>(w);
    height = static_cast<int>(h);
}

bool project_to_pixel(const Camera& camera, int width, int height, Vec3f p, float& x, float& y,
                      float& depth) {
    const Mat4f m = view_projection_matrix(camera, float(width) / float(height));
    double clip[4];
    for (int r = 0; r < 4; ++r)
        clip[r] = double(m.m[r]) * p.x + double(m.m[4 + r]) * p.y + double(m.m[8 + r]) * p.z +
                  double(m.m[12 + r]);
    if (clip[3] <= 0) return false;
    const double nx = clip[0] / clip[3], ny = clip[1] / clip[3], nz = clip[2] / clip[3];
    x = static_cast<float>((nx * 0.5 + 0.5) * width);
    y = static_cast<float>((0.5 - ny * 0.5) * height);
    depth = static_cast<float>(nz * 0.5 + 0.5);
    return std::abs(nx) <= 1 && std::abs(ny) <= 1 && std::abs(nz) <= 1;
}

void pixel_ray(const Camera& camera, int width, int height, float x, float y, Vec3f& origin,
               Vec3f& direction) {
    const Vec3f f = normalize(camera.target - camera.eye);
    const Vec3f s = normalize(cross(f, camera.up));
    const Vec3f u = cross(s, f);
    const double t = std::tan(camera.fov_y_deg * kPi / 360.0);
    const double aspect = double(width) / double(height);
    const double nx = 2.0 * x / width - 1.0, ny = 1.0 - 2.0 * y / height;
    const Vec3f d = f + s * static_cast<float>(nx * t * aspect) + u * static_cast<float>(ny * t);
    origin = camera.eye;
    direction = normalize(d);
}

Mat4f inverse(const Mat4f& a) {
    double m[16], inv[16];
    for (int i = 0; i < 16; ++i) m[i] = a.m[i];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] +
             m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] -
             m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] +
             m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] -
              m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] -
             m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] +
             m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] -
             m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] +
              m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] +
             m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] -
             m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] +
              m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] -
              m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] -
             m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] +
             m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] -
              m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] +
              m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    const double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    Mat4f r{};
    for (int i = 0; i < 16; ++i) r.m[i] = static_cast<float>(inv[i] / det);
    return r;
}

void check(const CameraChoice& choice) {
    SHPRT_CHECK(!choice.fov || (*choice.fov > 0 && *choice.fov < 180), invalid_argument,
                "--fov {}: must be in (0, 180) degrees", choice.fov.value_or(0));
    Camera parsed;
    if (!choice.camera.empty()) parse_camera(choice.camera, parsed);
}

Camera camera_from(const CameraChoice& choice, const Mesh& mesh, float aspect,
                   const std::string& input) {
    check(choice);
    Camera camera;
    if (choice.camera.empty()) {
        camera = default_camera(mesh, aspect);
    } else {
        Camera parsed;
        parse_camera(choice.camera, parsed);
        camera = look_at_camera(parsed.eye, parsed.target, Camera{}.fov_y_deg, mesh_bounds(mesh));
    }
    if (choice.fov) camera.fov_y_deg = static_cast<float>(*choice.fov);
    // A camera without a frame (eye and target too far apart or too large for single precision,
    // or a scene whose positions are): say which option or file it came from.
    try {
        (void)view_matrix(camera);
    } catch (const Error& e) {
        if (!choice.camera.empty())
            fail(ErrorCode::invalid_argument,
                 "--camera {}: {} (the coordinates are too large for single precision, or the "
                 "up axis +Y is the view direction)",
                 choice.camera, e.what());
        fail(ErrorCode::format,
             "{}: cannot frame the scene with the default camera: {} (its positions are too large "
             "for single precision); give --camera EX,EY,EZ,TX,TY,TZ",
             input, e.what());
    }
    return camera;
}

const std::vector<OptionRow<CameraChoice>>& camera_option_table() {
    static const std::vector<OptionRow<CameraChoice>> table = [] {
        std::vector<OptionRow<CameraChoice>> t;
        add_row(t, "camera", &CameraChoice::camera,
                "EX,EY,EZ,TX,TY,TZ: eye and target (default: frames the scene)");
        add_row(t, "fov", &CameraChoice::fov, "Vertical field of view, degrees");
        return complete_rows(std::move(t));
    }();
    return table;
}

}  // namespace shprt
