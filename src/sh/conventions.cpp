// The SH conventions in words (sh/conventions.hpp).
#include "shprt/sh/conventions.hpp"

#include "shprt/sh/basis.hpp"

namespace shprt {

namespace {

constexpr const char* kInfo =
    R"(shprt SH conventions (the paper's: Green 2003, "Spherical Harmonic Lighting: The Gritty Details")
basis       real spherical harmonics, orthonormal over the unit sphere: integral of y_i y_j = delta_ij
            y_l^m = sqrt(2) K_l^m cos(m phi)  P_l^m(cos theta)    m > 0
                  = sqrt(2) K_l^m sin(-m phi) P_l^-m(cos theta)   m < 0
                  =         K_l^0           P_l^0(cos theta)    m = 0
            K_l^m = sqrt((2l+1)(l-|m|)! / (4 pi (l+|m|)!))
phase       Condon-Shortley phase (-1)^m included in P_l^m (so y_1^1 = -sqrt(3/(4 pi)) x)
index       i = l(l+1) + m, l = 0, 1, ..., m = -l..l
bands       n bands = l from 0 to n-1 = n^2 coefficients; basis size K = the first K coefficients
            in index order (K need not be a square, e.g. 32, 48, 128: a partly filled last band
            is not rotation invariant; rotation treats its missing coefficients as zero)
axes        world space right-handed, +Y up (glTF); SH functions take the unit world vector (x, y, z)
angles      theta from +Z, phi from +X toward +Y: x = sin(theta)cos(phi), y = sin(theta)sin(phi),
            z = cos(theta); zonal functions are symmetric about +Z
equirect    u = 0.5 + atan2(d.x, -d.z)/(2 pi), v = acos(d.y)/pi (row 0 = zenith +Y, centre = -Z)
rotation    coefficients of g(d) = f(R^-1 d); --zyz A,B,G means R = Rz(G) Ry(B) Rz(A), radians
            methods: ivanic (Ivanic-Ruedenberg 1996 + 1998 errata), paper (Rz Rx(-pi/2) Rz Rx(pi/2) Rz)
radiometry  diffuse transfer T(w) = V(w) max(0, n.w); E = sum c_T c_L is irradiance;
            outgoing radiance = albedo/pi * E; uniform Monte Carlo weight 4 pi / S
max bands   )";

}  // namespace

std::string sh_conventions_text() {
    return kInfo + std::to_string(kMaxBands) + " (" + std::to_string(sh_count(kMaxBands)) +
           " coefficients)\n";
}

}  // namespace shprt
