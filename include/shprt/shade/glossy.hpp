// Glossy shading with transfer matrices (Sloan, Kautz & Snyder 2002, §5 "glossy"): BRDFs as zonal
// lobes, and the exit radiance of a vertex with a glossy (TransferKind::glossy) transfer matrix
// M_v under an SH light L, on the CPU in double precision. docs/glossy.md derives it.
//
// For vertex v with unit normal n, eye e, view direction w = normalize(e − p), reflection
// r = 2(n·w)n − w, light L_c (colour c, K' coefficients), and M_v the top-left K'×K' block of the
// vertex's symmetric matrix (K' = min(transfer K, light K, K_used)):
//
//   T_c   = M_v · L_c                     the shadowed incident radiance (SH, K' coefficients)
//   a(n)  = the clamped cosine lobe rotated to n (rotate_zonal of clamped_cosine_zonal)
//   g(r)  = the BRDF's zonal lobe (brdf_lobe) rotated to r: the vertex's material's BRDF
//           (Mesh::brdfs) with material_brdfs, where it has one, else options.brdf
//   E_c   = ⟨a(n), T_c⟩                   irradiance
//   L_c   = ρ_d,c/π · E_c + ρ_s,c · ⟨g(r), T_c⟩
//   ρ_d   = k · (albedo override, else the vertex albedo),  ρ_s = (1 − k) · (albedo override,
//           else the specular colour of the vertex's BRDF, Brdf::specular: white unless the
//           material or the --brdf spec gives one)
//
// The lobe integrates to 1 over the sphere (a "normalised" lobe), so an unshadowed vertex under
// a constant light 1 reflects ρ_s (white furnace) up to SH truncation (docs/glossy.md gives the
// bound). The lobes (θ: angle between the incident direction and the lobe axis r, x = cos θ):
//
//   phong:E   (E+1)/(2π) · max(0, x)^E                     exact zonal (phong_lobe_zonal)
//   blinn:E   c · ((1+x)/2)^(E/2) for x > 0: Blinn–Phong (n·h)^E at normal incidence, where
//             h is the half vector and n·h = cos(θ/2)
//   ggx:R     c · D_GGX(θ/2) for x > 0, α = R²: the GGX (Trowbridge–Reitz) distribution at
//             normal incidence (Fresnel and masking are left out: ρ_s is their place)
//
// with c normalising each to 1. Blinn and GGX are zonal about r only at normal incidence; away
// from it, the real lobes stretch, which a zonal lobe cannot follow (Sloan 2002 makes the same
// approximation). brdf_lobe projects each profile onto n bands (the L2-optimal zonal fit) and
// reports the relative L2 residual as the fit error.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/material.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace shprt {

// The normalised lobe profile f(x) above (∫ f dω = 1 over the sphere), x = cos θ from the axis:
// brdf_profile(b)(x). The normalisation is computed once, when the profile is made.
struct BrdfProfile {
    Brdf brdf;
    double scale = 1;  // 1 / ∫ (unnormalised profile) dω
    double operator()(double x) const;
};
BrdfProfile brdf_profile(const Brdf& brdf);

// The reflection r = 2(n·w)n − w of the view direction w = normalize(eye − p) about unit n (w = n
// at the eye itself): the axis of a vertex's lobe.
Vec3d reflect_view(const Vec3d& n, const Vec3d& p, const Vec3d& eye);

struct BrdfLobe {
    std::vector<double> zonal;  // z_l, l < bands (sh/zonal.hpp convention)
    double fit_error = 0;       // ‖f − f_n‖ / ‖f‖ (L2 over the sphere) of the n-band lobe
};
// The zonal lobe of `brdf` with `bands` bands (1..kMaxBands). Phong in closed form, Blinn and GGX
// by project_zonal. Throws Error(invalid_argument) for a bad parameter.
BrdfLobe brdf_lobe(const Brdf& brdf, int bands);

struct GlossyShadeOptions {
    // The lobe of every vertex; with material_brdfs, of the vertices whose material gives none.
    Brdf brdf;
    // Vertices whose material gives a BRDF (Mesh::brdfs, brdf_index) are shaded with it.
    bool material_brdfs = false;
    double k = 0.5;               // diffuse share in [0, 1]
    std::optional<Vec3f> albedo;  // override of both ρ colours (linear, 0..1)
    Vec3f eye{0, 0, 0};           // world-space eye position
    int K_used = 0;               // first K' coefficients; 0 = all available
};

// The BRDFs glossy shading uses: [0] is options.brdf, and with options.material_brdfs 1 + i is
// the mesh's BRDF i; brdf_table_index(mesh, material_brdfs, v) is vertex v's entry. Throws
// Error(invalid_argument) for a bad BRDF, or BRDF indices that do not fit the mesh.
std::vector<Brdf> brdf_table(const Mesh& mesh, bool material_brdfs, const Brdf& brdf);
inline std::uint32_t brdf_table_index(const Mesh& mesh, bool material_brdfs, std::size_t v) {
    if (!material_brdfs || mesh.brdf_index.empty() || mesh.brdf_index[v] == Mesh::kNoBrdf) return 0;
    return mesh.brdf_index[v] + 1;
}

// Checks that `transfer` is a glossy matrix set for `mesh`: transfer.check(mesh) and a symmetric
// matrix per receiver, one channel; otherwise Error(invalid_argument) ("… is diffuse (vector)
// transfer: glossy shading needs a glossy bake (--transfer glossy)").
void check_glossy_shadable(const Mesh& mesh, const TransferSet& transfer);

// Shades every vertex with the formulas above, in parallel (TBB; the result does not depend on
// the thread count). A transfer that carries a CPCA code (TransferSet::cpca, e.g. read from a
// `shprt compress` file) is shaded from the code: the light transformed once per cluster,
// M_v·L = mean·L + Σ_i w_i (B_i·L) (Sloan et al. 2003), equal to shading the rebuilt rows up to
// rounding. irradiance holds E, radiance L. Preconditions, checked (Error): as
// check_glossy_shadable, 0 ≤ k ≤ 1, albedo in [0, 1], a valid BRDF, light 3·K floats.
ShadeResult shade_glossy(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                         const GlossyShadeOptions& options);

// The diffuse (vector) transfer of a glossy set: t_v = M_v · a(n_v), the shadowed clamped-cosine
// transfer of the shading formula above, one channel, kind shadowed, per receiver: vertices, or
// texels (with their normals from the atlas, receiver_normals; the atlas is kept). The paper's
// glossy term (shade/shade.hpp, `--glossy paper`) shades it, so both terms come from one bake.
TransferSet glossy_to_diffuse(const Mesh& mesh, const TransferSet& transfer);

// A per-vertex colour as a transfer the GL renderer draws as is: three channels of K = 1 holding
// `radiance`, to be drawn with view irradiance under light_for_colours() (one coefficient 1 per
// channel), so that E = radiance. How `shprt render` shows CPU-shaded glossy radiance.
TransferSet colours_as_transfer(const std::vector<Vec3f>& radiance);
ShLight light_for_colours();

}  // namespace shprt
