// Options shared by the tools that shade or draw a baked scene (`shprt shade`, `render`, `view`,
// `export`): the light (--light, --sun, --rotate, --window, --window-strength), the camera
// (--camera, --fov) and the shading (ShadingParams, shade/params.hpp). One definition, so that the
// same options give the same picture in every tool (the viewer's --screenshot is compared with
// `shprt render` in the tests).
#pragma once

#include "shprt/io/shprt_file.hpp"

#include "shprt/light/light_setup.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/params.hpp"

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

// The files a command with these light options reads: `file` (the .shprt input) and every file
// the --light specs name, for check_output_is_not_input (core/file.hpp).
std::vector<std::string> input_files(const std::string& file, const LightArgs& args);

// Adds --camera and --fov (shade/camera.hpp: check and camera_from take the choice).
void add_camera_options(CLI::App& app, CameraChoice& choice);

// The shading options (shade/params.hpp's ShadingParams) as the command line spells them. Every
// command that shades has --k, --gloss, --exposure, --direct, --brdf, --glossy and --coeffs (K′);
// the `extra` ones where the command has them.
struct ShadingArgs {
    ShadingParams params;  // the numbers and flags, parsed straight in (shading_option_table)
    std::string brdf, glossy = "matrix", albedo, view = "radiance", eye;
    // K′ is --shading-coeffs (params.coeffs), or the deprecated --coeffs of `shade` and `render`
    // (in `bake` and `view --bake`, --coeffs is the K baked).
    std::optional<int> deprecated_coeffs;
};
enum ShadingExtra : unsigned {
    kViewOption = 1,
    kEyeOption = 2,
    kSunSamplesOption = 4,
    kAlbedoOption = 8,
    kCoeffsOption = 16,            // --shading-coeffs
    kDeprecatedCoeffsOption = 32,  // --coeffs as well, which says it is deprecated
};
// Adds them, with the command's own help for --exposure and --direct.
void add_shading_options(CLI::App& app, ShadingArgs& args, unsigned extra,
                         const std::string& exposure_help, const std::string& direct_help);
// The parsed options, with the light's --sun (light_setup_from), as ShadingParams checked
// (shade/params.hpp: one line naming the option) before any file is read. The deprecated --coeffs
// gives one warning line, and with --shading-coeffs an error.
ShadingParams shading_params(const ShadingArgs& args, const LightSetup& light);

}  // namespace shprt::tools
