// `shprt export`'s choice of what a file becomes (shade/export_file.hpp).
#include "shprt/shade/export_file.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/timer.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/gltf_export.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>

namespace shprt {

const std::vector<OptionRow<ExportChoice>>& export_option_table() {
    static const std::vector<OptionRow<ExportChoice>> table = [] {
        using C = ExportChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "bands", &C::bands,
                "Export the first n bands (n² coefficients; default: all of the file's)");
        add_row(t, "exposure", &C::exposure,
                "COLOR_0 = exposure × radiance, clamped to [0, 1] (default 1)");
        add_row(t, "attributes", &C::attributes,
                "Where the transfer goes: custom (default: _SHPRT_T* attributes, which "
                "three.js keeps) or standard (TEXCOORD_0..7, then COLOR_1.., which "
                "Blender and gltfpack -noq keep; float32); for a texel file, "
                "standard writes RGBA images of 4 coefficients each with a JSON "
                "sidecar (.exr; .png always does: 16-bit with offsets and scales)");
        add_row(t, "half", &C::half,
                "16-bit coefficients: normalized int16 with a scale per coefficient (glTF "
                "has no float16)");
        return complete_rows(std::move(t));
    }();
    return table;
}

std::string export_file(const std::string& input, const std::string& output,
                        const LightChoice& light, const ExportChoice& a) {
    const auto start = Clock::now();
    const std::string ext = lower_extension(output);
    const bool image = ext == ".exr" || ext == ".png";  // texel files only
    SHPRT_CHECK(ext == ".glb" || image, invalid_argument,
                "{}: the output must be a binary glTF file (.glb), or .exr or .png for a texel "
                "file",
                output);
    SHPRT_CHECK(a.bands >= 0 && a.bands <= kMaxComputeBands, invalid_argument,
                "--bands {}: must be 1 to {} (0 = all)", a.bands, kMaxComputeBands);
    GltfExportOptions options;
    options.light = light_setup_from(light);
    options.half = a.half;
    options.attributes = parse_gltf_attributes(a.attributes);
    SHPRT_CHECK(a.exposure > 0 && std::isfinite(a.exposure), invalid_argument,
                "--exposure {}: must be positive", a.exposure);
    options.exposure = static_cast<float>(a.exposure);
    const std::vector<std::string> inputs = input_files(input, light);
    check_output_is_not_input(output, inputs);
    check_output_writable(output);  // a directory, a device: refused before the work

    ShprtFile file = read_shprt(input);
    if (a.bands > 0) {
        options.K = sh_count(a.bands);
        SHPRT_CHECK(options.K <= file.transfer.layout.K, invalid_argument,
                    "--bands {}: {} has K = {}, fewer than {} coefficients", a.bands, input,
                    file.transfer.layout.K, options.K);
    }
    // glTF's attributes and the texel planes carry vectors: glossy matrices go as their diffuse
    // part t = M·a(n), the transfer `--glossy paper` shades (shade/glossy.hpp).
    const bool matrices = is_glossy_matrix(file.transfer.layout);
    if (matrices) file.transfer = glossy_to_diffuse(file.mesh, file.transfer);
    const char* from_matrices = matrices ? ", the glossy matrices' diffuse transfer M·a(n)" : "";
    const TransferSet& t = file.transfer;
    const bool texel = is_texel(t.layout);
    SHPRT_CHECK(texel == image, invalid_argument, "{}: {}", output,
                texel ? "a texel file exports its coefficient planes as .exr, or as standard "
                        "images (.png, or .exr with --attributes standard)"
                      : ".exr and .png export is for texel files (bake with --domain texel)");
    // Standard images: RGBA PNG16 or EXR, four coefficients each, with a JSON sidecar (a PNG
    // has no other layout); else the one multi-channel EXR.
    if (texel && (ext == ".png" || options.attributes == GltfAttributes::standard)) {
        const std::vector<std::string> files = texel_coefficient_image_paths(output, t.layout);
        for (const std::string& f : files) {
            check_output_is_not_input(f, inputs);
            check_output_writable(f);
        }
        write_texel_coefficient_images(output, t);
        std::uintmax_t bytes = 0;
        for (const std::string& f : files) bytes += std::filesystem::file_size(f);
        return fmt::format(
            "exported {} texels of {}x{}, K={} x {} channel(s), {}{} -> {} {} images ({} ... {}, "
            "{} bytes), offsets and scales in {}\n",
            t.texels.texel.size(), t.texels.width, t.texels.height, t.layout.K, t.layout.channels,
            ext == ".png" ? "16-bit unsigned normalized" : to_string(t.layout.encoding),
            from_matrices, files.size() - 1, ext == ".png" ? "RGBA PNG" : "RGBA EXR", files[1],
            files.back(), bytes, files[0]);
    }
    if (texel) {
        // The coefficient planes, dilated into the gutters, for engines.
        write_texel_coefficients_exr(output, t);
        return fmt::format(
            "exported {} texels of {}x{}, K={} x {} channel(s), {} planes{} -> {} ({} bytes)\n",
            t.texels.texel.size(), t.texels.width, t.texels.height, t.layout.K, t.layout.channels,
            to_string(t.layout.encoding), from_matrices, output,
            std::uintmax_t(std::filesystem::file_size(output)));
    }
    write_glb(output, file.mesh, t, options);
    std::string lines = fmt::format(
        "exported {} vertices, K={}, {}, {} attributes{} in {:.2f} s -> {} ({} bytes)\n",
        file.mesh.vertex_count(), options.K > 0 ? options.K : t.layout.K,
        a.half ? "int16 normalized" : "float32", to_string(options.attributes), from_matrices,
        seconds_since(start), output, std::uintmax_t(std::filesystem::file_size(output)));
    if (options.light.sun) {
        const Vec3d E = sun_irradiance(*options.light.sun);
        lines += fmt::format(
            "sun: a KHR_lights_punctual directional light of {:.4g} lux (node \"sun\"); the "
            "SH light holds the sky only\n",
            std::max({E.x, E.y, E.z}));
    }
    return lines;
}

}  // namespace shprt
