// Cube-map geometry: face orientations, texel directions and exact texel solid angles.
//
// Orientation (chosen to agree with the equirect convention of light/equirect.hpp: the front
// is −Z, up is +Y, the world is right-handed and every face is seen from inside the cube):
//
//   horizontal cross (4 × 3 faces)        vertical cross (3 × 4 faces)
//           [+Y]                                   [+Y]
//      [−X] [−Z] [+X] [+Z]                    [−X] [−Z] [+X]
//           [−Y]                                   [−Y]
//                                                  [+Z]  (upside down)
//
// In the horizontal cross the four side faces are upright (+Y up) and read left to right as you
// turn right: −X, then the front −Z, then +X, then the back +Z. The +Y face sits on top of the
// front face (its bottom edge touches −Z's top edge, its right is +X); the −Y face hangs below
// the front (its top edge touches −Z's bottom edge, its right is +X). The vertical cross is the
// same net with the back face folded down under −Y instead, which turns it by 180°.
// The six separate face images of `faces:` use the horizontal cross's orientations.
// Blank cells of a cross are ignored.
#pragma once

#include "shprt/core/vec.hpp"

namespace shprt {

enum class CubeFace { px, nx, py, ny, pz, nz };  // +X, −X, +Y, −Y, +Z, −Z (file order of faces:)

// Where a face image's pixels point: the face centre looks along `forward`; moving right in the
// image moves along `right`, moving down moves along `down` (all unit world axes).
struct CubeFaceFrame {
    Vec3d forward, right, down;
};

// Frame of each face as it appears in the horizontal cross (and in `faces:` files).
CubeFaceFrame cube_face_frame(CubeFace face);

// Unit direction through face coordinates (a, b) ∈ [−1, 1]², a to the right, b downward.
Vec3d cube_face_direction(const CubeFaceFrame& frame, double a, double b);

// Exact solid angle (steradians) of texel (x, y) of an n × n face: the texel spans
// a ∈ [2x/n − 1, 2(x+1)/n − 1], b likewise in y, on the plane at distance 1, and subtends
// A(a0,b0) − A(a0,b1) − A(a1,b0) + A(a1,b1) with A(a,b) = atan2(ab, sqrt(a² + b² + 1)).
// The 6n² texels sum to 4π up to rounding.
double cube_texel_solid_angle(int x, int y, int n);

enum class CrossLayout { horizontal, vertical };

// One face's cell in a cross: column and row in units of the face size, and its frame (the
// vertical cross's +Z cell is turned by 180°).
struct CrossCell {
    CubeFace face;
    int col, row;
    CubeFaceFrame frame;
};

// The six cells of a layout, in CubeFace order.
void cross_cells(CrossLayout layout, CrossCell cells[6]);

}  // namespace shprt
