// The shading options of the tools that shade or draw a baked scene (`shprt shade`, `render`,
// `view`): ShadingChoice (shade/params.hpp), registered by walking its two tables, with the
// command's own help for --exposure and --direct. The light (light_option_table), the camera
// (camera_option_table) and the object (object_option_table) are registered from their tables
// alone. One definition, so that the same options give the same picture in every tool (the
// viewer's --screenshot is compared with `shprt render` in the tests).
#pragma once

#include "shprt/shade/params.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace shprt::tools {

// Every command that shades has --k, --gloss, --exposure, --direct, --brdf and --glossy; the
// `extra` ones where the command has them.
enum ShadingExtra : unsigned {
    kViewOption = 1,
    kEyeOption = 2,
    kSunSamplesOption = 4,
    kAlbedoOption = 8,
    kCoeffsOption = 16,            // --shading-coeffs
    kDeprecatedCoeffsOption = 32,  // --coeffs as well, which says it is deprecated
};
// Adds them, writing into `choice` (which must outlive the parse).
void add_shading_options(CLI::App& app, ShadingChoice& choice, unsigned extra,
                         const std::string& exposure_help, const std::string& direct_help);

}  // namespace shprt::tools
