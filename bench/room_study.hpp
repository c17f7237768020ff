// What the room studies of issue 39 share (bench_local_directions, bench_edge_refine): the room's
// light, per-vertex luminance under it, the 65536-sample reference luminance (cached on disk, it
// takes a minute), the relative RMS error against it, and each receiver's true error
// ‖ĉ − c‖/‖c_open‖ (docs/sampling.md).
#pragma once

#include "shprt/bake/bake.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/trace/tracer.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace shprt::room_study {

// The room's light: a gradient sky plus a 2° sun.
inline ShLight light(int K) { return make_light({"gradient", "sun:0.4,0.8,-0.3,2"}, K); }
inline constexpr const char* kLightName = "gradient sky + 2 degree sun (sun:0.4,0.8,-0.3,2)";

// The light's luminance coefficients: 0.2126 R + 0.7152 G + 0.0722 B.
inline std::vector<double> luminance_light(const ShLight& light) {
    std::vector<double> l(static_cast<std::size_t>(light.K));
    for (int i = 0; i < light.K; ++i)
        l[std::size_t(i)] = 0.2126 * light.channel(0)[i] + 0.7152 * light.channel(1)[i] +
                            0.0722 * light.channel(2)[i];
    return l;
}

// Luminance of every receiver's irradiance under the light (rows of K coefficients).
inline std::vector<double> luminance(const std::vector<float>& rows, int K, const ShLight& light) {
    const std::vector<double> l = luminance_light(light);
    const std::size_t V = rows.size() / std::size_t(K);
    std::vector<double> y(V);
    for (std::size_t v = 0; v < V; ++v) {
        double e = 0;
        for (int i = 0; i < K; ++i)
            e += double(rows[v * std::size_t(K) + std::size_t(i)]) * l[std::size_t(i)];
        y[v] = e;
    }
    return y;
}

inline double relative_rms(const std::vector<double>& a, const std::vector<double>& ref) {
    double num = 0, den = 0;
    for (std::size_t v = 0; v < a.size(); ++v) {
        num += (a[v] - ref[v]) * (a[v] - ref[v]);
        den += ref[v] * ref[v];
    }
    return std::sqrt(num / den);
}

// Each receiver's true error ‖ĉ − c‖ / ‖c_open‖ (docs/sampling.md).
inline std::vector<double> true_errors(const std::vector<float>& got, const std::vector<float>& ref,
                                       int K) {
    const double open = open_transfer_norm(K);
    std::vector<double> e(got.size() / std::size_t(K));
    for (std::size_t r = 0; r < e.size(); ++r) {
        double sum = 0;
        for (std::size_t i = r * std::size_t(K); i < (r + 1) * std::size_t(K); ++i)
            sum += (double(got[i]) - ref[i]) * (double(got[i]) - ref[i]);
        e[r] = std::sqrt(sum) / open;
    }
    return e;
}

// The reference luminance: a sphere Sobol bake of `samples` with seed 7919 (another seed than
// the studies' 1), read from `cache` when it holds this mesh's, K's and S's, else baked and
// written there.
inline std::vector<double> reference_luminance(const Mesh& mesh, const Tracer& tracer,
                                               const ShLight& light, int K, std::uint32_t samples,
                                               int threads, const std::string& cache) {
    std::vector<double> ref;
    {
        std::ifstream in(cache, std::ios::binary);
        std::uint64_t header[3] = {};
        if (in && in.read(reinterpret_cast<char*>(header), sizeof(header)) &&
            header[0] == mesh.vertex_count() && header[1] == std::uint64_t(K) &&
            header[2] == samples) {
            ref.resize(mesh.vertex_count());
            in.read(reinterpret_cast<char*>(ref.data()), std::streamsize(ref.size() * 8));
            std::printf("\nreference: %s (cached)\n", cache.c_str());
            return ref;
        }
    }
    const auto start = std::chrono::steady_clock::now();
    BakeOptions o;
    o.K = K;
    o.samples = samples;
    o.seed = 7919;
    o.threads = threads;
    o.sampler = SamplerKind::sobol;
    o.direction_frame = DirectionFrame::sphere;
    ref = luminance(bake_with_tracer(mesh, o, bake_direction_set(o), tracer).coeffs, K, light);
    std::printf("\nreference: sphere Sobol S = %u, seed 7919, %.1f s\n", samples,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::ofstream out(cache, std::ios::binary);
    const std::uint64_t header[3] = {mesh.vertex_count(), std::uint64_t(K), samples};
    out.write(reinterpret_cast<const char*>(header), sizeof(header));
    out.write(reinterpret_cast<const char*>(ref.data()), std::streamsize(ref.size() * 8));
    return ref;
}

}  // namespace shprt::room_study
