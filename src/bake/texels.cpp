// Per-texel receivers (texels.hpp).
#include "shprt/bake/texels.hpp"

#include "shprt/bake/bake.hpp"

#include <algorithm>
#include <thread>

namespace shprt {

Receivers texel_receivers(const TexelSamples& samples) {
    return Receivers::all(ReceiverDomain::texel, samples.positions.data(), samples.normals.data(),
                          samples.count());
}

TexelAtlas texel_atlas(const TexelSamples& samples, int uv_set) {
    TexelAtlas a;
    a.width = samples.width;
    a.height = samples.height;
    a.uv_set = uv_set;
    a.texel = samples.texel;
    return a;
}

std::uint64_t texel_bake_bytes(std::size_t texels, int width, int height,
                               const TransferLayout& layout, std::size_t samples, int threads) {
    const std::uint64_t n = texels;
    const std::uint64_t rows = n * layout.floats_per_receiver() * sizeof(float);
    const std::uint64_t receivers = n * (3 * sizeof(Vec3f) + 2 * sizeof(std::uint32_t));
    const std::uint64_t image = std::uint64_t(width) * std::uint64_t(height) * 6;
    const std::uint64_t t =
        threads > 0 ? std::uint64_t(threads) : std::max(1u, std::thread::hardware_concurrency());
    const std::uint64_t chunk = auto_chunk_receivers(std::max<std::size_t>(texels, 1), samples);
    // Per thread: W[chunk×S] and the ray buffers of one receiver (about 48 bytes a direction).
    const std::uint64_t per_thread = chunk * samples * sizeof(float) + samples * 48;
    return rows + receivers + image + t * per_thread;
}

}  // namespace shprt
