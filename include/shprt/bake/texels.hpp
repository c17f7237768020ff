// Per-texel receivers: the texel centres of a mesh's UV atlas (scene/texel_raster.hpp) as the
// receivers of a bake (receivers.hpp, ReceiverDomain::texel), so a two-triangle floor gets as many
// receivers as its texture has texels; and what a texel bake needs before it traces.
#pragma once

#include "shprt/bake/receivers.hpp"
#include "shprt/scene/texel_raster.hpp"
#include "shprt/transfer/transfer.hpp"

#include <cstddef>
#include <cstdint>

namespace shprt {

// All of `samples` as the receivers of a bake (the arrays are the samples': keep them alive).
Receivers texel_receivers(const TexelSamples& samples);

// The TexelAtlas of a texel bake of `samples` (which texel each receiver is).
TexelAtlas texel_atlas(const TexelSamples& samples, int uv_set);

// Bytes a texel bake of `texels` receivers with `layout` and S = `samples` directions needs
// before it traces: the coefficients (float32 in memory), the receivers' arrays, the coverage
// image, and the bake's per-thread buffers for `threads` threads (0 = all). The BVH is not
// counted (the same as a vertex bake's). `shprt bake --domain texel` refuses a bake whose
// estimate exceeds available_memory_bytes() (shprt/core/memory.hpp).
std::uint64_t texel_bake_bytes(std::size_t texels, int width, int height,
                               const TransferLayout& layout, std::size_t samples, int threads);

}  // namespace shprt
