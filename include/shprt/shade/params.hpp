// How a baked file is shaded, as one value: what `shprt shade`, `render`, `view` and Python's
// shade() and render() are given, each in its own syntax (`--k 0.5`, `k=0.5`), and what the
// viewer's panel edits in place (viewer/panel.hpp); checked and resolved here, once, so the same
// options give the same numbers everywhere.
//
//   ShadingParams            the user's choices, parsed; check() before any file is read
//     │ resolve_shading(file): narrow_for_shading, then plan_shading (the panel's step: the
//     │                        file kept as read, resolved again on each edit)
//   ShadingPlan              what the file is shaded with: the diffuse/paper term's ShadeOptions,
//     │                      or the glossy matrices' GlossyShadeOptions; the file itself narrowed
//     │                      to its direct part, or its glossy matrices turned into diffuse
//     │                      transfer for the paper's term
//   shade_file(plan, light)  the CPU shading (shade.hpp, glossy.hpp, texel_shade.hpp, a traced sun:
//                            sun_shade.hpp); the GL renderer draws the same plan
#pragma once

#include "shprt/core/options.hpp"  // Spelling, option_text
#include "shprt/core/vec.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/scene/material.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/shade/sun_shade.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace shprt {

// Which glossy term shades a file of transfer matrices: the matrices with their BRDF, or the
// paper's zonal term of their diffuse part (glossy_to_diffuse).
enum class GlossyTerm { matrix, paper };

// "radiance", "irradiance" or "transfer"; "matrix" or "paper". Error(invalid_argument) naming the
// option (`view`, `glossy`) as `spelling` writes it.
ShadeView parse_view(const std::string& name, Spelling spelling);
GlossyTerm parse_glossy_term(const std::string& name, Spelling spelling);

// Every shading choice. The defaults are every front end's defaults.
struct ShadingParams {
    ShadeView view = ShadeView::radiance;
    double k = 1.0;                // diffuse share in [0, 1]
    double gloss = kDefaultGloss;  // Phong exponent ≥ 0 of the paper's glossy term
    // Glossy matrices: with `material_brdfs`, the materials' BRDFs where the scene gives them
    // (Mesh::brdfs), and `brdf` elsewhere; without, `brdf` everywhere. `brdf` unset: `gloss`'s
    // Phong lobe. The command line's `--brdf X` and Python's `brdf=` mean "X everywhere": they
    // set material_brdfs off (shading_params); the viewer's panel edits both. With
    // GlossyTerm::paper: `brdf` a Phong lobe whose exponent replaces `gloss`, and no materials.
    std::optional<Brdf> brdf;
    bool material_brdfs = true;
    GlossyTerm glossy = GlossyTerm::matrix;
    std::optional<Vec3f> albedo;  // glossy matrices: replaces both colours (linear, 0..1)
    int coeffs = 0;               // K′: the first coefficients used (0 = all)
    double exposure = 1.0;        // of pictures (PNG) and the PLY's colours
    bool direct = false;          // an interreflected file's direct part T₀ only
    std::optional<Vec3f> eye;     // the glossy terms' eye; unset: the default camera's (16:9)
    std::optional<Sun> sun;       // a sun kept out of the SH sum (sun_shade.hpp)
    int sun_samples = kDefaultSunSamples;  // directions on its disc: a square, 1..kMaxSunSamples
    bool operator==(const ShadingParams&) const = default;
};

// The numeric shading options as one table (core/options.hpp): name, default (ShadingParams{}'s),
// limits and help, and the field each sets — k, gloss, exposure, direct, shading_coeffs (K′:
// ShadingParams::coeffs) and sun_samples. The command line registers them by walking it
// (tools/common/shading_options.cpp, with shading_choice_table below), Python's shade() and
// render() take their defaults from ShadingParams{}, and check() checks their limits from it. The
// options with names (view, glossy, brdf, albedo, eye, sun) are parsed by the functions above and
// check().
const std::vector<OptionRow<ShadingParams>>& shading_option_table();

// The BRDF choice as the command line's --brdf and Python's brdf= spell it (the panel edits the
// two fields directly): "ggx:0.3" (parse_brdf's spec) for every vertex (material_brdfs off);
// "materials" for the materials' BRDFs where the scene gives them and gloss's Phong lobe
// elsewhere (the default); "materials+ggx:0.3" for the materials' BRDFs and that one elsewhere.
// Error(invalid_argument) from parse_brdf for a bad spec.
void set_brdf_choice(ShadingParams& params, const std::string& spec);

// Checks every choice on its own, before any file is read: k ∈ [0, 1], gloss ≥ 0, exposure > 0
// (finite), coeffs ≥ 0, a valid BRDF (a Phong lobe without colour for the paper's term), albedo in
// [0, 1] and only with the matrix term, sun_samples a square and only with a sun. One-line
// Error(invalid_argument) naming the option as `spelling` writes it.
void check(const ShadingParams& params, Spelling spelling);

// The shading options as the command line types them (`shprt shade`, `render`, `view`): the
// numbers and flags straight into `params` (shading_option_table), the ones with names as text.
// Python's shade() and render() take glossy's default from it.
struct ShadingChoice {
    ShadingParams params;
    std::string brdf, glossy = "matrix", albedo, view = "radiance", eye;
    // K′ is --shading-coeffs (params.coeffs), or the deprecated --coeffs of `shade` and `render`
    // (in `bake` and `view --bake`, --coeffs is the K baked).
    std::optional<int> coeffs;
};
// The options with names as a table (core/options.hpp), in the command line's help order: brdf,
// glossy, coeffs (deprecated), albedo, view, eye. A command leaves out the ones it does not take.
const std::vector<OptionRow<ShadingChoice>>& shading_choice_table();
// The choice, with the light's sun, as ShadingParams checked (check(), naming the options as the
// command line spells them) before any file is read. The deprecated --coeffs gives one warning
// line (core/log.hpp), and with --shading-coeffs an error.
ShadingParams shading_params(const ShadingChoice& choice, const std::optional<Sun>& sun);

// What a file is shaded with (see the top of this file).
struct ShadingPlan {
    ShadeOptions options;                      // the diffuse and paper terms (shade.hpp)
    std::optional<GlossyShadeOptions> glossy;  // set: the matrices with their BRDF (glossy.hpp)
    std::optional<Sun> sun;
    int sun_samples = kDefaultSunSamples;
};

// Resolves `params` against `file` (read from `source`, which errors name) and narrows the file
// to what is shaded: narrow_for_shading, then plan_shading. check(params) first.
ShadingPlan resolve_shading(const ShadingParams& params, ShprtFile& file, const std::string& source,
                            Spelling spelling);

// The two halves of resolve_shading. narrow_for_shading: with `direct`, the file's direct part
// (an error for a file without one); with the paper's term, glossy matrices become their diffuse
// transfer. plan_shading: the plan for a file already narrowed — or kept whole by a front end
// that shows its parts in turn (the viewer's panel toggles `direct` by drawing the direct part it
// keeps; `direct` is not read here) — so a panel edit resolves without reading or narrowing the
// file again. A diffuse file given a BRDF, or glossy matrices without a BRDF, materials or the
// paper's term, is a one-line Error naming `source`; so are matrices not yet narrowed for the
// paper's term.
void narrow_for_shading(const ShadingParams& params, ShprtFile& file, const std::string& source,
                        Spelling spelling);
ShadingPlan plan_shading(const ShadingParams& params, const Mesh& mesh, const TransferSet& transfer,
                         const std::string& source, Spelling spelling);

// The file's receivers shaded on the CPU under `sky` with the plan (shade_receivers), plus the
// sun when the plan has one: `sun` is its prepared form (prepare_sun: its direction turned with
// the sky, its SH projection at the sky's K), required then. `bounced` says whether the sun's
// bounced light came from the file (an interreflected bake) or it is direct only.
SunShadeResult shade_file(const ShprtFile& file, const ShLight& sky, const ShadingPlan& plan,
                          const PreparedSun* sun = nullptr);

// What the glossy terms are, for a command's summary line: "gloss=16" for the diffuse and paper
// terms; "brdf=ggx:0.3, zonal fit error 1.2% at 5 bands" for matrices, or with the materials'
// BRDFs "brdf=materials: phong:32 (1200 vertices), none (8 vertices); none = phong:16; worst zonal
// fit error 12.0% at 5 bands". K_used: the basis size shaded (effective_basis_size).
std::string describe_terms(const ShadingPlan& plan, const Mesh& mesh, int K_used);

}  // namespace shprt
