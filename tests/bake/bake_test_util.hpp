// Helpers shared by the bake tests: the brute-force tracer (common/brute_force_tracer.hpp),
// small hand-made meshes (a quad, the open spherical cavity), and the float-rounding bound of a
// length-S dot product.
#pragma once

#include "common/brute_force_tracer.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/tracer.hpp"
#include "shprt/transfer/sink.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace shprt::test {

// A sink that records every write() (the range, and whether rows came with it) and keeps the rows
// in a HostSink. With offer_host_rows the bake projects into those rows directly; with `device`
// set it offers that device buffer.
class RecordingSink final : public TransferSink {
public:
    struct Write {
        std::size_t first, count;
        bool had_rows;
    };
    void begin(const TransferLayout& layout, std::size_t first, std::size_t count) override {
        host.begin(layout, first, count);
        ++begins;
    }
    float* host_rows(std::size_t first, std::size_t count) override {
        return offer_host_rows ? host.host_rows(first, count) : nullptr;
    }
    float* device_rows() override { return device; }
    void write(std::size_t first, std::size_t count, const float* rows) override {
        const std::lock_guard<std::mutex> lock(mutex);
        writes.push_back({first, count, rows != nullptr});
        if (rows) host.write(first, count, rows);
    }
    void finish() override { ++finishes; }

    HostSink host;
    std::vector<Write> writes;
    std::mutex mutex;
    bool offer_host_rows = false;
    float* device = nullptr;
    int begins = 0, finishes = 0;
};

// Options for a small bake cut into many chunks (64 receivers each): the progressive-bake tests.
inline BakeOptions small_chunked_options() {
    BakeOptions o;
    o.K = 16;
    o.samples = 128;
    o.seed = 7;
    o.threads = 2;
    o.chunk_receivers = 64;
    return o;
}

// bake() of every vertex of `mesh` into `sink`, with `directions` when given.
inline TransferInfo bake_into(const Mesh& mesh, const BakeOptions& options, TransferSink& sink,
                              const DirectionSet* directions = nullptr) {
    BakeJob job;
    job.occluders = &mesh;
    job.receivers = vertex_receivers(mesh);
    job.sink = &sink;
    job.directions = directions;
    return bake(job, options);
}

// The GPU bake through bake()'s seams: every vertex into host memory, or (device non-null) into
// a DeviceSink over that device buffer of V·K floats (the result's coeffs are then empty).
inline TransferSet bake_gpu(const Mesh& mesh, BakeOptions options, const DirectionSet& set,
                            float* device = nullptr) {
    options.device = Device::cuda;
    if (!device) return bake(mesh, options, set);
    DeviceSink sink(device, mesh.vertex_count() * std::size_t(options.K));
    TransferSet out;
    static_cast<TransferInfo&>(out) = bake_into(mesh, options, sink, &set);
    return out;
}

// Unit round-off of float.
inline constexpr double kFloatEps = 5.9604644775390625e-8;  // 2^-24

// Bound on the float rounding of coefficient i of a bake with direction set `set`:
// |Σ_s W_s Y_si computed in float − exact| ≤ (S + 8)·u·Σ_s weight_s·|Y_si| (the classic dot
// product bound γ_S, plus a few roundings for the cosine, the weight and the table entry; W_s ≤
// weight_s). A single visibility difference that is not grazing exceeds it by orders of
// magnitude.
inline std::vector<double> float_dot_bounds(int K, const DirectionSet& set) {
    const std::vector<float> Y = basis_table(K, set);
    std::vector<double> bound(K, 0.0);
    for (std::size_t s = 0; s < set.size(); ++s)
        for (int i = 0; i < K; ++i)
            bound[i] += double(set.weights[s]) * std::fabs(double(Y[s * K + i]));
    for (double& b : bound) b *= double(set.size() + 8) * kFloatEps;
    return bound;
}

// Appends a quad (a, b, c, d counter-clockwise seen from the side `normal` points to) with its
// own four vertices.
inline void add_quad(Mesh& m, Vec3f a, Vec3f b, Vec3f c, Vec3f d, Vec3f normal) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (Vec3f p : {a, b, c, d}) {
        m.positions.push_back(p);
        m.normals.push_back(normal);
        m.albedo.push_back({0.5f, 0.5f, 0.5f});
    }
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
}

// The inside of a unit sphere (icosphere, `level`) with the cap y > cap_y cut away (triangles
// whose centroid is above it), a cavity open to the sky: vertex normals point inward; triangles
// wind counter-clockwise seen from inside (their front faces the cavity) when front_inside, else
// as the icosphere does (the cavity is the back of a closed surface's faces). Only the kept
// triangles' vertices. The closed form (docs/interreflection.md): every point sees any part of a
// sphere with a view factor equal to its share of the area, so under a constant sky L the bounce
// b irradiance is E_b = π·L·f·(ρ(1 − f))^b, f the opening's share (1/4 for cap_y = 0.5).
inline Mesh spherical_cavity(int level, double cap_y, Vec3f albedo, bool front_inside = true) {
    MeshBuilder b;
    b.add_icosphere({0, 0, 0}, 1.0, level, albedo);
    const Mesh sphere = b.take_mesh("test:cavity");
    Mesh m;
    m.source = "test:cavity";
    std::vector<std::uint32_t> remap(sphere.vertex_count(), ~0u);
    for (const auto& tri : sphere.triangles) {
        const Vec3f c =
            (sphere.positions[tri[0]] + sphere.positions[tri[1]] + sphere.positions[tri[2]]) / 3.0f;
        if (c.y > cap_y) continue;
        std::array<std::uint32_t, 3> out{};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = tri[k];
            if (remap[v] == ~0u) {
                remap[v] = static_cast<std::uint32_t>(m.positions.size());
                m.positions.push_back(sphere.positions[v]);
                m.normals.push_back(-normalize(sphere.positions[v]));
                m.albedo.push_back(albedo);
            }
            out[k] = remap[v];
        }
        if (front_inside) std::swap(out[1], out[2]);
        m.triangles.push_back(out);
    }
    return m;
}

}  // namespace shprt::test
