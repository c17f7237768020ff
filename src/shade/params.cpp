// ShadingParams: one check and one resolution for every front end (shade/params.hpp).
#include "shprt/shade/params.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shprt {

ShadeView parse_view(const std::string& name, Spelling spelling) {
    if (name == "radiance") return ShadeView::radiance;
    if (name == "irradiance") return ShadeView::irradiance;
    if (name == "transfer") return ShadeView::transfer;
    fail(ErrorCode::invalid_argument, "{}: expected radiance, irradiance or transfer",
         option_text(spelling, "view", "'" + name + "'"));
}

GlossyTerm parse_glossy_term(const std::string& name, Spelling spelling) {
    if (name == "matrix") return GlossyTerm::matrix;
    if (name == "paper") return GlossyTerm::paper;
    fail(ErrorCode::invalid_argument, "{}: expected matrix or paper",
         option_text(spelling, "glossy", "'" + name + "'"));
}

namespace {

using Row = OptionRow<ShadingParams>;

std::vector<Row> make_table() {
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    std::vector<Row> t;
    add_row(t, "k", &ShadingParams::k, "Diffuse share k in [0, 1] (default 1: pure diffuse)",
            {0, 1});
    add_row(t, "gloss", &ShadingParams::gloss,
            fmt::format("Phong exponent of the glossy lobe (default {})", kDefaultGloss),
            {0, kNone});
    add_row(t, "exposure", &ShadingParams::exposure, "Exposure multiplier (default 1)",
            {0, kNone, true});
    add_row(t, "direct", &ShadingParams::direct,
            "Interreflected files: shade the direct light only (the file's T_0)", {});
    add_row(t, "shading_coeffs", &ShadingParams::coeffs,
            "Shade with the first K' coefficients (default: all)", {0, kNone}, "≥ 0 (0: all)");
    add_row(
        t, "sun_samples", &ShadingParams::sun_samples,
        fmt::format("With --sun: directions traced on the sun's disc, a square (default {}; 1 = "
                    "the centre only, a point sun's hard shadow)",
                    kDefaultSunSamples),
        {1, double(kMaxSunSamples)}, fmt::format("a square, 1 to {}", kMaxSunSamples));
    return complete_rows(std::move(t));
}

}  // namespace

const std::vector<OptionRow<ShadingParams>>& shading_option_table() {
    static const std::vector<Row> table = make_table();
    return table;
}

void check(const ShadingParams& p, Spelling s) {
    const auto& t = shading_option_table();
    check_limits(find_row(t, "k"), p.k, s);
    check_limits(find_row(t, "gloss"), p.gloss, s);
    check_limits(find_row(t, "exposure"), p.exposure, s);
    check_limits(find_row(t, "shading_coeffs"), static_cast<long long>(p.coeffs), s);
    if (p.brdf) check_brdf(*p.brdf);
    if (p.glossy == GlossyTerm::paper && p.brdf) {
        const std::string paper = option_text(s, "glossy", "paper");
        SHPRT_CHECK(p.brdf->model == BrdfModel::phong, invalid_argument,
                    "{}: the paper's term has a Phong lobe only ({})", paper,
                    option_text(s, "brdf", "phong:E"));
        SHPRT_CHECK(p.brdf->specular == (Vec3f{1, 1, 1}), invalid_argument,
                    "{}: the paper's term has no specular colour ({})", paper,
                    option_text(s, "brdf", "phong:E"));
    }
    if (p.albedo) {
        const Vec3f a = *p.albedo;
        const std::string text = option_text(s, "albedo", fmt::format("{},{},{}", a.x, a.y, a.z));
        SHPRT_CHECK(a.x >= 0 && a.x <= 1 && a.y >= 0 && a.y <= 1 && a.z >= 0 && a.z <= 1,
                    invalid_argument, "{}: each component must be 0 to 1 (linear reflectance)",
                    text);
        SHPRT_CHECK(p.glossy == GlossyTerm::matrix, invalid_argument,
                    "{} needs the matrix term ({})", option_text(s, "albedo"),
                    option_text(s, "glossy", "matrix"));
    }
    const std::string samples = option_text(s, "sun_samples", std::to_string(p.sun_samples));
    SHPRT_CHECK(p.sun || p.sun_samples == kDefaultSunSamples, invalid_argument, "{} needs {}",
                samples, option_text(s, "sun"));
    if (p.sun) {
        try {
            (void)sun_disc_directions(*p.sun, p.sun_samples, 0);
        } catch (const Error& e) {
            fail(e.code(), "{}: {}", option_text(s, "sun_samples"), e.what());
        }
    }
}

ShadingPlan resolve_shading(const ShadingParams& p, ShprtFile& file, const std::string& source,
                            Spelling s) {
    narrow_for_shading(p, file, source, s);
    return plan_shading(p, file.mesh, file.transfer, source, s);
}

void narrow_for_shading(const ShadingParams& p, ShprtFile& file, const std::string& source,
                        Spelling s) {
    if (p.direct) {
        SHPRT_CHECK(!file.transfer.direct.empty(), invalid_argument,
                    "{}: {} has no direct part (only interreflected bakes keep one)",
                    option_text(s, "direct", s == Spelling::python ? "True" : ""), source);
        file.transfer = file.transfer.direct_only();
    }
    if (p.glossy == GlossyTerm::paper && is_matrix(file.transfer.layout))
        file.transfer = glossy_to_diffuse(file.mesh, file.transfer);
}

ShadingPlan plan_shading(const ShadingParams& p, const Mesh& mesh, const TransferSet& transfer,
                         const std::string& source, Spelling s) {
    ShadingPlan plan;
    plan.sun = p.sun;
    plan.sun_samples = p.sun_samples;
    plan.options.k = p.k;
    plan.options.gloss = p.gloss;
    plan.options.K_used = p.coeffs;
    plan.options.eye = p.eye ? *p.eye : default_camera(mesh, 16.0f / 9.0f).eye;
    const bool matrices = is_matrix(transfer.layout);
    const std::string brdf_option = option_text(s, "brdf");
    if (p.glossy == GlossyTerm::paper) {
        SHPRT_CHECK(!matrices, invalid_argument,
                    "{}: {} shades the matrices' diffuse transfer: narrow the file first "
                    "(narrow_for_shading)",
                    source, option_text(s, "glossy", "paper"));
        if (p.brdf) plan.options.gloss = p.brdf->parameter;
        return plan;
    }
    // The materials' BRDFs, where the scene gives them and material_brdfs asks for them.
    const bool has_materials = !mesh.brdf_index.empty();
    const bool materials = matrices && p.material_brdfs && has_materials;
    SHPRT_CHECK(
        !matrices || p.brdf || materials, invalid_argument,
        "{}: glossy transfer matrices need {} (or {}): {}", source,
        option_text(s, "brdf", "phong:E|blinn:E|ggx:R"), option_text(s, "glossy", "paper"),
        has_materials ? "the materials' BRDFs are off" : "the scene's materials give no BRDF");
    if (!p.brdf && !materials) {
        SHPRT_CHECK(!p.albedo, invalid_argument, "{} needs {}", option_text(s, "albedo"),
                    brdf_option);
        return plan;
    }
    SHPRT_CHECK(matrices, invalid_argument,
                "{}: {} transfer is diffuse (a vector per receiver): {} needs a glossy bake ({}), "
                "or use {}",
                source, to_string(transfer.kind), brdf_option, option_text(s, "transfer", "glossy"),
                option_text(s, "gloss"));
    GlossyShadeOptions g;
    g.material_brdfs = materials;  // then g.brdf where a material gives none
    g.brdf = p.brdf ? *p.brdf : Brdf{BrdfModel::phong, p.gloss};
    check_brdf(g.brdf);
    g.k = p.k;
    g.albedo = p.albedo;
    g.eye = plan.options.eye;
    g.K_used = p.coeffs;
    plan.glossy = g;
    return plan;
}

SunShadeResult shade_file(const ShprtFile& file, const ShLight& sky, const ShadingPlan& plan,
                          const PreparedSun* sun) {
    SHPRT_CHECK(!plan.sun || sun, invalid_argument,
                "shade_file: the plan has a sun, and no prepared sun was given");
    if (!plan.sun) {
        SunShadeResult result;
        static_cast<ShadeResult&>(result) = shade_receivers(
            file.mesh, file.transfer, sky, plan.options, plan.glossy ? &*plan.glossy : nullptr);
        return result;
    }
    SunShadeOptions sun_options;
    sun_options.disc_samples = plan.sun_samples;
    if (plan.glossy)
        return shade_glossy_with_sun(file.mesh, file.transfer, sky, *sun, *plan.glossy,
                                     sun_options);
    return shade_with_sun(file.mesh, file.transfer, sky, *sun, plan.options, sun_options);
}

namespace {

// What a large zonal fit error means, for the summary line: nothing is wrong; a lobe sharper than
// the bands can hold, or cut off at the horizon, is shaded as its fit (blurred, as the paper's
// glossy term is). More bands shrink it, up to 8 (the most a glossy bake holds).
std::string fit_note(const Brdf& worst, double error, int bands) {
    if (error < 0.1 || bands >= 8) return {};
    return fmt::format(
        " (expected of a zonal lobe in {} bands: it is shaded as fitted, blurred; {:.1f}% at 8 "
        "bands)",
        bands, 100 * brdf_lobe(worst, 8).fit_error);
}

}  // namespace

std::string describe_terms(const ShadingPlan& plan, const Mesh& mesh, int K_used) {
    if (!plan.glossy) return fmt::format("gloss={}", plan.options.gloss);
    const GlossyShadeOptions& g = *plan.glossy;
    const int bands = sh_bands_for(K_used);
    if (!g.material_brdfs || mesh.brdf_index.empty()) {
        const double error = brdf_lobe(g.brdf, bands).fit_error;
        return fmt::format("brdf={}, zonal fit error {:.1f}% at {} bands{}", to_string(g.brdf),
                           100 * error, bands, fit_note(g.brdf, error, bands));
    }
    double worst = -1;
    Brdf worst_brdf = g.brdf;
    for (const Brdf& b : brdf_table(mesh, true, g.brdf)) {
        const double error = brdf_lobe(b, bands).fit_error;
        if (error > worst) worst = error, worst_brdf = b;
    }
    return fmt::format("brdf=materials: {}; none = {}; worst zonal fit error {:.1f}% at {} bands{}",
                       describe_brdfs(mesh), to_string(g.brdf), 100 * worst, bands,
                       fit_note(worst_brdf, worst, bands));
}

void set_brdf_choice(ShadingParams& params, const std::string& spec) {
    constexpr std::string_view kMaterials = "materials";
    const std::string_view text(spec);
    params.material_brdfs = text.starts_with(kMaterials);
    if (!params.material_brdfs) {
        params.brdf = parse_brdf(spec);  // that BRDF everywhere
    } else if (text.size() == kMaterials.size()) {
        params.brdf.reset();
    } else {
        SHPRT_CHECK(text[kMaterials.size()] == '+', invalid_argument,
                    "brdf '{}': expected materials, materials+SPEC or a BRDF spec such as ggx:0.3",
                    spec);
        params.brdf = parse_brdf(spec.substr(kMaterials.size() + 1));
    }
}

const std::vector<OptionRow<ShadingChoice>>& shading_choice_table() {
    static const std::vector<OptionRow<ShadingChoice>> table = [] {
        using C = ShadingChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "brdf", &C::brdf,
                "Glossy bakes: the BRDF lobe phong:E (normalised Phong), blinn:E (Blinn-Phong) "
                "or ggx:R (roughness), optionally :R,G,B, its specular colour (default white), "
                "for every vertex; materials+SPEC: the materials' BRDFs where the scene gives "
                "them and SPEC elsewhere (default: materials, Phong --gloss elsewhere); with --k "
                "the diffuse share");
        add_row(t, "glossy", &C::glossy,
                "matrix (default: transfer matrices, needs a glossy bake) or paper (the "
                "paper's zonal term; a glossy bake is turned into diffuse transfer)");
        add_row(t, "coeffs", &C::coeffs,
                "Deprecated here: --shading-coeffs (bake's --coeffs is the K baked)");
        add_row(t, "albedo", &C::albedo,
                "Glossy shading: R,G,B (linear, 0 to 1) overriding the diffuse and "
                "specular colours");
        add_row(t, "view", &C::view,
                "radiance (default), irradiance, or transfer (AO-like, light ignored)");
        add_row(t, "eye", &C::eye,
                "Eye position X,Y,Z for the glossy term (default: the default render "
                "camera)");
        return complete_rows(std::move(t));
    }();
    return table;
}

ShadingParams shading_params(const ShadingChoice& c, const std::optional<Sun>& sun) {
    constexpr Spelling cli = Spelling::command_line;
    ShadingParams p = c.params;
    SHPRT_CHECK(!(p.coeffs != 0 && c.coeffs), invalid_argument,
                "--coeffs {} and --shading-coeffs {}: give --shading-coeffs alone (--coeffs is "
                "its deprecated name here)",
                c.coeffs.value_or(0), p.coeffs);
    if (c.coeffs) {
        log_warn(
            "--coeffs {0} is deprecated in shading: it means K' here and K in bake; use "
            "--shading-coeffs {0}",
            *c.coeffs);
        p.coeffs = *c.coeffs;
    }
    p.view = parse_view(c.view, cli);
    p.glossy = parse_glossy_term(c.glossy, cli);
    if (!c.brdf.empty()) set_brdf_choice(p, c.brdf);
    if (!c.albedo.empty()) {
        const std::vector<double> rgb = parse_numbers(c.albedo, 3, "--albedo R,G,B");
        p.albedo = Vec3f{float(rgb[0]), float(rgb[1]), float(rgb[2])};
    }
    if (!c.eye.empty()) p.eye = parse_vec3(c.eye, "--eye");
    p.sun = sun;
    check(p, cli);
    return p;
}

}  // namespace shprt
