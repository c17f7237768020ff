// Per-vertex transfer: what a bake produces, what .shprt files store, what shading consumes.
#pragma once

#include "shprt/core/progress.hpp"
#include "shprt/sh/sampler.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

enum class TransferKind {
    unshadowed,  // T(w) = max(0, n·w)
    shadowed,    // T(w) = V(w) · max(0, n·w), V = 1 where the ray escapes the scene
};

enum class Device { cpu, cuda, automatic };

const char* to_string(TransferKind kind);
TransferKind parse_transfer_kind(const std::string& name);  // throws Error(invalid_argument)
const char* to_string(Device device);
Device parse_device(const std::string& name);  // "cpu", "cuda", "auto"; throws Error

// Timings (seconds) and counters of one bake, stored in the file's metadata.
struct BakeStats {
    double seconds_bvh = 0, seconds_trace = 0, seconds_project = 0, seconds_total = 0;
    std::uint64_t rays_cast = 0;        // rays actually traced (below-horizon rays are not cast)
    std::uint64_t peak_bytes_host = 0;  // bake's peak working memory with its BVH, host
    std::uint64_t peak_bytes_device = 0;
    std::string device_name;  // "cpu: 2 threads" or the GPU's name
};

// Transfer coefficients, vertex-major: coeffs[(v * channels + c) * K + i] is coefficient i (flat
// SH index, paper convention) of channel c at vertex v. Diffuse transfer has one channel.
struct TransferSet {
    TransferKind kind = TransferKind::shadowed;
    int K = 0;         // basis size: the first K coefficients in index order
    int channels = 1;  // 1 (grey transfer) or 3 (RGB, e.g. with interreflections)
    std::vector<float> coeffs;

    // Sampling that produced it (recorded in the file).
    SamplerKind sampler = SamplerKind::uniform;
    int samples = 0;
    std::uint64_t seed = 0;
    BakeStats stats;

    std::size_t vertex_count() const {
        return K > 0 && channels > 0 ? coeffs.size() / (std::size_t(K) * channels) : 0;
    }
    const float* vertex(std::size_t v, int channel = 0) const {
        return coeffs.data() + (v * channels + channel) * std::size_t(K);
    }
};

}  // namespace shprt
