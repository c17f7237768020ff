// Numbers for the paper's quality rows. The paper (Parubets & Berestneva 2011) judges its basis
// sizes by eye: "shadow edge aliasing", "shadow fill", "artifacts". These functions measure the
// same things against a ground truth (bake/ground_truth.hpp), on per-vertex values and on
// rendered images. docs/paper_table.md defines every number with the bench that reports it.
//
// Per-vertex values are scalars S_i (the bench uses the luminance of the irradiance, see
// luminance()); Ŝ_i is the SH estimate, S_i the ground truth, N the number of vertices compared
// (those where the optional mask is non-zero).
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/light/image.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace shprt::paper {

// Rec. 709 / sRGB luminance of linear RGB: 0.2126 R + 0.7152 G + 0.0722 B.
double luminance(Vec3d rgb);
std::vector<double> luminance(std::span<const Vec3d> rgb);
std::vector<double> luminance(std::span<const Vec3f> rgb);

// ---- Errors over vertices --------------------------------------------------------------------

struct VertexError {
    std::size_t count = 0;      // N
    double rmse = 0;            // the seed's СКО: sqrt(1/N Σ (Ŝ_i − S_i)²)
    double max_abs = 0;         // max_i |Ŝ_i − S_i|
    double bias = 0;            // 1/N Σ (Ŝ_i − S_i)
    double mean_reference = 0;  // 1/N Σ S_i
    // rmse and max_abs over mean_reference (0 when the mean is 0).
    double relative_rmse() const { return mean_reference != 0 ? rmse / mean_reference : 0; }
    double relative_max() const { return mean_reference != 0 ? max_abs / mean_reference : 0; }
};

// Compares estimate with reference over the vertices where mask[i] != 0 (all when the mask is
// empty). Throws Error(invalid_argument) when the sizes differ (mask: empty or the same size) or
// no vertex is selected.
VertexError vertex_error(std::span<const double> estimate, std::span<const double> reference,
                         std::span<const std::uint8_t> mask = {});

// ---- Ringing over vertices -------------------------------------------------------------------

struct VertexRinging {
    std::size_t count = 0;              // N
    double negative_fraction = 0;       // #{i : Ŝ_i < 0} / N — light that cannot exist
    double most_negative = 0;           // min(0, min_i Ŝ_i)
    double most_negative_relative = 0;  // most_negative / (1/N Σ S_i): ≤ 0
    double overshoot_fraction = 0;  // #{i : Ŝ_i > max_j S_j} / N — brighter than anything true
};

// Same selection and errors as vertex_error.
VertexRinging vertex_ringing(std::span<const double> estimate, std::span<const double> reference,
                             std::span<const std::uint8_t> mask = {});

// ---- Shadow contrast (saturation) ------------------------------------------------------------

struct ShadowContrast {
    std::size_t lit_count = 0, shadow_count = 0;
    double estimate_lit = 0, estimate_shadow = 0;    // means of Ŝ over the two sets
    double reference_lit = 0, reference_shadow = 0;  // means of S over the two sets
    // (estimate_lit − estimate_shadow) / (reference_lit − reference_shadow): 1 = the shadow is
    // as deep as it should be; < 1 = unsaturated (light leaks into the shadow); > 1 = too deep.
    double saturation = 0;
    // Evenness of the shadow's fill: sqrt(mean over the shadow set of (Ŝ_i − S_i)²) over the
    // reference contrast (reference_lit − reference_shadow): how far the shadow's values stray,
    // measured in units of the shadow's true depth (0 = right; 1 = errors as large as the step
    // between sun and shadow).
    double shadow_fill_error = 0;
};

// Lit and shadowed vertex sets are the non-zero entries of the two masks (same size as the
// values, disjoint not required). Throws Error(invalid_argument) for size mismatches, an empty
// set, or a reference contrast that is not positive.
ShadowContrast shadow_contrast(std::span<const double> estimate, std::span<const double> reference,
                               std::span<const std::uint8_t> lit,
                               std::span<const std::uint8_t> shadow);

// ---- Edges in images -------------------------------------------------------------------------

// A 1-D profile: values at positions (increasing) along a line.
struct Profile {
    std::vector<double> position;
    std::vector<double> value;
};

// Luminance of `image` (linear RGB, as rendered with `camera`) at `count` ≥ 2 evenly spaced
// points of the world segment a → b, bilinearly interpolated between pixel centres;
// position = distance from a in world units. Throws Error(invalid_argument) if a point projects
// outside the image or behind the eye, or count < 2.
Profile image_profile(const Image& image, const Camera& camera, Vec3f a, Vec3f b, int count);

struct EdgeMeasure {
    bool valid = false;     // false when the profile has no positive contrast (high ≤ low)
    double high = 0;        // mean of the first `plateau` share of the samples (the lit side)
    double low = 0;         // mean of the last `plateau` share (the shadowed side)
    double x90 = 0;         // first crossing of the 90 % level coming from the lit side
    double x10 = 0;         // last crossing of the 10 % level (first coming from the dark side)
    double width = 0;       // x10 − x90: the 10–90 % width
    double overshoot = 0;   // (max value − high) / (high − low), ≥ 0: Gibbs overshoot
    double undershoot = 0;  // (low − min value) / (high − low), ≥ 0: dark ringing
};

// The 10–90 % width of an edge profile that runs from a lit plateau (first samples) to a dark
// one (last samples). With t(x) = (value − low) / (high − low): x90 is where t first falls
// below 0.9 scanning from the start, x10 where it last rises above 0.1 scanning from the end,
// both linearly interpolated between samples (a sample already past a level puts the crossing at
// that sample). For a monotone ramp this is the usual 10–90 % rise distance; ringing that leaves
// the 10–90 % band outside the ramp widens it, as it widens the edge one sees. Throws
// Error(invalid_argument) for fewer than 4 samples, mismatched sizes or plateau outside (0, 0.5).
EdgeMeasure measure_edge(const Profile& profile, double plateau = 0.15);

// ---- Showing a ground truth with the SH renderer ---------------------------------------------

// A transfer that makes the Renderer (or shade_vertices) show given per-vertex irradiance E:
// K = 1, three channels, coefficient E_c / sqrt(4π), so that under constant_light({1, 1, 1}, 1)
// (c_0 = sqrt(4π)) the shaded irradiance is E_c exactly and the radiance ρ_c/π · E_c.
TransferSet irradiance_as_transfer(std::span<const Vec3d> irradiance);

}  // namespace shprt::paper
