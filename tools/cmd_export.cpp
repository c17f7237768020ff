// `shprt export FILE.shprt -o SCENE.glb [--light L ...] [--sun S] [--bands n] [--half] [--exposure
// E]`: the mesh, its colours baked under the light and the transfer coefficients as a glTF 2.0
// binary (shade/gltf_export.hpp); a glossy bake as its matrices' diffuse transfer; a texel file as
// its coefficient planes. Thin: parses the options, calls export_file (shade/export_file.hpp, which
// chooses what the file becomes), prints its lines.
#include "common/command.hpp"
#include "common/option_table.hpp"

#include "shprt/light/light_setup.hpp"
#include "shprt/shade/export_file.hpp"

#include <cstdio>
#include <memory>
#include <string>

namespace shprt::tools {
namespace {

struct ExportArgs {
    std::string input, output;
    LightChoice light;  // light/light_setup.hpp, as `shprt shade` and `shprt render`
    ExportChoice options;
};

const bool export_registered = register_command(
    {"export", "Export a baked scene as glTF (.glb): mesh, baked colours, transfer attributes", 55,
     [](CLI::App& app) {
         auto args = std::make_shared<ExportArgs>();
         app.add_option("file", args->input, "Baked .shprt file")->required();
         app.add_option("-o,--output", args->output,
                        "Output .glb (texel files: .exr coefficient planes, or .png images)")
             ->required();
         add_table_options(app, light_option_table(), args->light);
         add_table_options(app, export_option_table(), args->options);
         app.callback([args] {
             const ExportArgs& a = *args;
             std::fputs(export_file(a.input, a.output, a.light, a.options).c_str(), stdout);
         });
     }});

}  // namespace
}  // namespace shprt::tools
