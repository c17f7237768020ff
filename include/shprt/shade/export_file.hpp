// `shprt export`'s choice of what a file becomes (shade/gltf_export.hpp, shade/texel_shade.hpp):
// a vertex file a glTF 2.0 binary (.glb: the mesh, its colours under the light, the transfer
// coefficients as attributes); a texel file its coefficient planes as one multi-channel EXR, or as
// standard RGBA images (PNG16, or EXR with attributes=standard) with a JSON sidecar; glossy
// matrices as their diffuse transfer M·a(n), the transfer `--glossy paper` shades
// (shade/glossy.hpp). The options as the command line types them are one table (core/options.hpp).
#pragma once

#include "shprt/core/options.hpp"
#include "shprt/light/light_setup.hpp"

#include <string>
#include <vector>

namespace shprt {

struct ExportChoice {
    int bands = 0;  // the first n bands (n² coefficients); 0: all of the file's
    double exposure = 1.0;
    std::string attributes = "custom";  // parse_gltf_attributes
    bool half = false;                  // normalized int16 coefficients
};
// One row per option, in the command line's help order.
const std::vector<OptionRow<ExportChoice>>& export_option_table();

// Exports the .shprt file `input` to `output` (.glb; .exr or .png for a texel file) under `light`.
// Every option is checked before the file is read, and the output against the inputs (one-line
// Error(invalid_argument) naming the option or the path); every file is written atomically.
// Returns the summary lines ("exported 1200 vertices, K=16, ... -> out.glb (123 bytes)\n", and
// the sun's line with a --sun).
std::string export_file(const std::string& input, const std::string& output,
                        const LightChoice& light, const ExportChoice& choice);

}  // namespace shprt
