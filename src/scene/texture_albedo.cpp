// Colour textures for albedo (texture_albedo.hpp).
#include "texture_albedo.hpp"

#include "shprt/core/colour.hpp"

#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

namespace shprt::detail {
namespace {

struct StbFree {
    void operator()(stbi_uc* p) const { stbi_image_free(p); }
};

// The sRGB → linear table of the 256 8-bit codes.
const std::array<float, 256>& srgb8_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[std::size_t(i)] = srgb_to_linear(float(i) / 255.0f);
        return t;
    }();
    return table;
}

bool size_ok(long long w, long long h) {
    return w > 0 && h > 0 && w <= kMaxTextureSide && h <= kMaxTextureSide &&
           w * h <= kMaxTextureTexels;
}

// Decodes 8-bit RGB(A) pixels, rows from the top, into linear texels.
AlbedoTexture from_rgb8(const stbi_uc* rgb, int w, int h) {
    AlbedoTexture t;
    t.width = w;
    t.height = h;
    t.texels.resize(std::size_t(w) * std::size_t(h));
    const auto& lut = srgb8_table();
    for (std::size_t i = 0; i < t.texels.size(); ++i)
        t.texels[i] = {lut[rgb[3 * i]], lut[rgb[3 * i + 1]], lut[rgb[3 * i + 2]]};
    return t;
}

// A compressed image (PNG, JPEG, ...) in memory; empty on failure or an oversized header.
AlbedoTexture decode(const stbi_uc* bytes, int length) {
    int w = 0, h = 0, comp = 0;
    if (length <= 0 || !stbi_info_from_memory(bytes, length, &w, &h, &comp) || !size_ok(w, h))
        return {};
    std::unique_ptr<stbi_uc, StbFree> rgb(stbi_load_from_memory(bytes, length, &w, &h, &comp, 3));
    if (!rgb || !size_ok(w, h)) return {};
    return from_rgb8(rgb.get(), w, h);
}

AlbedoTexture read_file(const std::string& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!f) return {};
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_file(f.get(), &w, &h, &comp) || !size_ok(w, h)) return {};
    std::unique_ptr<stbi_uc, StbFree> rgb(stbi_load_from_file(f.get(), &w, &h, &comp, 3));
    if (!rgb || !size_ok(w, h)) return {};
    return from_rgb8(rgb.get(), w, h);
}

AlbedoTexture from_embedded(const aiTexture& tex) {
    if (!tex.pcData) return {};
    if (tex.mHeight == 0)  // compressed: mWidth bytes of a PNG, JPEG, ...
        return tex.mWidth > 0x7fffffffu
                   ? AlbedoTexture{}
                   : decode(reinterpret_cast<const stbi_uc*>(tex.pcData), int(tex.mWidth));
    if (!size_ok(tex.mWidth, tex.mHeight)) return {};
    const int w = int(tex.mWidth), h = int(tex.mHeight);
    std::vector<stbi_uc> rgb(std::size_t(w) * std::size_t(h) * 3);
    for (std::size_t i = 0; i < std::size_t(w) * std::size_t(h); ++i) {
        rgb[3 * i] = tex.pcData[i].r;
        rgb[3 * i + 1] = tex.pcData[i].g;
        rgb[3 * i + 2] = tex.pcData[i].b;
    }
    return from_rgb8(rgb.data(), w, h);
}

int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
}

}  // namespace

Vec3f AlbedoTexture::sample(float u, float v) const {
    if (texels.empty() || !std::isfinite(u) || !std::isfinite(v)) return {0, 0, 0};
    // Texel centres at (i + ½)/width; v = 0 at the bottom row (height − 1 from the top).
    const double x = double(u) * width - 0.5;
    const double y = (1.0 - double(v)) * height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const float ax = float(x - fx), ay = float(y - fy);
    // Wrapped indices: fmod first, so huge coordinates cannot overflow an int.
    const int x0 = wrap(int(std::fmod(fx, double(width))), width);
    const int y0 = wrap(int(std::fmod(fy, double(height))), height);
    const int x1 = (x0 + 1) % width, y1 = (y0 + 1) % height;
    const auto at = [&](int xi, int yi) { return texels[std::size_t(yi) * width + xi]; };
    const Vec3f top = at(x0, y0) * (1 - ax) + at(x1, y0) * ax;
    const Vec3f bottom = at(x0, y1) * (1 - ax) + at(x1, y1) * ax;
    return top * (1 - ay) + bottom * ay;
}

AlbedoTextures::AlbedoTextures(const aiScene& scene, std::string model_path) : m_scene(scene) {
    const std::size_t slash = model_path.find_last_of('/');
    m_folder = slash == std::string::npos ? std::string() : model_path.substr(0, slash + 1);
}

const AlbedoTexture* AlbedoTextures::find(const aiMaterial& material, unsigned& uv_set,
                                          Vec3f& factor, bool& failed) {
    failed = false;
    aiString path;
    unsigned uv = 0;
    aiTextureType type = aiTextureType_BASE_COLOR;
    if (material.GetTexture(type, 0, &path, nullptr, &uv) != AI_SUCCESS) {
        type = aiTextureType_DIFFUSE;
        if (material.GetTexture(type, 0, &path, nullptr, &uv) != AI_SUCCESS) return nullptr;
    }
    const std::string key(path.C_Str());
    if (key.empty()) return nullptr;
    auto it = m_cache.find(key);
    if (it == m_cache.end()) {
        AlbedoTexture texture;
        if (const aiTexture* embedded = m_scene.GetEmbeddedTexture(key.c_str()))
            texture = from_embedded(*embedded);
        else if (key[0] != '*') {
            m_files.push_back(key[0] == '/' ? key : m_folder + key);
            texture = read_file(m_files.back());
        }
        it = m_cache.emplace(key, std::move(texture)).first;
    }
    if (it->second.texels.empty()) {
        failed = true;
        return nullptr;
    }
    uv_set = uv;
    aiColor4D c;
    factor = {1, 1, 1};
    if (aiGetMaterialColor(&material, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
        aiGetMaterialColor(&material, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS)
        factor = {c.r, c.g, c.b};
    return &it->second;
}

}  // namespace shprt::detail
