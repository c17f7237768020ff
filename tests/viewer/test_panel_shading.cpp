// The viewer's panel shades as the command line does (panel.hpp, PanelShading): the same
// ShadingParams, given to the panel and to `shprt render`'s path (resolve_shading, then
// draw_settings), give the same DrawSettings and the same pixels — the materials' BRDFs with a
// GGX lobe elsewhere included, which the panel edits as two fields and the command line types as
// `--brdf materials+ggx:0.25`. And an edit past a limit is check()'s one-line error, the last good
// shading kept.
#include "panel.hpp"

#include "render/render_test_util.hpp"
#include "shprt/io/shprt_file.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>

namespace shprt::viewer {
namespace {

// A glossy bake of quad_box whose floor's material gives GGX 0.4 and whose box gives none.
const ShprtFile& glossy_file() {
    static const std::unique_ptr<ShprtFile> file = [] {
        auto f = std::make_unique<ShprtFile>();
        f->mesh = test::quad_box_with_glossy_floor();
        BakeOptions options;
        options.transfer = TransferKind::glossy;
        options.K = 9;
        options.samples = 64;
        f->transfer = bake(f->mesh, options);
        return f;
    }();
    return *file;
}

// `shprt render`'s path: the file resolved (a copy: resolve_shading narrows it), then drawn.
DrawSettings render_path(const ShadingParams& params) {
    ShprtFile file = glossy_file();
    check(params, Spelling::command_line);
    const ShadingPlan plan = resolve_shading(params, file, "glossy.shprt", Spelling::command_line);
    return draw_settings(plan, params.view);
}

// The panel's path: its params, edited in place, resolved by PanelShading.
DrawSettings panel_path(const ShadingParams& params) {
    PanelState panel;
    panel.params = params;
    PanelShading shading;
    shading.update(panel.params, glossy_file().mesh, glossy_file().transfer, "glossy.shprt");
    EXPECT_EQ(shading.error(), "");
    return shading.settings();
}

void expect_same_shading(const DrawSettings& a, const DrawSettings& b) {
    EXPECT_EQ(a.k, b.k);
    EXPECT_EQ(a.gloss, b.gloss);
    EXPECT_EQ(a.brdf, b.brdf);
    EXPECT_EQ(a.material_brdfs, b.material_brdfs);
    EXPECT_EQ(a.albedo, b.albedo);
    EXPECT_EQ(a.K_used, b.K_used);
    EXPECT_EQ(a.view, b.view);
}

ShadingParams materials_and_ggx() {
    ShadingParams p;
    p.k = 0.3;
    p.brdf = parse_brdf("ggx:0.25");  // the box's; the floor keeps its material's GGX 0.4
    p.material_brdfs = true;
    return p;
}

TEST(PanelShading, GivesTheCommandLinesDrawSettings) {
    ShadingChoice everywhere;  // `shprt render --brdf blinn:40 --k 0.5`: that BRDF everywhere
    everywhere.brdf = "blinn:40";
    everywhere.params.k = 0.5;
    ShadingParams colour = materials_and_ggx();
    colour.albedo = Vec3f{0.8f, 0.4f, 0.2f};
    colour.coeffs = 4;
    colour.view = ShadeView::irradiance;
    colour.material_brdfs = false;
    const ShadingParams cases[] = {ShadingParams{}, shading_params(everywhere, std::nullopt),
                                   materials_and_ggx(), colour};
    for (const ShadingParams& params : cases) {
        SCOPED_TRACE(::testing::Message()
                     << "k " << params.k << ", materials " << params.material_brdfs << ", brdf "
                     << (params.brdf ? to_string(*params.brdf) : "unset"));
        expect_same_shading(panel_path(params), render_path(params));
    }
    EXPECT_FALSE(cases[1].material_brdfs) << "--brdf means that BRDF everywhere";
    // … and --brdf materials+SPEC the panel's materials with a lobe elsewhere; materials alone
    // the default.
    ShadingChoice mixed;
    mixed.brdf = "materials+ggx:0.25";
    mixed.params.k = 0.3;
    EXPECT_EQ(shading_params(mixed, std::nullopt), materials_and_ggx());
    ShadingChoice typed;
    typed.brdf = "materials";
    EXPECT_EQ(shading_params(typed, std::nullopt), ShadingParams{});
    typed.brdf = "materials,ggx:0.25";
    EXPECT_THROW(shading_params(typed, std::nullopt), Error);
    const DrawSettings both = panel_path(materials_and_ggx());
    EXPECT_TRUE(both.material_brdfs);
    EXPECT_EQ(both.brdf, parse_brdf("ggx:0.25"));
    // No BRDF: the materials' and gloss's Phong lobe elsewhere, as `shprt render` without --brdf.
    const DrawSettings plain = panel_path(ShadingParams{});
    EXPECT_TRUE(plain.material_brdfs);
    EXPECT_EQ(plain.brdf, (Brdf{BrdfModel::phong, kDefaultGloss}));
}

TEST(PanelShading, DrawsTheCommandLinesPixelsWithMaterialsAndGgxElsewhere) {
    REQUIRE_GL(context);
    const ShprtFile& file = glossy_file();
    const ShLight light = test::smooth_light(9, 9, 4);
    Camera camera;
    camera.eye = {1.2f, 1.4f, 2.2f};
    camera.target = {0, 0.3f, 0};
    camera.near_plane = 0.1f;
    const auto image = [&](DrawSettings settings) {
        settings.camera = camera;
        return render_image_in_current_context(file.mesh, file.transfer, light, settings, 48, 36, 1)
            .rgb;
    };
    const std::vector<float> panel = image(panel_path(materials_and_ggx()));
    EXPECT_EQ(panel, image(render_path(materials_and_ggx())));
    // Both parts reach the pixels: the box's GGX (against gloss's Phong lobe there) and the
    // floor's material (against GGX 0.25 everywhere).
    ShadingParams phong_elsewhere = materials_and_ggx();
    phong_elsewhere.brdf.reset();
    EXPECT_NE(panel, image(panel_path(phong_elsewhere)));
    ShadingParams ggx_everywhere = materials_and_ggx();
    ggx_everywhere.material_brdfs = false;
    EXPECT_NE(panel, image(panel_path(ggx_everywhere)));
}

TEST(PanelShading, AnEditPastALimitIsCheckedAndTheLastGoodShadingStays) {
    const ShprtFile& file = glossy_file();
    PanelState panel;
    panel.params = materials_and_ggx();
    PanelShading shading;
    shading.update(panel.params, file.mesh, file.transfer, "glossy.shprt");
    ASSERT_EQ(shading.error(), "");
    panel.params.k = 1.5;  // typed into the k slider (Ctrl+click), past its range
    shading.update(panel.params, file.mesh, file.transfer, "glossy.shprt");
    EXPECT_NE(shading.error().find("--k 1.5"), std::string::npos) << shading.error();
    EXPECT_EQ(shading.error().find('\n'), std::string::npos) << "one line";
    EXPECT_EQ(shading.settings().k, 0.3) << "the last good shading stays";
    EXPECT_EQ(shading.params().k, 0.3);
    panel.params.material_brdfs = false;  // and the BRDF unset: nothing shades the matrices
    panel.params.k = 0.6;
    panel.params.brdf.reset();
    shading.update(panel.params, file.mesh, file.transfer, "glossy.shprt");
    EXPECT_NE(shading.error().find("the materials' BRDFs are off"), std::string::npos)
        << shading.error();
    panel.params.brdf = parse_brdf("phong:8");
    shading.update(panel.params, file.mesh, file.transfer, "glossy.shprt");
    EXPECT_EQ(shading.error(), "");
    EXPECT_EQ(shading.settings().k, 0.6);
    // The first params must resolve: no good shading to keep.
    ShadingParams bad;
    bad.exposure = 0;
    EXPECT_THROW(PanelShading().update(bad, file.mesh, file.transfer, "glossy.shprt"), Error);
}

}  // namespace
}  // namespace shprt::viewer
