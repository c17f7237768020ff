// Cube maps: exact texel solid angles, right-handed face frames that fold into a cube (every
// shared edge of the cross is the same world edge), a constant cross gives a constant light,
// horizontal = vertical = six faces, and a cross agrees with an equirect map of the same sky.
#include "shprt/core/math.hpp"
#include "shprt/light/cubemap.hpp"

#include "shprt/core/error.hpp"
#include "shprt/light/equirect.hpp"
#include "shprt/light/light.hpp"
#include "shprt/sh/basis.hpp"

#include "light/light_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace shprt {
namespace {

using test_support::expect_near;
using test_support::max_abs_diff;

using Sky = std::function<Vec3d(Vec3d)>;

Vec3d smooth_sky(Vec3d d) {
    const Vec3d a = normalize(Vec3d{0.5, 0.4, -0.7});
    return Vec3d{3.0, 2.0, 1.0} * std::exp(4.0 * (dot(d, a) - 1.0)) +
           Vec3d{0.2, 0.3, 0.5} * (1.0 + d.y) + Vec3d{0.4, 0.0, 0.0} * (d.x > 0 ? d.x * d.x : 0);
}

Image cross_of(CrossLayout layout, int n, const Sky& f) {
    const bool h = layout == CrossLayout::horizontal;
    Image image = Image::make(h ? 4 * n : 3 * n, h ? 3 * n : 4 * n);
    CrossCell cells[6];
    cross_cells(layout, cells);
    for (const CrossCell& cell : cells)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const Vec3d d =
                    cube_face_direction(cell.frame, (2.0 * x + 1) / n - 1, (2.0 * y + 1) / n - 1);
                const Vec3d v = f(d);
                for (int c = 0; c < 3; ++c)
                    image.pixel(cell.col * n + x, cell.row * n + y)[c] = float(v[c]);
            }
    return image;
}

Image equirect_of(int W, int H, const Sky& f) {
    Image image = Image::make(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const Vec3d v = f(equirect_pixel_direction<double>(x, y, W, H));
            for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = float(v[c]);
        }
    return image;
}

TEST(CubeMap, TexelSolidAnglesSumTo4Pi) {
    for (int n : {1, 2, 7, 64, 512}) {
        double sum = 0.0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) sum += cube_texel_solid_angle(x, y, n);
        EXPECT_NEAR(6 * sum, 4 * kPi, 1e-9) << n;
    }
    EXPECT_NEAR(cube_texel_solid_angle(0, 0, 1), 4 * kPi / 6, 1e-14);
    // A centre texel of a fine face subtends ≈ its area (2/n)²; a corner texel less.
    const int n = 1000;
    EXPECT_NEAR(cube_texel_solid_angle(500, 500, n), 4.0 / (n * n), 1e-10);
    EXPECT_LT(cube_texel_solid_angle(0, 0, n), 0.2 * 4.0 / (n * n));
}

TEST(CubeMap, FramesAreRightHandedSeenFromInside) {
    for (int f = 0; f < 6; ++f) {
        const CubeFaceFrame fr = cube_face_frame(static_cast<CubeFace>(f));
        expect_near(cross(fr.right, fr.down), fr.forward, 0.0);
        EXPECT_EQ(dot(fr.right, fr.forward), 0.0);
        EXPECT_EQ(dot(fr.down, fr.forward), 0.0);
    }
    // The front of the horizontal cross: −Z, +X to the right, +Y up (as the equirect centre).
    const CubeFaceFrame front = cube_face_frame(CubeFace::nz);
    expect_near(front.forward, {0, 0, -1}, 0);
    expect_near(front.right, {1, 0, 0}, 0);
    expect_near(front.down, {0, -1, 0}, 0);
    expect_near(cube_face_frame(CubeFace::px).forward, {1, 0, 0}, 0);
    expect_near(cube_face_frame(CubeFace::py).forward, {0, 1, 0}, 0);
}

// Cells that touch in the cross must touch on the cube along the same edge.
TEST(CubeMap, CrossFoldsIntoACube) {
    for (CrossLayout layout : {CrossLayout::horizontal, CrossLayout::vertical}) {
        CrossCell cells[6];
        cross_cells(layout, cells);
        int shared_edges = 0;
        for (const CrossCell& p : cells)
            for (const CrossCell& q : cells) {
                for (double t : {-1.0, -0.3, 0.5, 1.0}) {
                    if (q.col == p.col + 1 && q.row == p.row) {  // q right of p
                        expect_near(cube_face_direction(p.frame, 1, t),
                                    cube_face_direction(q.frame, -1, t), 1e-15);
                        shared_edges += t == 1.0;
                    }
                    if (q.row == p.row + 1 && q.col == p.col) {  // q below p
                        expect_near(cube_face_direction(p.frame, t, 1),
                                    cube_face_direction(q.frame, t, -1), 1e-15);
                        shared_edges += t == 1.0;
                    }
                }
            }
        EXPECT_EQ(shared_edges, 5);  // a cross is a tree of 6 cells: 5 shared edges
        bool seen[6] = {};
        for (const CrossCell& c : cells) seen[static_cast<int>(c.face)] = true;
        for (bool s : seen) EXPECT_TRUE(s);
    }
}

TEST(CubeMap, ConstantCrossIsConstantLight) {
    const int K = 25;
    double leak[2] = {0, 0};
    for (int r = 0; r < 2; ++r) {
        const int n = r == 0 ? 32 : 64;
        for (CrossLayout layout : {CrossLayout::horizontal, CrossLayout::vertical}) {
            const ShLight light = project_cube_cross(cross_of(layout, n,
                                                              [](Vec3d) {
                                                                  return Vec3d{2, 2, 2};
                                                              }),
                                                     K);
            for (int c = 0; c < 3; ++c) {
                // Exact texel solid angles: the mean is exact.
                EXPECT_NEAR(light.channel(c)[0], 2 * std::sqrt(4 * kPi), 1e-5);
                for (int i = 1; i < K; ++i)
                    leak[r] = std::max(leak[r], double(std::abs(light.channel(c)[i])));
            }
        }
    }
    // Centre-of-texel evaluation of the basis leaks O(texel²) into higher bands (l = 4, the
    // cube's symmetry): measured 3.3e-3 at n = 32 and about a quarter of that at n = 64, against
    // c_0 = 7.1.
    EXPECT_LT(leak[0], 5e-3);
    EXPECT_GT(leak[0] / leak[1], 3.5);
    EXPECT_LT(leak[0] / leak[1], 4.5);
}

TEST(CubeMap, LayoutsAndFacesAgree) {
    const int n = 16, K = 36;
    const Image h = cross_of(CrossLayout::horizontal, n, smooth_sky);
    const ShLight lh = project_cube_cross(h, K);
    const ShLight lv = project_cube_cross(cross_of(CrossLayout::vertical, n, smooth_sky), K);
    EXPECT_LT(max_abs_diff(lh, lv), 1e-6);
    // Six faces cut out of the horizontal cross.
    CrossCell cells[6];
    cross_cells(CrossLayout::horizontal, cells);
    std::array<Image, 6> faces;
    for (int f = 0; f < 6; ++f) {
        faces[f] = Image::make(n, n);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (int c = 0; c < 3; ++c)
                    faces[f].pixel(x, y)[c] =
                        h.pixel(cells[f].col * n + x, cells[f].row * n + y)[c];
    }
    EXPECT_LT(max_abs_diff(project_cube_faces(faces, K), lh), 1e-6);
    faces[3] = Image::make(n, n + 1);
    EXPECT_THROW(project_cube_faces(faces, K), Error);
    faces[3] = Image::make(n + 1, n + 1);
    EXPECT_THROW(project_cube_faces(faces, K), Error);
}

TEST(CubeMap, CrossAgreesWithEquirectOfTheSameSky) {
    const int K = 25;
    const ShLight cube = project_cube_cross(cross_of(CrossLayout::horizontal, 64, smooth_sky), K);
    const ShLight eq = project_equirect(equirect_of(512, 256, smooth_sky), K);
    // Two discretisations of one sky: they differ by O(h²) (coefficients are O(1)); a wrongly
    // oriented face would differ by O(1).
    EXPECT_LT(max_abs_diff(cube, eq), 3e-3) << max_abs_diff(cube, eq);
    // And an +X-only sky in a cross lights +X the most.
    const ShLight px =
        project_cube_cross(cross_of(CrossLayout::horizontal, 16,
                                    [](Vec3d d) {
                                        return Vec3d{1, 1, 1} * (d.x > 0.8 ? 1.0 : 0.0);
                                    }),
                           K);
    const Vec3d axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const double r_px = light_radiance(px, axes[0]).x;
    for (int a = 1; a < 6; ++a) EXPECT_LT(light_radiance(px, axes[a]).x, 0.5 * r_px);
}

TEST(CubeMap, WrongShapeThrows) {
    EXPECT_THROW(project_cube_cross(Image::make(10, 10), 9), Error);
    EXPECT_THROW(project_cube_cross(Image::make(40, 31), 9), Error);
    EXPECT_THROW(project_cube_cross(Image{}, 9), Error);
    try {
        project_cube_cross(Image::make(64, 32), 9);
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::format);
        EXPECT_NE(std::string(e.what()).find("64x32"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace shprt
