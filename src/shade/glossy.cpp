// Glossy shading with transfer matrices (shade/glossy.hpp, docs/glossy.md).
//
// Implements the glossy transfer of P.-P. Sloan, J. Kautz, J. Snyder, "Precomputed Radiance
// Transfer for Real-Time Rendering in Dynamic, Low-Frequency Lighting Environments", SIGGRAPH
// 2002 (§5: transfer matrices, lobes rotated to the reflection direction), with zonal lobes for
// normalised Phong, Blinn–Phong and GGX (B. Walter et al., "Microfacet Models for Refraction
// through Rough Surfaces", EGSR 2007, for D_GGX).
#include "shprt/shade/glossy.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <algorithm>
#include <cmath>

namespace shprt {
namespace {

// Quadrature nodes per half of [−1, 1] for the numerically fitted lobes.
constexpr int kLobeNodes = 1024;

// The lobe profile before normalisation.
double raw_profile(const Brdf& b, double x) {
    if (x <= 0) return 0;
    switch (b.model) {
        case BrdfModel::phong:
            return (b.parameter + 1) / (2 * kPi) * std::pow(x, b.parameter);
        case BrdfModel::blinn_phong:
            return std::pow(0.5 * (1 + x), 0.5 * b.parameter);  // cos(θ/2)^E
        case BrdfModel::ggx: {
            const double a2 = b.parameter * b.parameter * b.parameter * b.parameter;  // α = R²
            const double c2 = 0.5 * (1 + x);  // cos²(θ/2): n·h at normal incidence
            const double d = c2 * (a2 - 1) + 1;
            return a2 / (kPi * d * d);
        }
    }
    return 0;
}

double normalisation(const Brdf& b) {
    if (b.model == BrdfModel::phong) return 1;  // (E+1)/(2π) x^E integrates to 1 already
    const std::vector<double> z0 =
        project_zonal([&](double x) { return raw_profile(b, x); }, 1, kLobeNodes);
    return 1 / (z0[0] * std::sqrt(4 * kPi));  // ∫ f dω = z_0 · √(4π)
}

}  // namespace

Vec3d reflect_view(const Vec3d& n, const Vec3d& p, const Vec3d& eye) {
    const Vec3d to_eye = eye - p;
    const Vec3d w = length(to_eye) > 0 ? normalize(to_eye) : n;  // at the eye: along n
    return n * (2 * dot(n, w)) - w;
}

double BrdfProfile::operator()(double x) const { return scale * raw_profile(brdf, x); }

BrdfProfile brdf_profile(const Brdf& brdf) {
    check_brdf(brdf);
    return {brdf, normalisation(brdf)};
}

BrdfLobe brdf_lobe(const Brdf& brdf, int bands) {
    const BrdfProfile profile = brdf_profile(brdf);
    double norm2 = 0;
    BrdfLobe lobe;
    lobe.zonal = project_zonal(profile, bands, kLobeNodes, &norm2);
    // Phong: the closed form (the quadrature above only measures the residual).
    if (brdf.model == BrdfModel::phong) lobe.zonal = phong_lobe_zonal(bands, brdf.parameter);
    double kept = 0;
    for (double z : lobe.zonal) kept += z * z;
    lobe.fit_error = norm2 > 0 ? std::sqrt(std::max(0.0, norm2 - kept) / norm2) : 0;
    return lobe;
}

std::vector<Brdf> brdf_table(const Mesh& mesh, bool material_brdfs, const Brdf& brdf) {
    check_brdf(brdf);
    std::vector<Brdf> table{brdf};
    if (!material_brdfs || mesh.brdf_index.empty()) return table;
    SHPRT_CHECK(mesh.brdf_index.size() == mesh.vertex_count(), invalid_argument,
                "{} BRDF indices for {} vertices", mesh.brdf_index.size(), mesh.vertex_count());
    if (const auto v = bad_brdf_index(mesh))
        fail(ErrorCode::invalid_argument, "vertex {} has BRDF index {} but the mesh has {} BRDFs",
             *v, mesh.brdf_index[*v], mesh.brdfs.size());
    table.insert(table.end(), mesh.brdfs.begin(), mesh.brdfs.end());
    return table;
}

void check_glossy_shadable(const Mesh& mesh, const TransferSet& transfer) {
    transfer.check(mesh);
    SHPRT_CHECK(is_glossy_matrix(transfer.layout) && transfer.layout.channels == 1,
                invalid_argument,
                "{} transfer with {} channel(s) cannot be shaded with --brdf: glossy shading needs "
                "a glossy bake (--transfer glossy)",
                to_string(transfer.layout.shape), transfer.layout.channels);
}

ShadeResult shade_glossy(const Mesh& mesh, const TransferSet& transfer, const ShLight& light,
                         const GlossyShadeOptions& options) {
    check_glossy_shadable(mesh, transfer);
    SHPRT_CHECK(light.K > 0 && light.coeffs.size() == 3 * std::size_t(light.K), invalid_argument,
                "light has K = {} and {} coefficients (expected 3 × K)", light.K,
                light.coeffs.size());
    SHPRT_CHECK(options.k >= 0 && options.k <= 1, invalid_argument,
                "diffuse share k = {} is outside [0, 1]", options.k);
    if (options.albedo) {
        const Vec3f a = *options.albedo;
        SHPRT_CHECK(a.x >= 0 && a.x <= 1 && a.y >= 0 && a.y <= 1 && a.z >= 0 && a.z <= 1,
                    invalid_argument, "albedo ({}, {}, {}) must be in [0, 1]", a.x, a.y, a.z);
    }
    const int K = effective_basis_size(transfer, light, options.K_used);
    const int bands = sh_bands_for(K);
    const std::vector<Brdf> brdfs = brdf_table(mesh, options.material_brdfs, options.brdf);
    std::vector<std::vector<double>> lobes;  // per brdf_table entry
    for (const Brdf& b : brdfs) lobes.push_back(brdf_lobe(b, bands).zonal);
    const std::vector<double> cosine = clamped_cosine_zonal(bands);
    const Vec3d eye = cast<double>(options.eye);
    const int Kt = transfer.layout.K;

    const std::size_t V = mesh.vertex_count();
    ShadeResult result;
    result.irradiance.resize(V);
    result.radiance.resize(V);
    // A CPCA code (transfer/cpca.hpp) is shaded as Sloan et al. 2003 do: the light is transformed
    // once per cluster, mean·L and B_i·L, and a vertex's shadowed radiance is
    // T = mean·L + Σ_i w_i (B_i·L) — N·K per vertex and colour instead of K².
    const CpcaCode& code = transfer.cpca;
    const bool per_cluster = !code.empty();
    const std::size_t N = per_cluster ? std::size_t(code.vectors) : 0;
    std::vector<double> cluster_light;  // [cluster][1 + N][colour][K]
    if (per_cluster) {
        const std::size_t D = transfer.layout.floats_per_receiver();
        SHPRT_CHECK(code.means.size() == std::size_t(code.clusters) * D &&
                        code.basis.size() == std::size_t(code.clusters) * N * D &&
                        code.weights.size() == V * N && code.cluster.size() == V,
                    invalid_argument, "the transfer's CPCA code does not fit its {} receivers", V);
        cluster_light.assign(std::size_t(code.clusters) * (1 + N) * 3 * K, 0.0);
        parallel_for(
            0, std::size_t(code.clusters), 1, Split::automatic,
            [&](std::size_t first, std::size_t last) {
                std::vector<double> M(std::size_t(K) * K);
                for (int c = int(first); c != int(last); ++c)
                    for (std::size_t b = 0; b <= N; ++b) {
                        const float* packed = b == 0 ? code.means.data() + std::size_t(c) * D
                                                     : code.basis.data() + (c * N + b - 1) * D;
                        unpack_symmetric(packed, Kt, K, M.data());
                        for (int ch = 0; ch < 3; ++ch) {
                            double* out = cluster_light.data() + ((c * (1 + N) + b) * 3 + ch) * K;
                            const float* l = light.channel(ch);
                            for (int i = 0; i < K; ++i)
                                for (int j = 0; j < K; ++j)
                                    out[i] += M[std::size_t(i) * K + j] * double(l[j]);
                        }
                    }
            });
    }
    parallel_for(0, V, 128, Split::automatic, [&](std::size_t first, std::size_t last) {
        std::vector<double> M(std::size_t(K) * K), T(3 * std::size_t(K)), a(K), g(K);
        for (std::size_t v = first; v != last; ++v) {
            // T[colour][i]: the shadowed incident radiance M_v·L.
            std::fill(T.begin(), T.end(), 0.0);
            if (per_cluster) {
                const std::size_t c = code.cluster[v];
                for (std::size_t b = 0; b <= N; ++b) {
                    const double w = b == 0 ? 1.0 : double(code.weights[v * N + b - 1]);
                    const double* cl = cluster_light.data() + (c * (1 + N) + b) * 3 * K;
                    for (std::size_t i = 0; i < 3 * std::size_t(K); ++i) T[i] += w * cl[i];
                }
            } else {
                unpack_symmetric(transfer.receiver(v), Kt, K, M.data());
                for (int ch = 0; ch < 3; ++ch) {
                    const float* l = light.channel(ch);
                    for (int i = 0; i < K; ++i) {
                        const double* row = M.data() + std::size_t(i) * K;
                        double t = 0;
                        for (int j = 0; j < K; ++j) t += row[j] * double(l[j]);
                        T[std::size_t(ch) * K + i] = t;
                    }
                }
            }
            const Vec3d p = cast<double>(mesh.positions[v]);
            const Vec3d n = normalize(cast<double>(mesh.normals[v]));
            rotate_zonal(cosine.data(), K, n, a.data());
            const std::uint32_t brdf = brdf_table_index(mesh, options.material_brdfs, v);
            rotate_zonal(lobes[brdf].data(), K, reflect_view(n, p, eye), g.data());
            const Vec3f diffuse_colour = options.albedo.value_or(mesh.albedo[v]);
            const Vec3f specular_colour = options.albedo.value_or(brdfs[brdf].specular);
            const double rd[3] = {diffuse_colour.x, diffuse_colour.y, diffuse_colour.z};
            const double rs[3] = {specular_colour.x, specular_colour.y, specular_colour.z};
            double E[3], L[3];
            for (int ch = 0; ch < 3; ++ch) {
                double e = 0, s = 0;
                for (int i = 0; i < K; ++i) {
                    e += a[i] * T[std::size_t(ch) * K + i];
                    s += g[i] * T[std::size_t(ch) * K + i];
                }
                E[ch] = e;
                L[ch] = options.k * rd[ch] / kPi * e + (1 - options.k) * rs[ch] * s;
            }
            result.irradiance[v] = {float(E[0]), float(E[1]), float(E[2])};
            result.radiance[v] = {float(L[0]), float(L[1]), float(L[2])};
        }
    });
    return result;
}

TransferSet glossy_to_diffuse(const Mesh& mesh, const TransferSet& transfer) {
    check_glossy_shadable(mesh, transfer);
    const int K = transfer.layout.K;
    TransferInfo info = transfer;  // a shadowed set's layout in the matrices' domain and encoding
    info.kind = TransferKind::shadowed;
    info.layout = layout_for(info.kind, K, transfer.layout.domain, transfer.layout.encoding);
    const std::size_t V = transfer.receiver_count();
    const std::vector<Vec3f> normals = receiver_normals(mesh, transfer);  // vertices or texels
    TransferSet out = TransferSet::zeros(info, V);
    const std::vector<double> cosine = clamped_cosine_zonal(sh_bands_for(K));
    parallel_for(0, V, 128, Split::automatic, [&](std::size_t first, std::size_t last) {
        std::vector<double> M(std::size_t(K) * K), a(K);
        for (std::size_t v = first; v != last; ++v) {
            unpack_symmetric(transfer.receiver(v), K, K, M.data());
            rotate_zonal(cosine.data(), K, normalize(cast<double>(normals[v])), a.data());
            float* t = out.receiver(v);
            for (int i = 0; i < K; ++i) {
                double s = 0;
                for (int j = 0; j < K; ++j) s += M[std::size_t(i) * K + j] * a[j];
                t[i] = float(s);
            }
        }
    });
    return out;
}

TransferSet colours_as_transfer(const std::vector<Vec3f>& radiance) {
    TransferInfo info;
    info.kind = TransferKind::shadowed;
    info.layout.channels = 3;
    info.layout.K = 1;
    TransferSet out = TransferSet::zeros(info, radiance.size());
    for (std::size_t v = 0; v < radiance.size(); ++v) {
        out.receiver(v, 0)[0] = radiance[v].x;
        out.receiver(v, 1)[0] = radiance[v].y;
        out.receiver(v, 2)[0] = radiance[v].z;
    }
    return out;
}

ShLight light_for_colours() {
    ShLight light = ShLight::zero(1);
    for (int c = 0; c < 3; ++c) light.channel(c)[0] = 1;
    return light;
}

}  // namespace shprt
