// The viewer's Dear ImGui panel. It edits a PanelState; the window loop (viewer_app.cpp) reads the
// state every frame and reacts to what changed (new light source, light rotation reset, …). No
// OpenGL and no GLFW here: only ImGui widgets.
#pragma once

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

    // Shading.
    float exposure = 1;
    float k = 1;       // diffuse share
    float gloss = 16;  // Phong exponent
    int K_used = 0;    // 1..K_max (the panel never shows 0)
    int view = 0;      // ShadeView: 0 radiance, 1 irradiance, 2 transfer (AO-like)
    bool wireframe = false;
    bool background = false;
    bool has_direct = false;    // the transfer is interreflected and keeps its direct part
    bool direct_only = false;   // show the direct part (T_0) instead of T_0 + … + T_N
    bool diffuse_only = false;  // diffuse texel transfer: drawn per fragment without glossy term
    // Glossy transfer matrices (shade/glossy.hpp): the BRDF replaces the Phong "gloss" slider.
    bool matrices = false;
    // The scene's materials give BRDFs (Mesh::brdfs): `material_brdfs` shades their vertices
    // with them, the combo below then sets the BRDF of the vertices whose material gives none.
    bool has_material_brdfs = false;
    bool material_brdfs = false;
    std::string material_label;     // describe_brdfs: the materials' BRDFs and their vertices
    int brdf_model = 0;             // BrdfModel: 0 phong, 1 blinn, 2 ggx
    float brdf_parameter = 16;      // exponent (phong, blinn) or roughness (ggx)
    float specular[3] = {1, 1, 1};  // the BRDF's specular colour (Brdf::specular)
    bool override_albedo = false;   // --albedo: one colour for the diffuse and specular parts
    float albedo[3] = {1, 1, 1};
    std::string transfer_label;  // what the GPU holds: bytes per vertex, the CPCA settings
    std::string sun_label;       // --sun: how the sun kept out of the SH sum is drawn (or empty)

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
    bool direct_changed = false;  // direct_only toggled
};

// Draws the panel (inside an ImGui frame) and updates `state`.
void draw_panel(PanelState& state);

}  // namespace shprt::viewer
