// Cube-map geometry. The texel solid angle is the closed form of the solid angle subtended by an
// axis-aligned rectangle on the plane z = 1 (e.g. Driscoll, "Cubemap texel solid angle", 2012;
// the same formula is used in AMD CubeMapGen): ∫∫ (1 + a² + b²)^(−3/2) da db with antiderivative
// atan2(ab, sqrt(a² + b² + 1)).
#include "shprt/light/cubemap.hpp"

#include <cmath>

namespace shprt {
namespace {

constexpr Vec3d kPx{1, 0, 0}, kNx{-1, 0, 0}, kPy{0, 1, 0}, kNy{0, -1, 0}, kPz{0, 0, 1},
    kNz{0, 0, -1};

double corner_area(double a, double b) { return std::atan2(a * b, std::sqrt(a * a + b * b + 1.0)); }

}  // namespace

CubeFaceFrame cube_face_frame(CubeFace face) {
    // Each frame follows from the front face −Z (right +X, down −Y) by unfolding the cube along
    // shared edges, so adjacent cells of the horizontal cross meet along the same world edge.
    switch (face) {
        case CubeFace::px:
            return {kPx, kPz, kNy};
        case CubeFace::nx:
            return {kNx, kNz, kNy};
        case CubeFace::py:
            return {kPy, kPx, kNz};
        case CubeFace::ny:
            return {kNy, kPx, kPz};
        case CubeFace::pz:
            return {kPz, kNx, kNy};
        case CubeFace::nz:
            return {kNz, kPx, kNy};
    }
    return {kNz, kPx, kNy};
}

Vec3d cube_face_direction(const CubeFaceFrame& frame, double a, double b) {
    return normalize(frame.forward + frame.right * a + frame.down * b);
}

double cube_texel_solid_angle(int x, int y, int n) {
    const double a0 = 2.0 * x / n - 1.0, a1 = 2.0 * (x + 1) / n - 1.0;
    const double b0 = 2.0 * y / n - 1.0, b1 = 2.0 * (y + 1) / n - 1.0;
    return corner_area(a0, b0) - corner_area(a0, b1) - corner_area(a1, b0) + corner_area(a1, b1);
}

void cross_cells(CrossLayout layout, CrossCell cells[6]) {
    const bool horizontal = layout == CrossLayout::horizontal;
    cells[0] = {CubeFace::px, 2, 1, cube_face_frame(CubeFace::px)};
    cells[1] = {CubeFace::nx, 0, 1, cube_face_frame(CubeFace::nx)};
    cells[2] = {CubeFace::py, 1, 0, cube_face_frame(CubeFace::py)};
    cells[3] = {CubeFace::ny, 1, 2, cube_face_frame(CubeFace::ny)};
    cells[5] = {CubeFace::nz, 1, 1, cube_face_frame(CubeFace::nz)};
    if (horizontal) {
        cells[4] = {CubeFace::pz, 3, 1, cube_face_frame(CubeFace::pz)};
    } else {
        // Folded down under −Y: the back face's top edge touches −Y's bottom edge, which turns
        // it by 180° relative to the horizontal cross.
        CubeFaceFrame f = cube_face_frame(CubeFace::pz);
        cells[4] = {CubeFace::pz, 1, 3, {f.forward, -f.right, -f.down}};
    }
}

}  // namespace shprt
