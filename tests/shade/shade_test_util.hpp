// Helpers of the shading tests (tests/shade/) and the rendering tests: analytic transfer of
// unoccluded surfaces, lights with known coefficients, a brute-force ray caster that interpolates
// per-vertex values (the reference a rasteriser must agree with), and a temporary directory.
// No GL: the GL helpers are in tests/render/render_test_util.hpp.
#pragma once

#include "common/ray_triangle.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/bake/texels.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/transfer/transfer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace shprt::test {

// A texel-domain bake of `mesh` over its UV atlas at side × side texels, with `options` (the
// transfer kind, K, samples, threads), as `shprt bake --domain texel` makes one.
inline TransferSet texel_bake(const Mesh& mesh, int side, const BakeOptions& options) {
    const TexelSamples texels = rasterize_texels(mesh, side, side);
    HostSink sink;
    TransferSet t;
    static_cast<TransferInfo&>(t) =
        bake(BakeJob{&mesh, texel_receivers(texels), &sink, nullptr, nullptr, nullptr}, options);
    t.texels = texel_atlas(texels, 0);
    t.coeffs = sink.take_rows();
    return t;
}

// builtin:quad_box with a material BRDF, GGX of roughness 0.4, on its floor (the first quad) and
// none on the box.
inline Mesh quad_box_with_glossy_floor() {
    Mesh mesh = make_builtin("quad_box");
    mesh.brdfs = {Brdf{BrdfModel::ggx, 0.4}};
    mesh.brdf_index.assign(mesh.vertex_count(), Mesh::kNoBrdf);
    for (int v = 0; v < 4; ++v) mesh.brdf_index[v] = 0;
    return mesh;
}

// Unshadowed transfer of every vertex computed analytically: the clamped cosine about the
// vertex normal, c_i = rotate_zonal(clamped_cosine_zonal) (exact up to float rounding). With 3
// channels, channel c is scaled by channel_scale[c].
inline TransferSet analytic_transfer(const Mesh& mesh, int K, int channels = 1,
                                     const double channel_scale[3] = nullptr) {
    TransferSet t;
    t.kind = TransferKind::unshadowed;
    t.layout.K = K;
    t.layout.channels = channels;
    t.coeffs.resize(mesh.vertex_count() * channels * std::size_t(K));
    const std::vector<double> z = clamped_cosine_zonal(sh_bands_for(K));
    std::vector<double> c(K);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        rotate_zonal(z.data(), K, normalize(cast<double>(mesh.normals[v])), c.data());
        for (int ch = 0; ch < channels; ++ch) {
            const double s = channel_scale ? channel_scale[ch] : 1.0;
            float* out = t.coeffs.data() + (v * channels + ch) * std::size_t(K);
            for (int i = 0; i < K; ++i) out[i] = static_cast<float>(s * c[i]);
        }
    }
    return t;
}

// A smooth, positive light of basis size K whose first `nonzero` coefficients per channel are
// set (deterministic pseudo-random, c_0 dominant) and the rest zero: band-limited by
// construction, so its radiance is exactly light_radiance(light, d).
inline ShLight smooth_light(int K, int nonzero, unsigned seed = 1) {
    ShLight light = ShLight::zero(K);
    unsigned state = seed * 2654435761u + 12345u;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return double(state >> 8) / double(1u << 24) - 0.5;  // [−0.5, 0.5)
    };
    for (int c = 0; c < 3; ++c) {
        float* ch = light.channel(c);
        ch[0] = static_cast<float>(std::sqrt(4 * kPi) * (1.0 + 0.2 * c));
        for (int i = 1; i < std::min(K, nonzero); ++i) ch[i] = static_cast<float>(0.6 * next());
    }
    return light;
}

// Closest hit of a ray with the mesh (every triangle, two-sided, double precision) and the
// perspective-correct interpolation of a per-vertex value there (= barycentric in 3D, what a
// rasteriser interpolates). Returns false if nothing is hit.
inline bool trace_interpolate(const Mesh& mesh, const std::vector<Vec3f>& values, Vec3f origin,
                              Vec3f direction, Vec3d& value, double& t_hit) {
    const Vec3d o = cast<double>(origin), d = cast<double>(direction);
    t_hit = 1e300;
    bool hit = false;
    for (const auto& tri : mesh.triangles) {
        const Vec3d a = cast<double>(mesh.positions[tri[0]]);
        const auto h = intersect_triangle(o, d, a, cast<double>(mesh.positions[tri[1]]) - a,
                                          cast<double>(mesh.positions[tri[2]]) - a);
        if (!h || h->t <= 0 || h->t >= t_hit) continue;
        const double u = h->u, v = h->v;
        t_hit = h->t;
        hit = true;
        value = cast<double>(values[tri[0]]) * (1 - u - v) + cast<double>(values[tri[1]]) * u +
                cast<double>(values[tri[2]]) * v;
    }
    return hit;
}

// A fresh directory under the system temp dir, named after the running test; removed by the
// destructor.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = std::filesystem::temp_directory_path() /
                 ("shprt_render_" + std::to_string(::getpid()) + "_" + info->test_suite_name() +
                  "_" + info->name());
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() { std::filesystem::remove_all(m_path); }
    std::string file(const std::string& name) const { return (m_path / name).string(); }
    const std::filesystem::path& path() const { return m_path; }

private:
    std::filesystem::path m_path;
};

}  // namespace shprt::test
