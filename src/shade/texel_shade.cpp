// Texel-domain shading and export (texel_shade.hpp).
#include "shprt/shade/texel_shade.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/save_image.hpp"
#include "shprt/shade/shade_export.hpp"

#include <fmt/format.h>

#include <limits>

namespace shprt {
namespace {

void require_texels(const TransferSet& transfer) {
    SHPRT_CHECK(transfer.layout.domain == ReceiverDomain::texel && !transfer.texels.empty(),
                invalid_argument, "not a texel transfer (domain {})",
                to_string(transfer.layout.domain));
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
    if (transfer.layout.domain == ReceiverDomain::texel)
        return glossy ? shade_texels_glossy(mesh, transfer, light, *glossy)
                      : shade_texels(mesh, transfer, light, options);
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
    SHPRT_CHECK(transfer.layout.shape == TransferShape::vector, invalid_argument,
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

}  // namespace shprt
