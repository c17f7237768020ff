// The viewer's Dear ImGui panel. It edits a PanelState; the window loop (viewer_app.cpp) reads the
// state every frame and reacts to what changed (new light source, light rotation reset, …). Its
// shading is one ShadingParams that the widgets edit and PanelShading resolves as the command
// line does. No OpenGL and no GLFW here: only ImGui widgets and the library's shading.
#pragma once

#include "shprt/render/renderer.hpp"
#include "shprt/shade/params.hpp"

#include <optional>
#include <string>
#include <vector>

namespace shprt::viewer {

// One entry of the light menu: a label and the specs that are summed (light/light.hpp syntax).
struct LightChoice {
    std::string label;
    std::vector<std::string> specs;
};

// The menu: builtin, constant, gradient, sun, then every --light spec of the command line on its
// own, then (when there are several) their sum as the command line gives it.
std::vector<LightChoice> light_choices(const std::vector<std::string>& command_line_specs);

struct PanelState {
    // Scene (read-only in the panel).
    std::string scene_label;  // file name and counts
    std::string gl_label;     // OpenGL version and renderer
    int K_file = 1;           // K of the transfer; the K' slider runs over 1..K_max
    int K_max = 1;            // min(K of the transfer, K of the light)

    // Shading: the same value `shprt render` is given (shade/params.hpp), edited in place by the
    // widgets — view, exposure, k, gloss, the BRDF and the materials' BRDFs, the colour override,
    // K′ (params.coeffs, 1..K_max: the panel never shows 0) and the direct part. The window
    // resolves it as the command line does (PanelShading). The paper's term is not offered: it
    // would need the transfer turned into vectors and uploaded again; a window opened with
    // --glossy paper shows it, with the gloss slider.
    ShadingParams params;
    std::string shading_error;  // the last edit check() or the resolution refused ("" = none)
    bool wireframe = false;
    bool background = false;
    bool has_direct = false;    // the transfer is interreflected: params.direct shows its T_0
    bool diffuse_only = false;  // diffuse texel transfer: drawn per fragment without glossy term
    // Glossy transfer matrices (shade/glossy.hpp): the BRDF replaces the Phong "gloss" slider.
    bool matrices = false;
    // The scene's materials give BRDFs (Mesh::brdfs): params.material_brdfs shades their
    // vertices with them, params.brdf then is the BRDF of the vertices whose material gives none.
    bool has_material_brdfs = false;
    std::string material_label;    // describe_brdfs: the materials' BRDFs and their vertices
    Vec3f albedo_colour{1, 1, 1};  // the colour override's colour while it is off
    std::string transfer_label;    // what the GPU holds: bytes per vertex, the CPCA settings
    std::string sun_label;         // --sun: how the sun kept out of the SH sum is drawn (or empty)

    // Light.
    std::vector<LightChoice> choices;
    int choice = 0;          // index into choices, or −1 for the typed spec
    std::string typed_spec;  // the text field
    int window = 0;          // WindowKind: none, hann, lanczos, sloan
    float window_strength = 0;
    std::string light_error;  // last failure to make a light, shown in red ("" = none)

    // A probe-lit object (--object, docs/probes.md): its position, dragged here or moved with the
    // arrow keys (horizontally, relative to the camera) and Page Up/Down (vertically).
    bool has_object = false;
    std::string object_label;  // file and vertex count
    float object_position[3] = {0, 0, 0};
    std::string object_status;  // shading time; "outside the probe grid" when clamped
    // Camera.
    int camera_mode = 0;  // CameraMode: 0 orbit, 1 fly
    float fly_speed = 1;  // world units per second

    // Display.
    bool vsync = true;
    int msaa = 1;                 // samples asked for: 1, 2, 4 or 8
    int msaa_samples = 1;         // samples the target has (the implementation may support fewer)
    float frame_ms = 0, fps = 0;  // smoothed, measured by the loop

    // Bake shown while it refines.
    bool baking = false;
    float bake_fraction = 0;
    std::string bake_status;

    // Requests from the panel to the loop, set for one frame.
    bool light_source_changed = false;  // choice, typed spec or window changed
    bool reset_light_rotation = false;
    bool reset_camera = false;
    bool camera_mode_changed = false;
    bool direct_changed = false;  // params.direct toggled
};

// Draws the panel (inside an ImGui frame) and updates `state`.
void draw_panel(PanelState& state);

// The panel's params as the renderer draws them, by the path `shprt render` takes
// (resolve_shading, then draw_settings; render/renderer.hpp) without reading the file again:
// check(params), then plan_shading against the transfer shown (the file the window keeps whole,
// or its direct part when params.direct) and draw_settings. Resolved again only when the params
// differ from the last ones tried. An edit that check() or the resolution refuses (a value typed
// past a slider's range) keeps the last good settings, and its one-line error in error().
class PanelShading {
public:
    // `source` names the file in errors. The first params must resolve (the command line's,
    // already resolved by `shprt view`): their error is thrown.
    void update(const ShadingParams& params, const Mesh& mesh, const TransferSet& shown,
                const std::string& source);
    const ShadingParams& params() const { return m_params; }  // the last good ones
    const ShadingPlan& plan() const { return m_plan; }
    // The shading fields of DrawSettings (k, gloss, K′, view, the BRDFs, the colour); the
    // camera and the display's fields are the caller's.
    const DrawSettings& settings() const { return m_settings; }
    const std::string& error() const { return m_error; }

private:
    std::optional<ShadingParams> m_tried;
    ShadingParams m_params;
    ShadingPlan m_plan;
    DrawSettings m_settings;
    std::string m_error;
};

}  // namespace shprt::viewer
