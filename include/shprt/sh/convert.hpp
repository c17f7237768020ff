// Converters between shprt's SH convention (sh/basis.hpp: real SH with the Condon–Shortley
// phase, index l(l+1)+m, right-handed world, +Y up, pole +Z, radiance coefficients) and other
// common conventions. Coefficient vectors are single-channel; convert RGB channel by channel.
// All functions allow in == out.
//
// What the other conventions are (checked against their sources, 2024):
// * No Condon–Shortley phase (e.g. Ivanic & Ruedenberg, many physics codes without (−1)^m):
//   y'_lm = (−1)^m y_lm, so c'_lm = (−1)^m c_lm. Its own inverse.
// * three.js SphericalHarmonics3 (src/math/SphericalHarmonics3.js, getBasisAt/getAt): 9
//   coefficients in the order (0,0), (1,−1), (1,0), (1,1), (2,−2), (2,−1), (2,0), (2,1), (2,2)
//   with basis 0.282095; 0.488603·(y, z, x); 1.092548·xy, 1.092548·yz, 0.315392·(3z²−1),
//   1.092548·xz, 0.546274·(x²−y²) — i.e. our basis without the Condon–Shortley phase, same
//   index order. three.js world space is right-handed with +Y up, like ours, and it evaluates
//   the polynomials directly in world (x, y, z), so no axis change. Coefficients are radiance
//   (getIrradianceAt applies the clamped-cosine factors itself).
// * Unity SphericalHarmonicsL2 (Unity manual "Light Probes: technical information"; HDRP's
//   SphericalHarmonicMath): same index order, Sloan's "Stupid SH Tricks" basis, which carries
//   the Condon–Shortley phase (constants {k0, −k1, k1, −k1, k2, −k2, k3, −k2, k4} on
//   (1, y, z, x, xy, yz, 3z²−1, xz, x²−y²)), evaluated in Unity's LEFT-handed world (+Y up,
//   +Z forward). We map directions as the glTF importers do (UnityGLTF's
//   CoordinateSpaceConversionScale = (−1, 1, 1)): d_unity = (−x, y, z). Mirroring x sends
//   y_lm to s_lm·y_lm with s_lm = (−1)^m for m ≥ 0 and −(−1)^m for m < 0.
//   - to_unity_l2: the canonical coefficients (what HDRP's UndoCosineRescaling returns).
//   - to_unity_probe_l2: the values Unity stores in light probes and RenderSettings.ambientProbe:
//     canonical radiance coefficients convolved with the clamped cosine and divided by π
//     (factors 1, 2/3, 1/4 per band) and premultiplied by the basis constants (Unity's
//     kNormalizationConstants {c0, −c1, c1, −c1, c2, −c2, c3, −c2, c4}, c0 = 1/(2√π),
//     c1 = √3/(3√π), c2 = √15/(8√π), c3 = √5/(16√π), c4 = √15/(16√π)), so that Unity's shader
//     polynomial (s0 − s6) + s1 y + s2 z + s3 x + s4 xy + s5 yz + 3 s6 z² + s7 xz + s8 (x² − y²)
//     gives irradiance/π (the radiance of a white Lambertian surface) at the Unity normal.
#pragma once

namespace shprt {

// c'_lm = (−1)^m c_lm for the first K coefficients (K ≥ 0; throws Error when K < 0).
void to_no_condon_shortley(const double* in, double* out, int K);
void from_no_condon_shortley(const double* in, double* out, int K);

// 9 coefficients (3 bands) each.
void to_threejs_l2(const double* in9, double* out9);
void from_threejs_l2(const double* in9, double* out9);
void to_unity_l2(const double* in9, double* out9);
void from_unity_l2(const double* in9, double* out9);
void to_unity_probe_l2(const double* in9, double* out9);
void from_unity_probe_l2(const double* in9, double* out9);

}  // namespace shprt
