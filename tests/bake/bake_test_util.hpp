// Helpers shared by the bake tests: a brute-force tracer (the host ray test over all triangles),
// small hand-made meshes, and the float-rounding bound of a length-S dot product.
#pragma once

#include "common/ray_triangle.hpp"
#include "shprt/bake/bake.hpp"
#include "shprt/transfer/sink.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/projection.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/trace/tracer.hpp"

#include <cmath>
#include <cstdint>
#include <mutex>
#include <string>
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

// Every ray against every triangle, Möller–Trumbore in double precision, two-sided, hits counted
// for tnear < t < tfar. Slow and obvious: the reference the Embree bake is compared with.
class BruteForceTracer final : public Tracer {
public:
    explicit BruteForceTracer(const Mesh& mesh) {
        for (const auto& tri : mesh.triangles) {
            const Vec3d a = cast<double>(mesh.positions[tri[0]]);
            m_tris.push_back({a, cast<double>(mesh.positions[tri[1]]) - a,
                              cast<double>(mesh.positions[tri[2]]) - a});
        }
    }

    void occluded(Vec3f origin, const Vec3f* dirs, int count, float tnear, float tfar,
                  std::uint8_t* occluded) const override {
        for (int i = 0; i < count; ++i)
            occluded[i] = closest(origin, dirs[i], tnear, tfar, true).hit ? 1 : 0;
    }
    Hit intersect(Vec3f origin, Vec3f dir, float tnear, float tfar) const override {
        return closest(origin, dir, tnear, tfar, false);
    }
    const char* name() const override { return "brute-force"; }
    std::size_t memory_bytes() const override { return m_tris.size() * sizeof(m_tris[0]); }

private:
    Hit closest(Vec3f of, Vec3f df, float tnear, float tfar, bool any) const {
        const Vec3d o = cast<double>(of), d = cast<double>(df);
        Hit best{false, 0xFFFFFFFFu, 0, 0, 0};
        double best_t = tfar;
        for (std::size_t k = 0; k < m_tris.size(); ++k) {
            const auto h = intersect_triangle(o, d, m_tris[k].a, m_tris[k].e1, m_tris[k].e2);
            if (!h || !(h->t > double(tnear) && h->t < best_t)) continue;
            best = Hit{true, std::uint32_t(k), float(h->t), float(h->u), float(h->v)};
            best_t = h->t;
            if (any) break;
        }
        return best;
    }
    struct Triangle {
        Vec3d a, e1, e2;  // vertex a and the edges to b and c
    };
    std::vector<Triangle> m_tris;
};

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

}  // namespace shprt::test
