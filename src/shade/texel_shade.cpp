// Texel-domain shading and export (texel_shade.hpp).
#include "shprt/shade/texel_shade.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/shade_export.hpp"
#include "shprt/transfer/kind_table.hpp"

#include "shade/sh_convention.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace shprt {
namespace {

void require_texels(const TransferSet& transfer) {
    SHPRT_CHECK(is_texel(transfer.layout) && !transfer.texels.empty(), invalid_argument,
                "not a texel transfer (domain {})", to_string(transfer.layout.domain));
}

const char* channel_label(int channels, int c) {
    static const char* kNames[3] = {"R", "G", "B"};
    return channels == 1 ? "Y" : kNames[c];
}

}  // namespace

TexelPoints texel_points(const Mesh& mesh, const TransferSet& transfer) {
    require_texels(transfer);
    transfer.check(mesh);
    const TexelAtlas& atlas = transfer.texels;
    TexelSamples samples = atlas_texel_samples(mesh, atlas);
    TexelPoints out;
    Mesh& points = out.points;
    points.source = mesh.source;
    points.positions = std::move(samples.positions);
    points.normals = std::move(samples.normals);
    points.albedo = std::move(samples.albedo);
    if (!mesh.brdf_index.empty()) {
        points.brdfs = mesh.brdfs;
        for (std::uint32_t t : samples.triangle)
            points.brdf_index.push_back(mesh.brdf_index[mesh.triangles[t][0]]);
    }
    out.rows = transfer;
    out.rows.layout.domain = ReceiverDomain::vertex;
    out.rows.texels = {};
    return out;
}

ShadeResult shade_texels(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                         const ShadeOptions& options) {
    const TexelPoints t = texel_points(mesh, transfer);
    return shade_vertices(t.points, t.rows, light, options);
}

ShadeResult shade_texels_glossy(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                                const GlossyShadeOptions& options) {
    const TexelPoints t = texel_points(mesh, transfer);
    return shade_glossy(t.points, t.rows, light, options);
}

ShadeResult shade_receivers(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                            const ShadeOptions& options, const GlossyShadeOptions* glossy) {
    // The pass of the kind table, as the GL renderer chooses its scene pass (render/
    // scene_pass.hpp): texels are shaded as points by their rows' vertex pass.
    switch (shading_pass(transfer.layout)) {
        case ShadingPass::texels: {
            const TexelPoints t = texel_points(mesh, transfer);
            return shade_receivers(t.points, t.rows, light, options, glossy);
        }
        case ShadingPass::vertex_matrices:
            if (glossy) return shade_glossy(mesh, transfer, light, *glossy);
            break;
        case ShadingPass::vertex_vectors:
            if (!glossy) return shade_vertices(mesh, transfer, light, options);
            break;
        case ShadingPass::none:
            break;
    }
    // Options that do not fit the pass (a BRDF for vectors, none for matrices) or full matrices:
    // refused by the function the options ask for, in its words.
    return glossy ? shade_glossy(mesh, transfer, light, *glossy)
                  : shade_vertices(mesh, transfer, light, options);
}

void write_texel_image(const std::string& path, const TexelAtlas& atlas,
                       const std::vector<Vec3f>& values, float exposure) {
    const std::string ext = lower_extension(path);
    SHPRT_CHECK(ext == ".npy" || ext == ".exr" || ext == ".png", unsupported,
                "{}: a texel transfer shades to an image: .npy (H x W x 3), .exr or .png", path);
    SHPRT_CHECK(values.size() == atlas.texel.size(), invalid_argument,
                "{}: {} values for {} texels", path, values.size(), atlas.texel.size());
    const std::size_t W = std::size_t(atlas.width), H = std::size_t(atlas.height);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    if (ext == ".npy") {
        std::vector<float> image(W * H * 3, nan);
        for (std::size_t r = 0; r < values.size(); ++r)
            for (int c = 0; c < 3; ++c) image[3 * std::size_t(atlas.texel[r]) + c] = values[r][c];
        return write_npy_f32(path, {H, W, 3}, image);
    }
    if (ext == ".png") {  // a picture of the lightmap: tone mapped, black outside the charts
        Image image;
        image.width = atlas.width;
        image.height = atlas.height;
        image.rgb.assign(W * H * 3, 0.0f);
        for (std::size_t r = 0; r < values.size(); ++r)
            for (int c = 0; c < 3; ++c)
                image.rgb[3 * std::size_t(atlas.texel[r]) + c] = values[r][c];
        return save_image(path, image, exposure);
    }
    std::vector<ExrChannel> channels = {{"R", {}}, {"G", {}}, {"B", {}}};
    for (int c = 0; c < 3; ++c) {
        channels[c].plane.assign(W * H, nan);
        for (std::size_t r = 0; r < values.size(); ++r)
            channels[c].plane[atlas.texel[r]] = values[r][c];
    }
    save_exr_channels(path, atlas.width, atlas.height, channels, false);
}

void write_texel_coefficients_exr(const std::string& path, const TransferSet& transfer,
                                  int gutter) {
    require_texels(transfer);
    SHPRT_CHECK(!is_matrix(transfer.layout), invalid_argument,
                "{}: only vector transfer exports as texel planes", path);
    const TexelAtlas& atlas = transfer.texels;
    const std::vector<std::int64_t> source = dilate_texels(atlas, gutter);
    const int K = transfer.layout.K, C = transfer.layout.channels;
    static const char* kNames[3] = {"R", "G", "B"};
    std::vector<ExrChannel> channels;
    for (int i = 0; i < K; ++i)
        for (int c = 0; c < C; ++c) {
            ExrChannel ch{fmt::format("sh{:03}.{}", i, C == 1 ? "Y" : kNames[c]),
                          std::vector<float>(source.size(), 0.0f)};
            for (std::size_t p = 0; p < source.size(); ++p)
                if (source[p] >= 0) ch.plane[p] = transfer.receiver(std::size_t(source[p]), c)[i];
            channels.push_back(std::move(ch));
        }
    save_exr_channels(path, atlas.width, atlas.height, channels,
                      transfer.layout.encoding == TransferEncoding::f16);
}

std::vector<std::string> texel_coefficient_image_paths(const std::string& path,
                                                       const TransferLayout& layout) {
    const std::string ext = lower_extension(path);
    SHPRT_CHECK(ext == ".png" || ext == ".exr", unsupported,
                "{}: the texel coefficient images are .png (16-bit) or .exr", path);
    const std::filesystem::path p(path);
    const std::filesystem::path stem = p.parent_path() / p.stem();
    std::vector<std::string> out = {stem.string() + ".json"};
    for (int c = 0; c < layout.channels; ++c)
        for (int a = 0; a < (layout.K + 3) / 4; ++a)
            out.push_back(fmt::format("{}_{}{:03}{}", stem.string(),
                                      channel_label(layout.channels, c), a,
                                      p.extension().string()));
    return out;
}

std::vector<std::string> write_texel_coefficient_images(const std::string& path,
                                                        const TransferSet& transfer, int gutter) {
    require_texels(transfer);
    SHPRT_CHECK(!is_matrix(transfer.layout), invalid_argument,
                "{}: only vector transfer exports as texel images", path);
    const std::vector<std::string> paths = texel_coefficient_image_paths(path, transfer.layout);
    const bool png = lower_extension(path) == ".png";
    const bool half = !png && transfer.layout.encoding == TransferEncoding::f16;
    const TexelAtlas& atlas = transfer.texels;
    const std::size_t R = atlas.texel.size();
    SHPRT_CHECK(transfer.coeffs.size() == transfer.layout.floats(R), invalid_argument,
                "{}: {} coefficients for {} texels", path, transfer.coeffs.size(), R);
    for (std::size_t i = 0; i < transfer.coeffs.size(); ++i)
        SHPRT_CHECK(std::isfinite(transfer.coeffs[i]), invalid_argument,
                    "cannot write {}: texel {} has a non-finite coefficient", path,
                    i / transfer.layout.floats_per_receiver());
    const std::vector<std::int64_t> source = dilate_texels(atlas, gutter);
    const int K = transfer.layout.K, C = transfer.layout.channels;
    const std::size_t pixels = source.size();

    nlohmann::ordered_json images = nlohmann::ordered_json::array();
    std::vector<std::string> written;
    try {
        std::size_t next = 1;
        for (int c = 0; c < C; ++c)
            for (int a = 0; a < (K + 3) / 4; ++a) {
                const std::string& file = paths[next++];
                // Offset and scale per coefficient, rounded to float: the values the sidecar
                // gives are the ones encoded with.
                float offset[4] = {0, 0, 0, 0}, scale[4] = {1, 1, 1, 1};
                std::vector<float> plane[4];
                for (int j = 0; j < 4; ++j) {
                    const int i = 4 * a + j;
                    plane[j].assign(pixels, 0.0f);
                    if (i >= K) {
                        if (png) scale[j] = 0;
                        continue;
                    }
                    float lo = std::numeric_limits<float>::max(), hi = -lo;
                    for (std::size_t r = 0; r < R; ++r) {
                        const float x = transfer.receiver(r, c)[i];
                        lo = std::min(lo, x), hi = std::max(hi, x);
                    }
                    if (png) offset[j] = lo, scale[j] = static_cast<float>(double(hi) - lo);
                    const float empty = std::clamp(0.0f, lo, hi);  // beyond the gutters
                    for (std::size_t p = 0; p < pixels; ++p)
                        plane[j][p] = source[p] >= 0
                                          ? transfer.receiver(std::size_t(source[p]), c)[i]
                                          : empty;
                }
                if (png) {
                    std::vector<std::uint16_t> samples(pixels * 4);
                    for (std::size_t p = 0; p < pixels; ++p)
                        for (int j = 0; j < 4; ++j) {
                            const double v =
                                scale[j] > 0 ? (double(plane[j][p]) - offset[j]) / scale[j] : 0.0;
                            samples[4 * p + j] = static_cast<std::uint16_t>(
                                std::clamp(std::round(v * 65535.0), 0.0, 65535.0));
                        }
                    save_png16(file, atlas.width, atlas.height, 4, samples);
                } else {
                    std::vector<ExrChannel> channels;
                    for (int j = 0; j < 4; ++j)
                        channels.push_back({std::string(1, "RGBA"[j]), std::move(plane[j])});
                    save_exr_channels(file, atlas.width, atlas.height, channels, half);
                }
                written.push_back(file);
                images.push_back({{"file", std::filesystem::path(file).filename().string()},
                                  {"channel", channel_label(C, c)},
                                  {"first", 4 * a},
                                  {"count", std::min(4, K - 4 * a)},
                                  {"offset", std::vector<float>(offset, offset + 4)},
                                  {"scale", std::vector<float>(scale, scale + 4)}});
            }
        const nlohmann::ordered_json sidecar = {
            {"format", "shprt-texel-images"},
            {"version", 1},
            {"generator", std::string("shprt ") + SHPRT_VERSION_STRING},
            {"sh", detail::sh_convention_json()},
            {"K", K},
            {"bands", sh_bands_for(K)},
            {"channels", C},
            {"transfer", to_string(transfer.kind)},
            {"sampler", to_string(transfer.sampler)},
            {"samples", transfer.samples},
            {"width", atlas.width},
            {"height", atlas.height},
            {"uv_set", atlas.uv_set},
            {"uv",
             "texel (x, y), row 0 at the top of the image, has its centre at u = (x + 0.5) / "
             "width, v = 1 - (y + 0.5) / height"},
            {"texels", R},
            {"gutter", gutter},
            {"encoding", png ? "png16_unorm" : (half ? "exr_float16" : "exr_float32")},
            {"layout",
             "image a of channel c holds coefficients first .. first + count - 1 (first = 4a) of "
             "channel c in R, G, B, A; 0 past K"},
            {"decode",
             "T_c[first + j] = offset[j] + scale[j] * v_j, v_j the pixel's channel j as a "
             "sampler returns it (PNG: q / 65535; EXR: the float, scale 1, offset 0)"},
            {"radiometry",
             {{"irradiance",
               "E_c = sum_{i<K'} T_c[i] * L_c[i] (T_Y for every colour when channels = 1)"},
              {"radiance", "albedo_c / pi * E_c"}}},
            {"images", images},
        };
        AtomicFile out(paths[0]);
        out.write(sidecar.dump(1) + "\n");
        out.commit();
    } catch (...) {
        std::error_code ignored;  // the first error is the one to report
        for (const std::string& file : written) std::filesystem::remove(file, ignored);
        throw;
    }
    return paths;
}

void check_texel_view(const std::string& path, const TransferSet& transfer, double k,
                      ShadeView view) {
    SHPRT_CHECK(!is_texel(transfer.layout) || is_matrix(transfer.layout) || k >= 1 ||
                    view != ShadeView::radiance,
                unsupported,
                "{}: --k {}: diffuse texel transfer is drawn diffuse (k = 1); the paper's glossy "
                "term is not drawn per texel (a glossy bake's matrices are)",
                path, k);
}

}  // namespace shprt
