// `shprt export FILE.shprt -o SCENE.glb [--light L ...] [--sun S] [--bands n] [--half] [--exposure
// E]`: the mesh, its colours baked under the light and the transfer coefficients as a glTF 2.0
// binary (shade/gltf_export.hpp); a glossy bake as its matrices' diffuse transfer. Thin: checks
// the options, reads the file, calls write_glb.
#include "common/command.hpp"
#include "common/shading_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/gltf_export.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

struct ExportArgs {
    std::string input, output;
    LightArgs light;  // common/shading_options.hpp, as `shprt shade` and `shprt render`
    int bands = 0;
    double exposure = 1.0;
    bool half = false;
    std::string attributes = "custom";
};

void run(const ExportArgs& a) {
    const auto start = std::chrono::steady_clock::now();
    const std::string ext = lower_extension(a.output);
    const bool image = ext == ".exr" || ext == ".png";  // texel files only
    SHPRT_CHECK(ext == ".glb" || image, invalid_argument,
                "{}: the output must be a binary glTF file (.glb), or .exr or .png for a texel "
                "file",
                a.output);
    SHPRT_CHECK(a.bands >= 0 && a.bands <= kMaxComputeBands, invalid_argument,
                "--bands {}: must be 1 to {} (0 = all)", a.bands, kMaxComputeBands);
    GltfExportOptions options;
    options.light = light_setup_from(a.light);
    options.half = a.half;
    options.attributes = parse_gltf_attributes(a.attributes);
    SHPRT_CHECK(a.exposure > 0 && std::isfinite(a.exposure), invalid_argument,
                "--exposure {}: must be positive", a.exposure);
    options.exposure = static_cast<float>(a.exposure);
    check_output_is_not_input(a.output, input_files(a.input, a.light));
    check_output_writable(a.output);  // a directory, a device: refused before the work

    ShprtFile file = read_shprt(a.input);
    if (a.bands > 0) {
        options.K = sh_count(a.bands);
        SHPRT_CHECK(options.K <= file.transfer.layout.K, invalid_argument,
                    "--bands {}: {} has K = {}, fewer than {} coefficients", a.bands, a.input,
                    file.transfer.layout.K, options.K);
    }
    // glTF's attributes and the texel planes carry vectors: glossy matrices go as their diffuse
    // part t = M·a(n), the transfer `--glossy paper` shades (shade/glossy.hpp).
    const bool matrices = is_glossy_matrix(file.transfer.layout);
    if (matrices) file.transfer = glossy_to_diffuse(file.mesh, file.transfer);
    const char* from_matrices = matrices ? ", the glossy matrices' diffuse transfer M·a(n)" : "";
    const bool texel = is_texel(file.transfer.layout);
    SHPRT_CHECK(texel == image, invalid_argument, "{}: {}", a.output,
                texel ? "a texel file exports its coefficient planes as .exr, or as standard "
                        "images (.png, or .exr with --attributes standard)"
                      : ".exr and .png export is for texel files (bake with --domain texel)");
    // Standard images: RGBA PNG16 or EXR, four coefficients each, with a JSON sidecar (a PNG
    // has no other layout); else the one multi-channel EXR.
    if (texel && (ext == ".png" || options.attributes == GltfAttributes::standard)) {
        const std::vector<std::string> files =
            texel_coefficient_image_paths(a.output, file.transfer.layout);
        for (const std::string& f : files) {
            check_output_is_not_input(f, input_files(a.input, a.light));
            check_output_writable(f);
        }
        write_texel_coefficient_images(a.output, file.transfer);
        std::uintmax_t bytes = 0;
        for (const std::string& f : files) bytes += std::filesystem::file_size(f);
        std::printf(
            "exported %zu texels of %dx%d, K=%d x %d channel(s), %s%s -> %zu %s images "
            "(%s ... %s, %ju bytes), offsets and scales in %s\n",
            file.transfer.texels.texel.size(), file.transfer.texels.width,
            file.transfer.texels.height, file.transfer.layout.K, file.transfer.layout.channels,
            ext == ".png" ? "16-bit unsigned normalized" : to_string(file.transfer.layout.encoding),
            from_matrices, files.size() - 1, ext == ".png" ? "RGBA PNG" : "RGBA EXR",
            files[1].c_str(), files.back().c_str(), bytes, files[0].c_str());
        return;
    }
    if (texel) {
        // The coefficient planes, dilated into the gutters, for engines.
        write_texel_coefficients_exr(a.output, file.transfer);
        std::printf(
            "exported %zu texels of %dx%d, K=%d x %d channel(s), %s planes%s -> %s (%ju "
            "bytes)\n",
            file.transfer.texels.texel.size(), file.transfer.texels.width,
            file.transfer.texels.height, file.transfer.layout.K, file.transfer.layout.channels,
            to_string(file.transfer.layout.encoding), from_matrices, a.output.c_str(),
            static_cast<std::uintmax_t>(std::filesystem::file_size(a.output)));
        return;
    }
    write_glb(a.output, file.mesh, file.transfer, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("exported %zu vertices, K=%d, %s, %s attributes%s in %.2f s -> %s (%ju bytes)\n",
                file.mesh.vertex_count(), options.K > 0 ? options.K : file.transfer.layout.K,
                a.half ? "int16 normalized" : "float32", to_string(options.attributes),
                from_matrices, seconds, a.output.c_str(),
                static_cast<std::uintmax_t>(std::filesystem::file_size(a.output)));
    if (options.light.sun) {
        const Vec3d E = sun_irradiance(*options.light.sun);
        std::printf(
            "sun: a KHR_lights_punctual directional light of %.4g lux (node \"sun\"); the "
            "SH light holds the sky only\n",
            std::max({E.x, E.y, E.z}));
    }
}

const bool export_registered = register_command(
    {"export", "Export a baked scene as glTF (.glb): mesh, baked colours, transfer attributes", 55,
     [](CLI::App& app) {
         auto args = std::make_shared<ExportArgs>();
         app.add_option("file", args->input, "Baked .shprt file")->required();
         app.add_option("-o,--output", args->output,
                        "Output .glb (texel files: .exr coefficient planes, or .png images)")
             ->required();
         add_light_options(app, args->light);
         app.add_option("--bands", args->bands,
                        "Export the first n bands (n² coefficients; default: all of the file's)");
         app.add_option("--exposure", args->exposure,
                        "COLOR_0 = exposure × radiance, clamped to [0, 1] (default 1)");
         app.add_option("--attributes", args->attributes,
                        "Where the transfer goes: custom (default: _SHPRT_T* attributes, which "
                        "three.js keeps) or standard (TEXCOORD_0..7, then COLOR_1.., which "
                        "Blender and gltfpack -noq keep; float32); for a texel file, "
                        "standard writes RGBA images of 4 coefficients each with a JSON "
                        "sidecar (.exr; .png always does: 16-bit with offsets and scales)");
         app.add_flag("--half", args->half,
                      "16-bit coefficients: normalized int16 with a scale per coefficient (glTF "
                      "has no float16)");
         app.callback([args] { run(*args); });
     }});

}  // namespace
}  // namespace shprt::tools
