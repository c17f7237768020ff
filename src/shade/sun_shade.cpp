// A sun kept out of the SH sum (shade/sun_shade.hpp): the direct light traced with Embree at each
// receiver, the bounced light from T − T_0, the sky from T. The split is the one games use with
// precomputed light (Enlighten; Far Cry 3's deferred radiance transfer): the direct sun drawn
// sharp, the bounces precomputed. Disc sampling: light/sun.hpp (Shirley & Chiu 1997).
#include "shprt/shade/sun_shade.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/trace/ray.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <cstdint>
#include <limits>

namespace shprt {
namespace {

// The bounced part T − T_0 of an interreflected set: T_0 (TransferSet::direct, one channel)
// subtracted from each channel, with the set's layout and no direct part.
TransferSet indirect_part(const TransferSet& transfer) {
    TransferLayout one = transfer.layout;
    one.channels = 1;
    const std::size_t R = transfer.receiver_count(), n = transfer.layout.floats_per_channel();
    SHPRT_CHECK(transfer.direct.size() == R * n, invalid_argument,
                "the direct part has {} floats for {} receivers of {}", transfer.direct.size(), R,
                n);
    TransferSet out = transfer;
    out.direct.clear();
    out.cpca = {};  // the rows are no longer the code's
    for (std::size_t r = 0; r < R; ++r) {
        const float* t0 = transfer.direct.data() + one.offset(r, 0);
        for (int c = 0; c < transfer.layout.channels; ++c) {
            float* t = out.receiver(r, c);
            for (std::size_t i = 0; i < n; ++i) t[i] -= t0[i];
        }
    }
    return out;
}

// Traces the sun's disc directions `dirs` above each receiver's horizon (the rest bring nothing)
// and calls visit(v, d) for each unoccluded one, in order, per receiver on one thread: the same
// bits for any thread count.
template <class Visit>
void trace_disc(const Tracer& tracer, const std::vector<Vec3f>& positions,
                const std::vector<Vec3f>& normals, const std::vector<Vec3d>& dirs, Visit&& visit) {
    SHPRT_CHECK(positions.size() == normals.size(), invalid_argument,
                "the sun's trace: {} positions but {} normals", positions.size(), normals.size());
    const int N = static_cast<int>(dirs.size());
    std::vector<Vec3f> dirs_f(dirs.size());
    for (std::size_t j = 0; j < dirs.size(); ++j) dirs_f[j] = cast<float>(dirs[j]);
    const float inf = std::numeric_limits<float>::infinity();
    parallel_for(0, positions.size(), 64, Split::automatic,
                 [&](std::size_t first, std::size_t last) {
                     std::vector<Vec3f> up(N);
                     std::vector<int> index(N);
                     std::vector<std::uint8_t> hit(N);
                     for (std::size_t v = first; v != last; ++v) {
                         const Vec3d n = normalize(cast<double>(normals[v]));
                         int m = 0;
                         for (int j = 0; j < N; ++j)
                             if (dot(n, dirs[j]) > 0) {
                                 up[m] = dirs_f[j];
                                 index[m++] = j;
                             }
                         if (m == 0) continue;
                         tracer.occluded(offset_ray_origin(positions[v], cast<float>(n)), up.data(),
                                         m, 0.0f, inf, hit.data());
                         for (int j = 0; j < m; ++j)
                             if (!hit[j]) visit(v, dirs[std::size_t(index[j])]);
                     }
                 });
}

}  // namespace

std::vector<Vec3f> sun_direct_irradiance(const Tracer& tracer, const std::vector<Vec3f>& positions,
                                         const std::vector<Vec3f>& normals, const Sun& sun,
                                         const SunShadeOptions& options) {
    const std::vector<Vec3d> dirs = sun_disc_directions(sun, options.disc_samples, options.seed);
    // Each direction stands for Ω/N of the disc (sun_disc_directions: uniform in solid angle).
    const Vec3d weight = sun.radiance * (sun_solid_angle(sun) / double(dirs.size()));
    std::vector<double> sum(positions.size(), 0.0);
    trace_disc(tracer, positions, normals, dirs, [&](std::size_t v, const Vec3d& d) {
        sum[v] += dot(normalize(cast<double>(normals[v])), d);
    });
    std::vector<Vec3f> out(positions.size());
    for (std::size_t v = 0; v < out.size(); ++v) out[v] = cast<float>(weight * sum[v]);
    return out;
}

SunShadeResult shade_with_sun(const Mesh& mesh, const TransferSet& transfer, const ShLight& sky,
                              const PreparedSun& sun, const ShadeOptions& options,
                              const SunShadeOptions& sun_options) {
    SHPRT_CHECK(options.k == 1, unsupported,
                "a traced sun lights diffuse receivers only (k = 1, got {}): the glossy term under "
                "a traced sun is not implemented; a sun: light projects the sun into SH for it",
                options.k);
    SHPRT_CHECK(!is_matrix(transfer.layout), unsupported,
                "a traced sun lights diffuse transfer only: {} transfer (glossy matrices) is not "
                "implemented with it; a sun: light projects the sun into SH for it",
                to_string(transfer.layout.shape));
    const bool texel = is_texel(transfer.layout);
    SunShadeResult result;
    static_cast<ShadeResult&>(result) = shade_receivers(mesh, transfer, sky, options, nullptr);
    // The sun's bounced light: T − T_0 under its SH projection (interreflected files only; their
    // receivers are vertices).
    ShadeResult bounced;
    result.bounced = !transfer.direct.empty();
    if (result.bounced)
        bounced = shade_receivers(mesh, indirect_part(transfer), sun.sh, options, nullptr);

    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    std::vector<Vec3f> albedo;
    if (texel) {
        TexelPoints points = texel_points(mesh, transfer);
        result.sun_direct = sun_direct_irradiance(*tracer, points.points.positions,
                                                  points.points.normals, sun.sun, sun_options);
        albedo = std::move(points.points.albedo);
    } else {
        result.sun_direct =
            sun_direct_irradiance(*tracer, mesh.positions, mesh.normals, sun.sun, sun_options);
        albedo = mesh.albedo;
    }
    for (std::size_t r = 0; r < result.irradiance.size(); ++r) {
        const Vec3d d = cast<double>(result.sun_direct[r]);
        Vec3d E = cast<double>(result.irradiance[r]) + d;
        const Vec3d rho = cast<double>(albedo[r]);
        Vec3d L =
            cast<double>(result.radiance[r]) + Vec3d{rho.x * d.x, rho.y * d.y, rho.z * d.z} / kPi;
        if (result.bounced) {
            E += cast<double>(bounced.irradiance[r]);
            L += cast<double>(bounced.radiance[r]);
        }
        result.irradiance[r] = cast<float>(E);
        result.radiance[r] = cast<float>(L);
    }
    return result;
}

SunShadeResult shade_glossy_with_sun(const Mesh& mesh, const TransferSet& transfer,
                                     const ShLight& sky, const PreparedSun& sun,
                                     const GlossyShadeOptions& options,
                                     const SunShadeOptions& sun_options) {
    SHPRT_CHECK(!is_texel(transfer.layout), unsupported,
                "a sun kept out of the SH sum lights glossy matrices per vertex only: texel "
                "matrices are refused with it; a sun: light projects the sun into SH");
    SunShadeResult result;
    static_cast<ShadeResult&>(result) = shade_glossy(mesh, transfer, sky, options);
    const std::vector<Brdf> brdfs = brdf_table(mesh, options.material_brdfs, options.brdf);
    std::vector<BrdfProfile> profiles;
    for (const Brdf& b : brdfs) profiles.push_back(brdf_profile(b));
    const std::vector<Vec3d> dirs =
        sun_disc_directions(sun.sun, sun_options.disc_samples, sun_options.seed);
    const double share = sun_solid_angle(sun.sun) / double(dirs.size());  // Ω/N
    // Per vertex: Σ n·d_j and Σ f(r·d_j) over the unoccluded disc directions.
    const std::size_t V = mesh.vertex_count();
    std::vector<double> cosines(V, 0.0), lobe(V, 0.0);
    std::vector<Vec3d> reflected(V);
    const Vec3d eye = cast<double>(options.eye);
    for (std::size_t v = 0; v < V; ++v)
        reflected[v] = reflect_view(normalize(cast<double>(mesh.normals[v])),
                                    cast<double>(mesh.positions[v]), eye);
    const std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    trace_disc(*tracer, mesh.positions, mesh.normals, dirs, [&](std::size_t v, const Vec3d& d) {
        cosines[v] += dot(normalize(cast<double>(mesh.normals[v])), d);
        lobe[v] +=
            profiles[brdf_table_index(mesh, options.material_brdfs, v)](dot(reflected[v], d));
    });
    result.sun_direct.resize(V);
    for (std::size_t v = 0; v < V; ++v) {
        // E as the diffuse split adds it: rounded to its float first.
        result.sun_direct[v] = cast<float>(sun.sun.radiance * (share * cosines[v]));
        const Vec3d E = cast<double>(result.sun_direct[v]);
        const Vec3d S = sun.sun.radiance * (share * lobe[v]);
        const std::uint32_t b = brdf_table_index(mesh, options.material_brdfs, v);
        const Vec3d rd = cast<double>(options.albedo.value_or(mesh.albedo[v])) * options.k / kPi;
        const Vec3d rs = cast<double>(options.albedo.value_or(brdfs[b].specular)) * (1 - options.k);
        result.irradiance[v] = cast<float>(cast<double>(result.irradiance[v]) + E);
        result.radiance[v] = cast<float>(
            cast<double>(result.radiance[v]) +
            Vec3d{rd.x * E.x + rs.x * S.x, rd.y * E.y + rs.y * S.y, rd.z * E.z + rs.z * S.z});
    }
    return result;
}

}  // namespace shprt
