// The test light L(w) = 1 + d·w of the texel and refinement tests: non-negative and exactly two SH
// bands, so an SH bake and the direct ground truth (bake/ground_truth.hpp) integrate the same
// light and differ only by sampling and interpolation.
#pragma once

#include "shprt/bake/ground_truth.hpp"
#include "shprt/sh/zonal.hpp"

#include <cmath>
#include <vector>

namespace shprt::test {

inline const Vec3d kLinearLightDir = normalize(Vec3d{0.6, 0.8, 0.3});

// The light's first K SH coefficients (zonal z_0 = 2√π, z_1 = √(4π/3) rotated to d).
inline std::vector<double> linear_light_coeffs(int K) {
    const double pi = 3.14159265358979323846;
    const double zonal[2] = {2 * std::sqrt(pi), std::sqrt(4 * pi / 3)};
    std::vector<double> c(std::size_t(K), 0.0);
    rotate_zonal(zonal, K < 4 ? K : 4, kLinearLightDir, c.data());
    return c;
}

// The ground truth of every vertex of `mesh` under the light (2 threads).
inline GroundTruth linear_light_truth(const Mesh& mesh, std::uint32_t sky_samples) {
    GroundTruthLight light;
    light.sky = [](Vec3d w) {
        const double l = 1 + dot(kLinearLightDir, w);
        return Vec3d{l, l, l};
    };
    GroundTruthOptions options;
    options.sky_samples = sky_samples;
    options.threads = 2;
    return ground_truth_irradiance(mesh, light, options);
}

}  // namespace shprt::test
