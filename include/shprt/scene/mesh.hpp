// The scene as every other area sees it: one static triangle mesh with per-vertex data.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/material.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

struct Mesh {
    std::vector<Vec3f> positions;  // world space, right-handed, +Y up
    std::vector<Vec3f> normals;    // unit length, one per vertex
    std::vector<Vec3f> albedo;     // linear RGB diffuse reflectance in [0, 1], one per vertex
    std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise = front face
    // Texture coordinates (u, v) of one UV set, one per vertex, or empty when the scene has none
    // (load_scene's uv_set chooses the set). Per-texel transfer (bake/texels.hpp) rasterises the
    // triangles in this space. Not part of the scene hash.
    std::vector<std::array<float, 2>> uvs;
    // Adaptive refinement (bake/refine.hpp) only, else empty: one per vertex, the two vertices
    // whose edge vertex i split (its parents, both lower indices), or {kNoParent, kNoParent} for a
    // vertex of the scene as loaded. Not part of the scene hash.
    std::vector<std::array<std::uint32_t, 2>> parents;
    static constexpr std::uint32_t kNoParent = 0xFFFFFFFFu;

    // Where vertex i came from in the loader's order: for PLY input this is the identity (the
    // file's vertex i is vertex i); for other formats, the index Assimp produced across the
    // scene's meshes in order. Empty for generated scenes (identity).
    std::vector<std::uint32_t> source_vertex;
    // The glossy BRDFs the scene's materials give (load_scene reads them from the file), and per
    // vertex the index of its material's BRDF in `brdfs`, or kNoBrdf where the material gives
    // none; both empty when no material gives one. Glossy shading uses them unless a BRDF is
    // given for the whole scene (`--brdf`). Not part of the scene hash.
    std::vector<Brdf> brdfs;
    std::vector<std::uint32_t> brdf_index;
    static constexpr std::uint32_t kNoBrdf = 0xFFFFFFFFu;
    std::string source;  // file path or "builtin:NAME"
    // Where `albedo` came from, for people (`shprt info`): "vertex colours", "material diffuse
    // colour", "default 0.8 grey", "builtin scene colours", "--albedo R,G,B", a mix ("vertex
    // colours + default 0.8 grey"); empty when unknown. Not part of the scene hash.
    std::string albedo_source;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t triangle_count() const { return triangles.size(); }
};

}  // namespace shprt
