// Lighting a dynamic object from transfer probes (issue 37, docs/probes.md "Lighting objects"): the
// CPU reference, and what `shprt render --object`, Python's render(object=...) and `shprt view`
// draw (the renderer uploads these colours per vertex: Renderer::set_object).
//
// For object vertex v placed by the pose (transfer/object.hpp) at world position p with world
// normal n, the light L (3 × K floats, world frame), the probes' matrix P(p) interpolated at p
// (sample_probes, transfer/probes.hpp; one matrix per colour, or one for all), and
// K' = min(probes' K, light K, self-transfer K, K_used if > 0):
//
//   L_in,c = P_c(p) · L_c                   the SH of the radiance arriving at p (K' coefficients)
//   a      = D(R) · t_v                     the self-shadowing transfer t_v (object frame) rotated
//                                           to world by the SH rotation of the pose's R
//                                           (sh/rotation.hpp), truncated to K';
//            or, without a self-transfer, the clamped cosine's zonal lobe rotated to n
//            (sh/zonal.hpp, rotate_zonal: the Funk–Hecke convolution of L_in)
//   E_c    = ⟨a, L_in,c⟩                     irradiance
//   L_c    = k · ρ_c/π · E_c + (1 − k) · ρ_s,c · ⟨g(r), L_in,c⟩ · V_r
//
// with the glossy term only for k < 1: g(r) the BRDF's zonal lobe (shade/glossy.hpp, brdf_lobe)
// rotated to the reflection r of the view direction about n; the BRDF is the object's material
// BRDF (Mesh::brdfs) where it has one and options.material_brdfs, else options.brdf; ρ_s its
// specular colour (Brdf::specular, white by default); V_r = ⟨a, g(r)⟩ / max(n·w, kMinCosEta) the
// paper's self-shadowing estimate along r with a self-transfer (shade/shade.hpp), 1 without. ρ is
// the vertex albedo, or options.albedo for both colours. The irradiance view gives E; the
// transfer view E under a uniform white sky (radiance 1) over π, grey (channel 0).
//
// Sampled per vertex (not once at the object's centre): an object that straddles a shadow edge of
// the scene shows it, and at 10k vertices the cost stays a few milliseconds (bench/RESULTS.md).
// The object's own shadow on the scene, and the scene's light bounced off the object, are not
// modelled (out of scope: docs/probes.md).
#pragma once

#include "shprt/core/options.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/material.hpp"
#include "shprt/shade/params.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/transfer/object.hpp"
#include "shprt/transfer/probes.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace shprt {

struct ObjectShadeOptions {
    ShadeView view = ShadeView::radiance;
    double k = 1.0;  // diffuse share in [0, 1]
    // The glossy lobe (k < 1), as GlossyShadeOptions: `brdf` for every vertex, or with
    // material_brdfs for the vertices whose material (Mesh::brdfs) gives none.
    Brdf brdf;
    bool material_brdfs = true;
    std::optional<Vec3f> albedo;  // replaces both ρ colours (linear, 0..1)
    Vec3f eye{0, 0, 0};           // world-space eye (the glossy term only)
    int K_used = 0;               // K′: the first coefficients used (0 = all)
};

// The object's options from the scene's plan (shade/params.hpp), so the object and the scene are
// shaded with the same choices: k, gloss and K′, and the BRDF and albedo of glossy matrices; the
// eye is the caller's (the camera's).
ObjectShadeOptions object_shade_options(const ShadingPlan& plan, ShadeView view);

struct ObjectShading {
    // Per object vertex, input order: where the pose puts it (world), its world normal, albedo.
    std::vector<Vec3f> positions, normals, albedo;
    std::vector<Vec3f> irradiance, radiance;  // E and L (formulas above)
    // The pose's position (the object's pivot) lies outside the probe grid: the probes were
    // sampled clamped to the grid (sample_probes). Shells warn once.
    bool clamped = false;
    // The grid has no valid probe: the object is black.
    bool no_valid = false;
    int K_used = 0;  // K′
};

// One-line Error(invalid_argument) "SOURCE: the file has no transfer probes (bake it with shprt
// bake --probes)" for an empty grid; else grid.validate().
void check_probes(const ProbeGrid& grid, const std::string& source);

// The one warning line for a pose outside the grid (ObjectShading::clamped), naming the option as
// the front end spells it (`--at`, `at=`): "--at 9,0,0 is outside the probe grid (-1,0,-1 to
// 3,2,3): the object is lit from the grid's nearest edge".
std::string clamped_warning(const ProbeGrid& grid, Vec3f position, const std::string& option);

// The object lit by the probes under `light` (formulas above), on the CPU in double precision, in
// parallel (TBB; the result does not depend on the thread count). Preconditions, checked (Error):
// check_probes, check(pose), a light of 3·K floats, options in range (k, albedo in [0, 1], a
// valid BRDF), a self-transfer that fits the mesh (one channel of vectors).
ObjectShading shade_object(const DynamicObject& object, const ObjectPose& pose,
                           const ProbeGrid& grid, const ShLight& light,
                           const ObjectShadeOptions& options);

// The object as the command line's `render` and `view` take it: `--object MESH --at X,Y,Z
// [--object-scale S] [--object-rotate YAW,PITCH,ROLL]`, as typed.
struct ObjectChoice {
    std::string object, at;
    double object_scale = 1;
    std::string object_rotate;
};
// Its rows (core/options.hpp), in the command line's help order.
const std::vector<OptionRow<ObjectChoice>>& object_option_table();
// The pose of the choice, or none without an object; checked before any file is read (one-line
// Error(invalid_argument): --at missing or not three numbers, a scale ≤ 0, the object options
// without --object).
std::optional<ObjectPose> object_pose_from(const ObjectChoice& choice);

}  // namespace shprt
