// A receiver's tangent frame for the local direction sets (sampler.hpp, DirectionFrame::local;
// docs/sampling.md, "The local set").
//
// The frame is the rotation R = Rz(γ)·Ry(β) with (β, γ) the polar angles of the unit normal n
// (θ from +Z, φ from +X toward +Y, as sh/basis.hpp): R·ẑ = n, and its columns are
//     t = (cos β cos γ, cos β sin γ, −sin β),  b = (−sin γ, cos γ, 0),  n.
// A local direction l (hemisphere around +z) is the world direction R·l = t·l.x + b·l.y + n·l.z.
// A function f' of local directions is the world function g(d) = f'(R⁻¹d): in the convention of
// sh/rotation.hpp its coefficients are D(R)·c', i.e. rotate_zyz_paper(0, β, γ, c', c, K) — the
// paper's factorisation with ZYZ angles (α, β, γ) = (0, β, γ), no angle extraction needed.
// At the poles (n = ±z) γ = 0. Deterministic: a pure function of the normal's bits.
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"

#include <cmath>

namespace shprt {

struct LocalFrame {
    Vec3f t, b, n;       // R's columns, float (the rays' directions)
    double beta, gamma;  // R = Rz(gamma)·Ry(beta): the SH rotation's ZYZ angles (0, beta, gamma)
};

// The frame of a normal (need not be unit length; normalised here in double; a zero normal
// gives the identity).
SHPRT_HD_INLINE LocalFrame local_frame(Vec3f normal) {
    const double x = normal.x, y = normal.y, z = normal.z;
    const double len = std::sqrt(x * x + y * y + z * z);
    const double nx = len > 0 ? x / len : 0.0, ny = len > 0 ? y / len : 0.0,
                 nz = len > 0 ? z / len : 1.0;
    const double sin_beta = std::sqrt(nx * nx + ny * ny);
    const double cos_gamma = sin_beta > 0 ? nx / sin_beta : 1.0;
    const double sin_gamma = sin_beta > 0 ? ny / sin_beta : 0.0;
    LocalFrame f;
    f.t = Vec3f{float(nz * cos_gamma), float(nz * sin_gamma), float(-sin_beta)};
    f.b = Vec3f{float(-sin_gamma), float(cos_gamma), 0.0f};
    f.n = Vec3f{float(nx), float(ny), float(nz)};
    f.beta = std::atan2(sin_beta, nz);
    f.gamma = sin_beta > 0 ? std::atan2(ny, nx) : 0.0;
    return f;
}

// The world direction R·l of a local direction, in float: the direction a bake traces (the
// reference bake computes it the same way, so both trace the same rays).
SHPRT_HD_INLINE Vec3f to_world(const LocalFrame& f, Vec3f l) {
    return f.t * l.x + f.b * l.y + f.n * l.z;
}

}  // namespace shprt
