// Options shared by the tools that draw a baked scene (`shprt render`, `shprt view`): the light
// (--light, --rotate, --window, --window-strength), the camera (--camera, --fov), --view, and the
// checks of --k, --gloss, --exposure. One definition, so that the same options give the same
// picture in every tool (the viewer's --screenshot is compared with `shprt render` in the tests).
#pragma once

#include "shprt/io/shprt_file.hpp"

#include "shprt/light/light_setup.hpp"
#include "shprt/render/camera.hpp"
#include "shprt/render/glossy.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/mesh.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace shprt::tools {

struct LightArgs {
    std::vector<std::string> lights;
    std::string sun;  // --sun X,Y,Z[,RADIUS_DEG[,R,G,B]] (light/sun.hpp), or empty
    std::string rotate, window = "none";
    double window_strength = 0;
};

// Adds --light (repeatable), --sun, --rotate, --window and --window-strength writing into `args`
// (which must outlive the parse).
void add_light_options(CLI::App& app, LightArgs& args);
// The LightSetup of the parsed options; throws Error(invalid_argument) naming a bad --sun, window
// or rotation. Light files are only read later, by prepare_light.
LightSetup light_setup_from(const LightArgs& args);
// The commands that do not draw a sun kept out of the SH sum yet (`render`, `view`, `export`):
// a one-line Error(unsupported) naming `command` when --sun was given.
void refuse_sun(const LightArgs& args, const std::string& command);

struct CameraArgs {
    std::string camera;         // "EX,EY,EZ,TX,TY,TZ" or empty (default camera)
    std::optional<double> fov;  // degrees
};

// The files a command with these light options reads: `file` (the .shprt input) and every file
// the --light specs name, for check_output_is_not_input (core/file.hpp).
std::vector<std::string> input_files(const std::string& file, const LightArgs& args);

// Adds --camera and --fov.
void add_camera_options(CLI::App& app, CameraArgs& args);
// Checks --camera and --fov without a scene (one-line Error(invalid_argument)), so that a bad
// option fails before a file is read.
void check_camera_args(const CameraArgs& args);
// The camera `shprt render` uses for these options: default_camera(mesh, aspect) without
// --camera; otherwise look_at_camera (render/camera.hpp) of the eye and target given, with clip
// planes fitted to the mesh's bounds; --fov overrides the field of view.
// `input` names the file the mesh came from in the error for a camera without a frame (a scene
// whose positions are too large for single precision).
Camera camera_from(const CameraArgs& args, const Mesh& mesh, float aspect,
                   const std::string& input);

// "radiance", "irradiance" or "transfer"; throws Error(invalid_argument) naming `name`.
ShadeView parse_view(const std::string& name);

// The shading options `shade`, `render` and `view` share: --k, --gloss, --exposure, --direct.
struct ShadingArgs {
    double k = 1.0, gloss = kDefaultGloss, exposure = 1.0;
    bool direct = false;  // shade the direct part of an interreflected bake only
};
// Adds them, with the command's own help for --exposure and --direct.
void add_shading_options(CLI::App& app, ShadingArgs& args, const std::string& exposure_help,
                         const std::string& direct_help);
// Checks --k ∈ [0, 1], --gloss ≥ 0 and --exposure > 0 (finite), naming the option.
void check_shading_args(const ShadingArgs& args);

// A diffuse texel file (docs/texels.md) is drawn per fragment without the paper's glossy term:
// one-line Error(unsupported) naming `path` for --k < 1 in the radiance view (glossy matrices per
// texel are drawn). `render` and `view`.
void check_texel_view(const std::string& path, const TransferSet& transfer, double k,
                      ShadeView view);

// Throws Error(invalid_argument) unless `path` ends in .png, .exr or .hdr (any case).
void check_image_extension(const std::string& path);

// Reads a .shprt file to shade; with `direct`, only its direct part (an interreflected bake's T_0;
// a one-line error for a file without one). `shade` and `render --direct`.
ShprtFile read_for_shading(const std::string& path, bool direct);

// Glossy shading (render/glossy.hpp): --brdf, --glossy, --albedo, shared by `shade` and `render`.
struct GlossyArgs {
    std::string brdf;               // "phong:E", "blinn:E", "ggx:R", or empty
    std::string glossy = "matrix";  // "matrix" (transfer matrices) or "paper" (the zonal term)
    std::string albedo;             // "R,G,B" or empty
};
// Without `with_albedo` the command has its own --albedo (`view`, whose bake options have one) and
// fills args.albedo itself.
void add_glossy_options(CLI::App& app, GlossyArgs& args, bool with_albedo = true);
// Checks --brdf, --glossy and --albedo before any file is read (one-line Error).
void check_glossy_args(const GlossyArgs& args);

// How a file read with these options is shaded: `glossy` set = the matrix term (shade_glossy);
// unset = the diffuse/paper path (shade_vertices, the GL renderer), with `file.transfer` turned
// into diffuse transfer first when it is a glossy bake shaded with --glossy paper (whose Phong
// exponent then replaces `gloss`). A glossy file without --brdf is shaded with its materials' BRDFs
// (GlossyShadeOptions::material_brdfs; `gloss`'s Phong lobe where a material gives none). A
// diffuse file with --brdf (unless --glossy paper), or a glossy file without --brdf, --glossy
// paper or material BRDFs, is a one-line Error(invalid_argument) naming `path`.
struct GlossyPlan {
    std::optional<GlossyShadeOptions> glossy;
};
// "brdf=phong:16, zonal fit error 47.5% at 5 bands": what `shade` and `render` print.
std::string describe_brdf(const Brdf& brdf, int K);
// describe_brdf of options.brdf, or with material BRDFs: "brdf=materials: phong:32 (1200 vertices),
// none (8 vertices); none = phong:16; worst zonal fit error 12.0% at 5 bands".
std::string describe_glossy(const Mesh& mesh, const GlossyShadeOptions& options, int K);

GlossyPlan plan_glossy(const GlossyArgs& args, const std::string& path, ShprtFile& file, double k,
                       double& gloss);

}  // namespace shprt::tools
