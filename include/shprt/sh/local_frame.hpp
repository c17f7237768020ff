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

// The frame's axes alone: what a ray needs. The GPU kernel computes them per sample (no angles).
struct LocalAxes {
    Vec3f t, b, n;  // R's columns, float (the rays' directions)
};

struct LocalFrame : LocalAxes {
    double beta, gamma;  // R = Rz(gamma)·Ry(beta): the SH rotation's ZYZ angles (0, beta, gamma)
};

namespace detail {

// The unit normal and the sines and cosines of its polar angles, in double (local_frame's and
// local_axes' common part, so that both give the same axes to the bit).
struct NormalAngles {
    double nx, ny, nz, sin_beta, cos_gamma, sin_gamma;
};

SHPRT_HD_INLINE NormalAngles normal_angles(Vec3f normal) {
    const double x = normal.x, y = normal.y, z = normal.z;
    const double len = std::sqrt(x * x + y * y + z * z);
    NormalAngles a;
    a.nx = len > 0 ? x / len : 0.0;
    a.ny = len > 0 ? y / len : 0.0;
    a.nz = len > 0 ? z / len : 1.0;
    a.sin_beta = std::sqrt(a.nx * a.nx + a.ny * a.ny);
    a.cos_gamma = a.sin_beta > 0 ? a.nx / a.sin_beta : 1.0;
    a.sin_gamma = a.sin_beta > 0 ? a.ny / a.sin_beta : 0.0;
    return a;
}

SHPRT_HD_INLINE LocalAxes axes_of(const NormalAngles& a) {
    return LocalAxes{
        Vec3f{float(a.nz * a.cos_gamma), float(a.nz * a.sin_gamma), float(-a.sin_beta)},
        Vec3f{float(-a.sin_gamma), float(a.cos_gamma), 0.0f},
        Vec3f{float(a.nx), float(a.ny), float(a.nz)}};
}

}  // namespace detail

// The axes of a normal's frame: local_frame(normal)'s t, b, n, to the bit.
SHPRT_HD_INLINE LocalAxes local_axes(Vec3f normal) {
    return detail::axes_of(detail::normal_angles(normal));
}

// The frame of a normal (need not be unit length; normalised here in double; a zero normal
// gives the identity).
SHPRT_HD_INLINE LocalFrame local_frame(Vec3f normal) {
    const detail::NormalAngles a = detail::normal_angles(normal);
    LocalFrame f;
    static_cast<LocalAxes&>(f) = detail::axes_of(a);
    f.beta = std::atan2(a.sin_beta, a.nz);
    f.gamma = a.sin_beta > 0 ? std::atan2(a.ny, a.nx) : 0.0;
    return f;
}

// The world direction R·l of a local direction, in float: the direction a bake traces (the
// reference bake computes it the same way, so both trace the same rays).
SHPRT_HD_INLINE Vec3f to_world(const LocalAxes& f, Vec3f l) {
    return f.t * l.x + f.b * l.y + f.n * l.z;
}

}  // namespace shprt
