// The viewer's ImGui panel (panel.hpp).
#include "panel.hpp"

#include <imgui.h>
#include <imgui_stdlib.h>

#include "shprt/core/error.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

namespace shprt::viewer {
namespace {

const char* const kViewNames[] = {"radiance", "irradiance", "transfer (AO-like)"};
const char* const kWindowNames[] = {"none", "hann", "lanczos", "sloan"};
const char* const kBrdfNames[] = {"phong", "blinn-phong", "ggx"};

bool choice_label(void* data, int index, const char** out) {
    const auto* choices = static_cast<const std::vector<LightChoice>*>(data);
    *out = (*choices)[static_cast<std::size_t>(index)].label.c_str();
    return true;
}

void help_marker(const char* text) {
    ImGui::SameLine();
    ImGui::TextDisabled("(?)");
    if (ImGui::IsItemHovered()) {
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
        ImGui::TextUnformatted(text);
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
    }
}

void light_section(PanelState& s) {
    int choice = std::max(s.choice, 0);
    if (ImGui::Combo("light", &choice, choice_label, &s.choices,
                     static_cast<int>(s.choices.size()))) {
        s.choice = choice;
        s.light_source_changed = true;
    }
    ImGui::InputTextWithHint("##spec", "spec, e.g. sun:1,2,1 or sky.hdr", &s.typed_spec);
    ImGui::SameLine();
    if (ImGui::Button("apply") && !s.typed_spec.empty()) {
        s.choice = -1;
        s.light_source_changed = true;
    }
    if (s.choice < 0) ImGui::TextDisabled("typed: %s", s.typed_spec.c_str());
    if (ImGui::Combo("window", &s.window, kWindowNames, IM_ARRAYSIZE(kWindowNames)))
        s.light_source_changed = true;
    if (s.window != 0 && ImGui::SliderFloat("strength", &s.window_strength, 0.0f, 64.0f, "%.1f"))
        s.light_source_changed = true;
    if (s.window != 0)
        help_marker("0 = the window's default (width for hann/lanczos, lambda for sloan)");
    if (!s.sun_label.empty()) {
        ImGui::TextWrapped("%s", s.sun_label.c_str());
        help_marker(
            "--sun: the sun's direct light is drawn per pixel with a shadow map whose penumbra "
            "follows the sun's radius, beside the SH sky; its bounced light comes from an "
            "interreflected file's T - T0. It turns with the light: Shift+drag moves the sun, "
            "its shadows and its bounces in the same frame.");
    }
    if (ImGui::Button("reset rotation")) s.reset_light_rotation = true;
    help_marker(
        "Shift+drag or Ctrl+drag in the picture turns the light (an SH rotation of the "
        "coefficients): left/right about the vertical axis, up/down about the screen's "
        "horizontal axis.");
    if (!s.light_error.empty())
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", s.light_error.c_str());
}

// The probe-lit object: where it is (drag the numbers, or the keys in the help).
void object_section(PanelState& s) {
    ImGui::TextWrapped("%s", s.object_label.c_str());
    ImGui::DragFloat3("position", s.object_position, 0.01f, -1e4f, 1e4f, "%.2f");
    help_marker(
        "Drag the numbers; or hold G and drag the object in the window (left button: over the "
        "floor, right button: up and down); or move it with the arrow keys (horizontally, "
        "relative to the camera) and Page Up/Page Down (vertically). It is lit per vertex from "
        "the file's "
        "transfer probes under the current light, which Shift+drag still turns.");
    if (!s.object_status.empty()) ImGui::TextWrapped("%s", s.object_status.c_str());
}

// A double slider over [lo, hi] (the params' fields are doubles).
bool slider(const char* label, double& value, double lo, double hi, const char* format,
            ImGuiSliderFlags flags = 0) {
    return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, format, flags);
}

// A colour picker over a Vec3f (linear RGB).
bool colour(const char* label, Vec3f& c) {
    float rgb[3] = {c.x, c.y, c.z};
    if (!ImGui::ColorEdit3(label, rgb, ImGuiColorEditFlags_Float)) return false;
    c = Vec3f{rgb[0], rgb[1], rgb[2]};
    return true;
}

// Glossy matrices: the BRDF's zonal lobe and the colour override, and what the GPU holds.
void brdf_controls(PanelState& s) {
    ShadingParams& p = s.params;
    if (s.has_material_brdfs) {
        ImGui::Checkbox("material BRDFs", &p.material_brdfs);
        help_marker(
            "The BRDFs the scene's materials give (shininess or roughness, and specular colour). "
            "The BRDF below is then the one of the vertices whose material gives none.");
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped("%s", s.material_label.c_str());
        ImGui::PopStyleColor();
    }
    // Unset, the BRDF is gloss's Phong lobe (ShadingParams::brdf): the same, made editable.
    if (!p.brdf) p.brdf = Brdf{BrdfModel::phong, p.gloss};
    Brdf& brdf = *p.brdf;
    int model = static_cast<int>(brdf.model);
    if (ImGui::Combo("brdf", &model, kBrdfNames, IM_ARRAYSIZE(kBrdfNames))) {
        brdf.model = static_cast<BrdfModel>(model);
        // A sensible value for the new model's parameter.
        brdf.parameter = brdf.model == BrdfModel::ggx ? 0.3 : 16.0;
    }
    if (brdf.model == BrdfModel::ggx)
        slider("roughness", brdf.parameter, 0.05, 1.0, "%.2f", ImGuiSliderFlags_AlwaysClamp);
    else
        slider("exponent", brdf.parameter, 0.0, 256.0, "%.1f",
               ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
    colour("specular", brdf.specular);
    help_marker(
        "Glossy transfer matrices: exit radiance k·albedo/pi·E + (1-k)·specular·<BRDF lobe "
        "rotated to the reflected view, M·L>. The lobe is fitted with the file's bands (its "
        "error grows as the lobe narrows). Specular: white for a dielectric's highlight, the "
        "metal's colour for a metal.");
    bool override_albedo = p.albedo.has_value();
    if (ImGui::Checkbox("albedo override", &override_albedo)) {
        if (override_albedo)
            p.albedo = s.albedo_colour;
        else
            s.albedo_colour = *std::exchange(p.albedo, std::nullopt);
    }
    help_marker("One colour for both the diffuse and the specular part (--albedo).");
    if (p.albedo) colour("albedo", *p.albedo);
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", s.transfer_label.c_str());
    ImGui::PopStyleColor();
}

void shading_section(PanelState& s) {
    ShadingParams& p = s.params;
    int view = static_cast<int>(p.view);
    if (ImGui::Combo("view", &view, kViewNames, IM_ARRAYSIZE(kViewNames)))
        p.view = static_cast<ShadeView>(view);
    slider("exposure", p.exposure, 0.01, 100.0, "%.3f", ImGuiSliderFlags_Logarithmic);
    if (s.diffuse_only) {
        ImGui::TextDisabled("k = 1 (diffuse)");
        help_marker(
            "Texel transfer is shaded per fragment without the glossy term; under a sun kept "
            "out of the SH sum (--sun), diffuse transfer is shaded without the paper's glossy "
            "term, which is not linear in the light.");
    } else {
        slider("k (diffuse)", p.k, 0.0, 1.0, "%.2f");
        help_marker("L = k·L_D + (1-k)·L_S: 1 = pure diffuse, 0 = pure glossy");
        if (s.matrices)
            brdf_controls(s);
        else
            slider("gloss", p.gloss, 1.0, 256.0, "%.1f", ImGuiSliderFlags_Logarithmic);
    }
    p.coeffs = std::clamp(p.coeffs, 1, std::max(s.K_max, 1));
    ImGui::SliderInt("K'", &p.coeffs, 1, std::max(s.K_max, 1), "%d", ImGuiSliderFlags_AlwaysClamp);
    help_marker(
        "Basis size used: the first K' coefficients of transfer and light (truncation; "
        "only full bands n² are rotation invariant).");
    ImGui::Checkbox("wireframe", &s.wireframe);
    ImGui::SameLine();
    ImGui::Checkbox("background", &s.background);
    if (s.has_direct) {
        if (ImGui::Checkbox("direct light only", &p.direct)) s.direct_changed = true;
        help_marker(
            "An interreflected bake keeps its direct (shadowed) transfer T_0: on, the light "
            "that reaches each vertex straight from the sky; off, with the light that bounced "
            "off the scene (T_0 + ... + T_N).");
    }
    if (!s.shading_error.empty())
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", s.shading_error.c_str());
}

void camera_section(PanelState& s) {
    const int before = s.camera_mode;
    ImGui::RadioButton("orbit", &s.camera_mode, 0);
    ImGui::SameLine();
    ImGui::RadioButton("fly", &s.camera_mode, 1);
    if (s.camera_mode != before) s.camera_mode_changed = true;
    ImGui::SameLine();
    if (ImGui::Button("reset")) s.reset_camera = true;
    help_marker(
        "Drag: turn (orbit around the target / look around). Right or middle drag: pan. "
        "Wheel: zoom (orbit) or move forward (fly). W/A/S/D, Q/E: move. Tab: orbit/fly.");
    ImGui::SliderFloat("speed", &s.fly_speed, 0.01f, 100.0f, "%.2f /s",
                       ImGuiSliderFlags_Logarithmic);
}

void display_section(PanelState& s) {
    static const int kSamples[] = {1, 2, 4, 8};
    const char* const names[] = {"off", "2x", "4x", "8x"};
    int index = 0;
    for (int i = 0; i < IM_ARRAYSIZE(kSamples); ++i)
        if (kSamples[i] == s.msaa) index = i;
    if (ImGui::Combo("MSAA", &index, names, IM_ARRAYSIZE(names))) s.msaa = kSamples[index];
    if (s.msaa_samples != s.msaa) {
        ImGui::SameLine();
        ImGui::TextDisabled("(%d here)", s.msaa_samples);
    }
    help_marker(
        "Samples per pixel of the float target. On a software rasteriser (llvmpipe) 4x MSAA "
        "more than halves the frame rate, so the window starts without it there.");
    ImGui::TextWrapped("%s", s.gl_label.c_str());
}

}  // namespace

std::vector<LightChoice> light_choices(const std::vector<std::string>& command_line_specs) {
    std::vector<LightChoice> out = {
        {"builtin (sky + sun)", {"builtin"}},
        {"constant (white sky)", {"constant"}},
        {"gradient (sky)", {"gradient"}},
        {"sun (overhead)", {"sun:0.3,1,0.2"}},
    };
    for (const auto& spec : command_line_specs) out.push_back({spec, {spec}});
    if (command_line_specs.size() > 1) out.push_back({"command line (sum)", command_line_specs});
    return out;
}

void PanelShading::update(const ShadingParams& params, const Mesh& mesh, const TransferSet& shown,
                          const std::string& source) {
    if (m_tried == params) return;
    const bool first = !m_tried;
    m_tried = params;
    try {
        check(params, Spelling::command_line);
        m_plan = plan_shading(params, mesh, shown, source, Spelling::command_line);
        m_settings = draw_settings(m_plan, params.view);
        m_params = params;
        m_error.clear();
    } catch (const Error& e) {
        if (first) throw;
        m_error = e.what();  // the last good settings stay
    }
}

void draw_panel(PanelState& s) {
    s.light_source_changed = s.reset_light_rotation = s.reset_camera = s.camera_mode_changed =
        s.direct_changed = false;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.85f);
    if (!ImGui::Begin("shprt view")) {
        ImGui::End();
        return;
    }
    ImGui::TextWrapped("%s", s.scene_label.c_str());
    ImGui::Text("%.1f frames/s, %.2f ms/frame", s.fps, s.frame_ms);
    ImGui::SameLine();
    ImGui::Checkbox("vsync", &s.vsync);
    if (s.baking || !s.bake_status.empty()) {
        char overlay[32];
        std::snprintf(overlay, sizeof overlay, "%.0f %%", 100.0 * s.bake_fraction);
        if (s.baking) ImGui::ProgressBar(s.bake_fraction, ImVec2(-1, 0), overlay);
        if (!s.bake_status.empty()) ImGui::TextWrapped("%s", s.bake_status.c_str());
    }
    if (ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) light_section(s);
    if (ImGui::CollapsingHeader("Shading", ImGuiTreeNodeFlags_DefaultOpen)) shading_section(s);
    if (s.has_object && ImGui::CollapsingHeader("Object", ImGuiTreeNodeFlags_DefaultOpen))
        object_section(s);
    if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) camera_section(s);
    if (ImGui::CollapsingHeader("Display")) display_section(s);
    ImGui::End();
}

}  // namespace shprt::viewer
