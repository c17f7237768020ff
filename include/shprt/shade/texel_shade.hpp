// Shading and exporting texel-domain transfer (docs/texels.md): per-texel irradiance and radiance
// as images, and the coefficients as EXR planes for engines.
#pragma once

#include "shprt/scene/mesh.hpp"
#include "shprt/shade/glossy.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/transfer/transfer.hpp"

#include <string>
#include <vector>

namespace shprt {

// Gutter of the exported coefficient planes, in texels (dilate_texels): enough for bilinear
// filtering and a few mip levels.
inline constexpr int kTexelGutter = 4;

// A diffuse texel file (docs/texels.md) is drawn per fragment without the paper's glossy term:
// one-line Error(unsupported) naming `path` for --k < 1 in the radiance view (glossy matrices per
// texel are drawn). `shprt render` and `view`.
void check_texel_view(const std::string& path, const TransferSet& transfer, double k,
                      ShadeView view);

// Shades every receiver (texel) of a texel-domain transfer with shade_vertices' formulas: the
// texels' positions, normals and albedo come from rasterize_texels over `mesh` (its UVs) at the
// atlas's size, which must give exactly the atlas's texels (else Error(format): the file's mesh
// and atlas disagree). Results are per receiver, in atlas order. Throws what shade_vertices
// throws, Error(invalid_argument) for a transfer that is not texel-domain.
ShadeResult shade_texels(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                         const ShadeOptions& options);

// The texels of a texel-domain transfer as the vertices of a mesh without triangles: positions,
// normals and albedo from rasterize_texels (checked against the atlas as above), each texel's
// material BRDF that of its triangle's first corner; and the transfer's rows as theirs (vertex
// domain). What per-texel shading shades, on the CPU and on the GPU.
struct TexelPoints {
    Mesh points;
    TransferSet rows;
};
TexelPoints texel_points(const Mesh& mesh, const TransferSet& transfer);

// The same for glossy transfer matrices per texel: shade_glossy's formulas at each texel's
// point (its material BRDF that of its triangle's first corner). Throws what shade_glossy throws.
ShadeResult shade_texels_glossy(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                                const GlossyShadeOptions& options);

// Every receiver of `transfer` shaded by the pass the kind table gives its layout (shading_pass,
// transfer/kind_table.hpp; the GL renderer chooses its scene pass by the same query):
// vertex_matrices the glossy matrix term (shade_glossy, with `glossy`), vertex_vectors
// shade_vertices' formulas, texels each texel as a point shaded by its rows' pass
// (shade_texels_glossy, shade_texels). One row per receiver. What `shprt shade` and Python's
// shade() call; throws what those throw (options that do not fit the layout: what shade_glossy
// or shade_vertices throws for it).
ShadeResult shade_receivers(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                            const ShadeOptions& options, const GlossyShadeOptions* glossy);

// Writes one value per receiver as a width × height × 3 image, row 0 at the top, texels outside
// every chart NaN: `.npy` (float32, shape (H, W, 3)) or `.exr` (float32 R, G, B); or a `.png`
// picture of it (times `exposure`, tone mapped as save_image does, black outside the charts).
// Throws Error(unsupported) for another extension, Error(invalid_argument) for a size mismatch.
void write_texel_image(const std::string& path, const TexelAtlas& atlas,
                       const std::vector<Vec3f>& values, float exposure = 1.0f);

// Writes the coefficients of a texel-domain transfer as one multi-channel EXR: channel c of
// coefficient i is "shIII.Y" (one channel) or "shIII.R|G|B" (three), each a width × height plane,
// dilated `gutter` texels into the empty space (dilate_texels) and 0 beyond; float16 when the
// transfer's encoding is f16, else float32. Throws Error(invalid_argument) for a transfer that is
// not texel-domain vectors.
void write_texel_coefficients_exr(const std::string& path, const TransferSet& transfer,
                                  int gutter = kTexelGutter);

// The same coefficients as standard images that engines import as textures (`shprt export
// TEXELS.shprt -o OUT.png|OUT.exr --attributes standard`): per colour channel c (Y for grey
// transfer, else R, G, B), ceil(K/4) RGBA images OUT_<c><a>.png|.exr (a = 000, 001, …), image a
// holding coefficients 4a … 4a+3 in R, G, B, A (0 past K) — the layout of the renderer's texture
// array and of the .glb's _SHPRT_T attributes — dilated as above. Each value decodes as
//     T_c[4a + j] = offset[j] + scale[j] · v,
// v the pixel's channel j as a texture sampler returns it: for .png, 16-bit unsigned normalized
// (v = q/65535), offset = the coefficient's smallest value over the texels, scale = its range, so
// the error is at most scale/131070 (plus float rounding of offset and scale); for .exr, the
// coefficient itself as float (float16 when the transfer's encoding is f16, else float32), with
// scale 1 and offset 0 — one decode for both. Texels beyond the gutters hold the value nearest 0.
// A sidecar OUT.json (written last) lists the images with their offsets and scales, the SH
// convention, K, channels, size, the UV convention and the radiometry. Every file through
// AtomicFile; when one fails, those already written are removed. Returns the paths written, the
// sidecar first. Throws what write_texel_coefficients_exr throws, Error(unsupported) for another
// extension, Error(invalid_argument) for a non-finite coefficient.
std::vector<std::string> write_texel_coefficient_images(const std::string& path,
                                                        const TransferSet& transfer,
                                                        int gutter = kTexelGutter);
// The paths write_texel_coefficient_images writes for `path` and `layout`, the sidecar first (so
// that a command can check them before the work).
std::vector<std::string> texel_coefficient_image_paths(const std::string& path,
                                                       const TransferLayout& layout);

}  // namespace shprt
