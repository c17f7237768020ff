// Dynamic objects lit from transfer probes (shade/object_shade.hpp): the probes' incident
// radiance (a deferred radiance transfer volume, as Far Cry 3 used; Sloan, Kautz & Snyder 2002's
// neighbourhood transfer at points) against the object's own rotated self-transfer.
#include "shprt/shade/object_shade.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/shade/glossy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace shprt {

ObjectShadeOptions object_shade_options(const ShadingPlan& plan, ShadeView view) {
    ObjectShadeOptions o;
    o.view = view;
    if (plan.glossy) {
        o.k = plan.glossy->k;
        o.brdf = plan.glossy->brdf;
        o.material_brdfs = plan.glossy->material_brdfs;
        o.albedo = plan.glossy->albedo;
        o.K_used = plan.glossy->K_used;
    } else {
        o.k = plan.options.k;
        o.brdf = Brdf{BrdfModel::phong, plan.options.gloss};
        o.K_used = plan.options.K_used;
    }
    return o;
}

void check_probes(const ProbeGrid& grid, const std::string& source) {
    SHPRT_CHECK(!grid.empty(), invalid_argument,
                "{}: the file has no transfer probes (bake it with shprt bake --probes)", source);
    grid.validate();
}

std::string clamped_warning(const ProbeGrid& grid, Vec3f p, const std::string& option) {
    const Vec3f a = grid.origin, b = grid.far_corner();
    return fmt::format(
        "{} {},{},{} is outside the probe grid ({},{},{} to {},{},{}): the object is "
        "lit from the grid's nearest edge",
        option, p.x, p.y, p.z, a.x, a.y, a.z, b.x, b.y, b.z);
}

ObjectShading shade_object(const DynamicObject& object, const ObjectPose& pose,
                           const ProbeGrid& grid, const ShLight& light,
                           const ObjectShadeOptions& options) {
    const Mesh& mesh = object.mesh;
    check_probes(grid, mesh.source.empty() ? std::string("object") : mesh.source);
    check(pose);
    SHPRT_CHECK(light.K > 0 && light.coeffs.size() == 3 * std::size_t(light.K), invalid_argument,
                "light has K = {} and {} coefficients (expected 3 × K)", light.K,
                light.coeffs.size());
    SHPRT_CHECK(options.k >= 0 && options.k <= 1, invalid_argument,
                "diffuse share k = {} is outside [0, 1]", options.k);
    SHPRT_CHECK(options.K_used >= 0, invalid_argument, "K' = {} must be ≥ 0", options.K_used);
    if (options.albedo) {
        const Vec3f a = *options.albedo;
        SHPRT_CHECK(a.x >= 0 && a.x <= 1 && a.y >= 0 && a.y <= 1 && a.z >= 0 && a.z <= 1,
                    invalid_argument, "albedo ({}, {}, {}) must be in [0, 1]", a.x, a.y, a.z);
    }
    const bool self = !object.self.coeffs.empty();
    if (self) {
        check_shadable(mesh, object.self);
        SHPRT_CHECK(object.self.layout.channels == 1, invalid_argument,
                    "an object's self-transfer has one channel (got {})",
                    object.self.layout.channels);
    }
    const ShadeView view = options.view;
    const bool glossy = options.k < 1 && view == ShadeView::radiance;

    int K = std::min(grid.K, light.K);
    if (self) K = std::min(K, object.self.layout.K);
    if (options.K_used > 0) K = std::min(K, options.K_used);
    const int bands = sh_bands_for(K);
    const Mat3d R = object_rotation(pose);
    const bool turned = !(R == Mat3d::identity());
    const ShRotation D = self && turned ? ShRotation::from_matrix(R, bands) : ShRotation();
    const std::vector<double> cosine = self ? std::vector<double>{} : clamped_cosine_zonal(bands);
    // The BRDF table of the glossy term and each entry's zonal lobe.
    std::vector<Brdf> table;
    std::vector<std::vector<double>> lobes;
    if (glossy) {
        table = brdf_table(mesh, options.material_brdfs, options.brdf);
        for (const Brdf& b : table) lobes.push_back(brdf_lobe(b, bands).zonal);
    }
    // The light shaded with: the transfer view's uniform white sky (c_0 = √(4π)), else the light.
    std::vector<double> L(3 * std::size_t(K), 0.0);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < K; ++i)
            L[c * K + i] = view == ShadeView::transfer ? (i == 0 ? std::sqrt(4 * kPi) : 0.0)
                                                       : double(light.channel(c)[i]);

    const std::size_t V = mesh.vertex_count();
    ObjectShading out;
    out.K_used = K;
    out.positions.resize(V);
    out.normals.resize(V);
    out.albedo.resize(V);
    out.irradiance.resize(V);
    out.radiance.resize(V);
    {
        const ProbeSample at = sample_probes(grid, pose.position);
        out.clamped = at.clamped;
        out.no_valid = at.no_valid;
    }
    const Vec3d position = cast<double>(pose.position), pivot = cast<double>(object.pivot);
    const Vec3d eye = cast<double>(options.eye);
    const std::size_t KK = std::size_t(grid.K) * std::size_t(grid.K);
    parallel_for(0, V, 64, Split::automatic, [&](std::size_t first, std::size_t last) {
        std::vector<double> L_in(3 * std::size_t(K)), a(K), in(K), g(glossy ? K : 0);
        for (std::size_t v = first; v != last; ++v) {
            const Vec3d p =
                position + R * (cast<double>(mesh.positions[v]) - pivot) * double(pose.scale);
            const Vec3d n = normalize(R * cast<double>(mesh.normals[v]));
            out.positions[v] = cast<float>(p);
            out.normals[v] = cast<float>(n);
            const ProbeSample s = sample_probes(grid, cast<float>(p));
            for (int c = 0; c < 3; ++c) {
                const float* M = s.matrix.data() + (grid.channels == 3 ? c : 0) * KK;
                for (int i = 0; i < K; ++i) {
                    double sum = 0;
                    for (int j = 0; j < K; ++j) sum += double(M[i * grid.K + j]) * L[c * K + j];
                    L_in[c * K + i] = sum;
                }
            }
            if (self) {
                const float* t = object.self.receiver(v, 0);
                if (turned) {
                    for (int i = 0; i < K; ++i) in[i] = t[i];
                    D.apply(in.data(), a.data(), K);
                } else {
                    for (int i = 0; i < K; ++i) a[i] = t[i];
                }
            } else {
                rotate_zonal(cosine.data(), K, n, a.data());
            }
            double E[3];
            for (int c = 0; c < 3; ++c) {
                double sum = 0;
                for (int i = 0; i < K; ++i) sum += a[i] * L_in[c * K + i];
                E[c] = sum;
            }
            const Vec3f albedo = options.albedo.value_or(mesh.albedo[v]);
            out.albedo[v] = albedo;
            out.irradiance[v] = {float(E[0]), float(E[1]), float(E[2])};
            if (view == ShadeView::irradiance) {
                out.radiance[v] = out.irradiance[v];
                continue;
            }
            if (view == ShadeView::transfer) {
                const float grey = float(E[0] / kPi);
                out.radiance[v] = {grey, grey, grey};
                continue;
            }
            const double rho[3] = {albedo.x, albedo.y, albedo.z};
            double Lo[3];
            for (int c = 0; c < 3; ++c) Lo[c] = rho[c] / kPi * E[c];
            if (glossy) {
                const std::uint32_t entry = brdf_table_index(mesh, options.material_brdfs, v);
                const Vec3d r = reflect_view(n, p, eye);
                rotate_zonal(lobes[entry].data(), K, r, g.data());
                const Vec3d to_eye = eye - p;
                const Vec3d w = length(to_eye) > 0 ? normalize(to_eye) : n;
                double V_r = 1;
                if (self) {
                    double ag = 0;
                    for (int i = 0; i < K; ++i) ag += a[i] * g[i];
                    V_r = ag / std::max(dot(n, w), kMinCosEta);
                }
                const Vec3f spec = options.albedo.value_or(table[entry].specular);
                const double rho_s[3] = {spec.x, spec.y, spec.z};
                for (int c = 0; c < 3; ++c) {
                    double lobe_light = 0;
                    for (int i = 0; i < K; ++i) lobe_light += g[i] * L_in[c * K + i];
                    Lo[c] = options.k * Lo[c] + (1 - options.k) * rho_s[c] * lobe_light * V_r;
                }
            }
            out.radiance[v] = {float(Lo[0]), float(Lo[1]), float(Lo[2])};
        }
    });
    return out;
}

const std::vector<OptionRow<ObjectChoice>>& object_option_table() {
    static const std::vector<OptionRow<ObjectChoice>> table = [] {
        using C = ObjectChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "object", &C::object,
                "A mesh (any scene file) lit from the file's transfer probes (docs/probes.md)");
        add_row(t, "at", &C::at, "X,Y,Z: where the object's centre goes (with --object)");
        add_row(t, "object_scale", &C::object_scale, "The object's uniform scale (default 1)");
        add_row(t, "object_rotate", &C::object_rotate,
                "YAW,PITCH,ROLL in degrees: the object's rotation, as --rotate of lights");
        return complete_rows(std::move(t));
    }();
    return table;
}

std::optional<ObjectPose> object_pose_from(const ObjectChoice& c) {
    if (c.object.empty()) {
        SHPRT_CHECK(c.at.empty() && c.object_rotate.empty() && c.object_scale == 1,
                    invalid_argument,
                    "--at, --object-scale and --object-rotate place an object: give --object MESH");
        return std::nullopt;
    }
    SHPRT_CHECK(!c.at.empty(), invalid_argument, "--object {}: give its position with --at X,Y,Z",
                c.object);
    const std::vector<double> at = parse_numbers(c.at, 3, "--at X,Y,Z");
    ObjectPose pose;
    pose.position = {float(at[0]), float(at[1]), float(at[2])};
    SHPRT_CHECK(c.object_scale > 0 && std::isfinite(c.object_scale), invalid_argument,
                "--object-scale {}: must be a finite number > 0", c.object_scale);
    pose.scale = float(c.object_scale);
    if (!c.object_rotate.empty()) pose.yaw_pitch_roll_deg = parse_yaw_pitch_roll(c.object_rotate);
    check(pose);
    return pose;
}

}  // namespace shprt
