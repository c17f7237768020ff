// Private to src/scene: the albedo of a textured material, sampled at a vertex's texture
// coordinates (scene/load.hpp, "albedo"). Runs in the importer child (isolated_import.hpp), so it
// only computes: no logging.
//
// The texture is the material's base colour texture (glTF) or else its diffuse texture (OBJ's
// map_Kd, FBX, Collada ...), read from the file it names (relative to the model's folder) or
// embedded in the model (glTF data URIs, GLB buffers, FBX: Assimp's "*N" textures, compressed or
// raw texels), decoded by stb_image (PNG, JPEG, BMP, TGA, ...). Texels are sRGB (as glTF and
// every common asset pipeline store colour textures) and are converted to linear with the exact
// curve before filtering; the result is multiplied by the material's colour factor (glTF's
// baseColorFactor, MTL's Kd: both specifications multiply), 1 where the material has none.
// Sampling is bilinear with repeat wrapping at texel centres, v = 0 at the image's bottom row
// (Assimp flips glTF's top-left origin to OpenGL's bottom-left on import).
#pragma once

#include "shprt/core/vec.hpp"

#include <map>
#include <string>
#include <vector>

struct aiScene;
struct aiMaterial;

namespace shprt::detail {

// A decoded colour texture, linear RGB.
struct AlbedoTexture {
    int width = 0, height = 0;
    std::vector<Vec3f> texels;  // row-major, row 0 at the image's top
    // Bilinear, repeat-wrapped, at (u, v) with v = 0 at the bottom.
    Vec3f sample(float u, float v) const;
};

// Largest side and texel count of a texture decoded for albedo (checked from the header).
inline constexpr int kMaxTextureSide = 1 << 14;
inline constexpr long long kMaxTextureTexels = 1LL << 26;

// The material textures of one scene, each decoded once.
class AlbedoTextures {
public:
    AlbedoTextures(const aiScene& scene, std::string model_path);

    // The texture for `material` and the UV set it uses, with its colour factor; nullptr when the
    // material has no colour texture or it cannot be read (`failed` is then set when it had one).
    const AlbedoTexture* find(const aiMaterial& material, unsigned& uv_set, Vec3f& factor,
                              bool& failed);
    // The texture files find() has tried to read (each once), for the files the scene reads.
    const std::vector<std::string>& files() const { return m_files; }

private:
    std::vector<std::string> m_files;
    const aiScene& m_scene;
    std::string m_folder;                          // the model's folder, "" or ending in '/'
    std::map<std::string, AlbedoTexture> m_cache;  // by texture path, empty = unreadable
};

}  // namespace shprt::detail
