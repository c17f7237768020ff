// CPU reference of the paper's per-vertex shading (shade/shade.hpp): diffuse E = c_T · c_L and
// the glossy term with a zonal Phong lobe rotated to the reflection direction in O(K).
//
// Implements: P.-P. Sloan, J. Kautz, J. Snyder, "Precomputed Radiance Transfer for Real-Time
// Rendering in Dynamic, Low-Frequency Lighting Environments", SIGGRAPH 2002 (diffuse transfer,
// zonal lobe rotation), and the shading model of the paper reproduced here
// (/work/shared/paper/PAPER.md, "Shading").
#include "shprt/shade/shade.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <cmath>

namespace shprt {
namespace {

void check_inputs(const Mesh& mesh, const TransferSet& transfer, const ShLight& light) {
    check_shadable(mesh, transfer);
    SHPRT_CHECK(light.K > 0 && light.coeffs.size() == 3 * std::size_t(light.K), invalid_argument,
                "light has K = {} and {} coefficients (expected 3 × K)", light.K,
                light.coeffs.size());
}

}  // namespace

void check_shadable(const Mesh& mesh, const TransferSet& transfer) {
    transfer.check(mesh);
    SHPRT_CHECK(!is_texel(transfer.layout), unsupported,
                "texel transfer is shaded per texel (shade_texels, shade/texel_shade.hpp; "
                "shprt shade -o .npy|.exr|.png)");
    SHPRT_CHECK(!is_matrix(transfer.layout), unsupported,
                "{} transfer cannot be shaded with L = k·L_D + (1−k)·L_S (it needs a vector per "
                "receiver; glossy transfer matrices are shaded with --brdf, shade/glossy.hpp)",
                to_string(transfer.layout.shape));
}

int effective_basis_size(const TransferSet& transfer, const ShLight& light, int K_used) {
    SHPRT_CHECK(K_used >= 0, invalid_argument, "basis size K' = {} is negative", K_used);
    int K = std::min(transfer.layout.K, light.K);
    if (K_used > 0) K = std::min(K, K_used);
    SHPRT_CHECK(K > 0, invalid_argument,
                "no SH coefficients to shade with (transfer K = {}, light K = {})",
                transfer.layout.K, light.K);
    return K;
}

std::vector<float> lobe_band_factors(int bands, double gloss) {
    SHPRT_CHECK(bands >= 1 && bands <= kMaxBands, invalid_argument, "lobe bands {} outside 1..{}",
                bands, kMaxBands);
    SHPRT_CHECK(gloss >= 0 && std::isfinite(gloss), invalid_argument,
                "gloss exponent {} must be finite and ≥ 0", gloss);
    return zonal_band_factors(phong_lobe_zonal(bands, gloss));
}

std::vector<float> zonal_band_factors(const std::vector<double>& zonal) {
    std::vector<float> g(zonal.size());
    for (std::size_t l = 0; l < zonal.size(); ++l)
        g[l] = static_cast<float>(std::sqrt(4 * kPi / (2 * double(l) + 1)) * zonal[l]);
    return g;
}

ShadeResult shade_vertices(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                           const ShadeOptions& options) {
    check_inputs(mesh, transfer, light);
    SHPRT_CHECK(options.k >= 0 && options.k <= 1, invalid_argument,
                "diffuse share k = {} is outside [0, 1]", options.k);
    SHPRT_CHECK(options.gloss >= 0 && std::isfinite(options.gloss), invalid_argument,
                "gloss exponent {} must be finite and ≥ 0", options.gloss);
    const int K = effective_basis_size(transfer, light, options.K_used);
    const int bands = sh_bands_for(K);
    const bool glossy = options.k < 1;
    const std::vector<double> lobe =
        glossy ? phong_lobe_zonal(bands, options.gloss) : std::vector<double>{};
    const Vec3d eye = cast<double>(options.eye);

    const std::size_t V = mesh.vertex_count();
    ShadeResult result;
    result.irradiance.resize(V);
    result.radiance.resize(V);
    parallel_for(0, V, 256, Split::automatic, [&](std::size_t first, std::size_t last) {
        std::vector<double> cs(glossy ? K : 0);
        for (std::size_t v = first; v != last; ++v) {
            double E[3], L_S[3] = {0, 0, 0};
            for (int c = 0; c < 3; ++c) {
                const float* t = transfer.receiver(v, channel_for(transfer.layout, c));
                const float* l = light.channel(c);
                double s = 0;
                for (int i = 0; i < K; ++i) s += double(t[i]) * double(l[i]);
                E[c] = s;
            }
            if (glossy) {
                const Vec3d p = cast<double>(mesh.positions[v]);
                const Vec3d n = normalize(cast<double>(mesh.normals[v]));
                const Vec3d to_eye = eye - p;
                // A vertex at the eye has no view direction; look along the normal there.
                const Vec3d w = length(to_eye) > 0 ? normalize(to_eye) : n;
                const double nw = dot(n, w);
                const Vec3d r = n * (2 * nw) - w;
                rotate_zonal(lobe.data(), K, r, cs.data());
                const double cos_eta = std::max(nw, kMinCosEta);
                for (int c = 0; c < 3; ++c) {
                    const float* t = transfer.receiver(v, channel_for(transfer.layout, c));
                    const float* l = light.channel(c);
                    double lobe_light = 0, lobe_transfer = 0;
                    for (int i = 0; i < K; ++i) {
                        lobe_light += cs[i] * double(l[i]);
                        lobe_transfer += cs[i] * double(t[i]);
                    }
                    L_S[c] = lobe_light * lobe_transfer / cos_eta;
                }
            }
            const Vec3f a = mesh.albedo[v];
            const double albedo[3] = {a.x, a.y, a.z};
            double L[3];
            for (int c = 0; c < 3; ++c) {
                const double L_D = albedo[c] / kPi * E[c];
                L[c] = glossy ? options.k * L_D + (1 - options.k) * L_S[c] : L_D;
            }
            result.irradiance[v] = {float(E[0]), float(E[1]), float(E[2])};
            result.radiance[v] = {float(L[0]), float(L[1]), float(L[2])};
        }
    });
    return result;
}

}  // namespace shprt
