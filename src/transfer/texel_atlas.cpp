// Texel atlases of texel-domain transfer (transfer.hpp): gutter dilation.
#include "shprt/transfer/transfer.hpp"

namespace shprt {

std::vector<std::int64_t> dilate_texels(const TexelAtlas& atlas, int gutter) {
    const std::size_t W = std::size_t(atlas.width), H = std::size_t(atlas.height);
    std::vector<std::int64_t> source(W * H, -1);
    for (std::size_t r = 0; r < atlas.texel.size(); ++r) source[atlas.texel[r]] = std::int64_t(r);
    static constexpr int kOrder[8][2] = {{-1, 0},  {1, 0},  {0, -1}, {0, 1},
                                         {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
    std::vector<std::int64_t> next;
    for (int ring = 0; ring < gutter; ++ring) {
        next = source;
        for (std::size_t y = 0; y < H; ++y)
            for (std::size_t x = 0; x < W; ++x) {
                if (source[y * W + x] >= 0) continue;
                for (const auto& d : kOrder) {
                    const long long nx = (long long)x + d[0], ny = (long long)y + d[1];
                    if (nx < 0 || ny < 0 || nx >= (long long)W || ny >= (long long)H) continue;
                    const std::int64_t s = source[std::size_t(ny) * W + std::size_t(nx)];
                    if (s >= 0) {
                        next[y * W + x] = s;
                        break;
                    }
                }
            }
        source.swap(next);
    }
    return source;
}

}  // namespace shprt
