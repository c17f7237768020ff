// Texel samples of a mesh's UV atlas: the texel centres on the surface, with their position,
// normal and albedo: the receivers of a texel-domain bake (bake/texels.hpp) and what shading a
// texel file needs (shade/texel_shade.hpp). Microsoft's D3DX PRT engine did per-texel PRT the
// same way; this is the open version, on the same bake as vertices.
//
// The image: width × height texels, row 0 at the top. Texel (x, y) covers
// u ∈ [x/W, (x+1)/W], v ∈ [1 − (y+1)/H, 1 − y/H]; its centre is u = (x + ½)/W, v = 1 − (y + ½)/H
// (OpenGL's v-up UVs, which Assimp delivers, shown as an image with its top row first).
//
// Coverage is conservative: a texel belongs to a triangle when its square overlaps the triangle in
// UV space (Akenine-Möller & Aila 2005: each edge function tested at the square's corner most
// inside), so thin triangles get texels too. A texel covered by several triangles of a chart
// (along a shared edge) takes the one that contains its centre, else the first by index. Its
// position, normal and albedo are the triangle's barycentric interpolation at the centre, with
// the barycentrics clamped to the triangle (a centre outside it moves onto it), the normal
// renormalised.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

// Largest texel image side accepted.
inline constexpr int kMaxTexelSide = 16384;

struct TexelSamples {
    int width = 0, height = 0;
    std::vector<std::uint32_t> texel;     // y·width + x of each covered texel, ascending
    std::vector<Vec3f> positions;         // one per covered texel
    std::vector<Vec3f> normals;           // unit
    std::vector<Vec3f> albedo;            // interpolated vertex albedo
    std::vector<std::uint32_t> triangle;  // the triangle each lies on

    std::size_t count() const { return texel.size(); }
};

// Rasterises every triangle of `mesh` in its UVs (Mesh::uvs, which load_scene took from UV set
// `uv_set`, named in messages) into a width × height image (see the top of this file). Throws
// Error(invalid_argument) when the mesh has no UVs ("has no texture coordinates (UV set N)"), a
// side is outside 1..kMaxTexelSide, no texel is covered, or two triangles overlap in UV space (a
// texel centre strictly inside both: "triangles A and B overlap in UV space at texel (x, y)":
// per-texel transfer needs a unique atlas). CPU, one thread; deterministic.
TexelSamples rasterize_texels(const Mesh& mesh, int width, int height, int uv_set = 0);

// Two triangles of one UV atlas that overlap: a texel centre strictly inside both.
struct UvOverlap {
    std::uint32_t first = 0, second = 0;  // triangle indices, first < second
    int x = 0, y = 0;                     // the texel
};
// The overlaps rasterize_texels would refuse at width × height (it refuses the first), in
// triangle order, at most `most` (the texel of one is not looked at again): the same coverage,
// without the samples. Throws what rasterize_texels throws for a mesh without UVs, a bad side or
// a non-finite UV.
std::vector<UvOverlap> find_uv_overlaps(const Mesh& mesh, int width, int height,
                                        std::size_t most = 1);

}  // namespace shprt
