// Image grids with bitmap labels (image_grid.hpp). The glyphs are a 5×7 pixel font drawn
// by hand for the few characters the labels use.
#include "paper/image_grid.hpp"

#include "shprt/core/error.hpp"

#include <algorithm>
#include <cstdint>

namespace shprt::paper {
namespace {

// Rows top to bottom, bit 4 = leftmost column.
struct Glyph {
    char c;
    std::uint8_t rows[7];
};
constexpr Glyph kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
    {'\'', {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'Y', {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04}},
};

const Glyph* glyph(char c) {
    for (const Glyph& g : kFont)
        if (g.c == c) return &g;
    return nullptr;
}

void fill(Image& img, int x0, int y0, int w, int h, float v) {
    for (int y = std::max(0, y0); y < std::min(img.height, y0 + h); ++y)
        for (int x = std::max(0, x0); x < std::min(img.width, x0 + w); ++x)
            for (int c = 0; c < 3; ++c) img.pixel(x, y)[c] = v;
}

// White text on a black box at (x0, y0), each font pixel `s`×`s` image pixels.
void draw_label(Image& img, int x0, int y0, const std::string& text, int s) {
    constexpr float kWhite = 50.0f;  // saturates the tone map to white
    const int advance = 6 * s, pad = 2 * s;
    fill(img, x0, y0, int(text.size()) * advance + 2 * pad - s, 7 * s + 2 * pad, 0.0f);
    for (std::size_t i = 0; i < text.size(); ++i) {
        const Glyph* g = glyph(text[i]);
        if (!g) continue;
        for (int r = 0; r < 7; ++r)
            for (int col = 0; col < 5; ++col)
                if (g->rows[r] & (0x10 >> col))
                    fill(img, x0 + pad + int(i) * advance + col * s, y0 + pad + r * s, s, s,
                         kWhite);
    }
}

}  // namespace

Image compose_grid(const std::vector<Image>& tiles, const std::vector<std::string>& labels,
                   int columns, float scale) {
    SHPRT_CHECK(!tiles.empty() && columns >= 1, invalid_argument,
                "compose_grid: {} tiles in {} columns", tiles.size(), columns);
    SHPRT_CHECK(labels.size() == tiles.size(), invalid_argument,
                "compose_grid: {} labels for {} tiles", labels.size(), tiles.size());
    const int tw = tiles[0].width, th = tiles[0].height;
    for (const Image& t : tiles)
        SHPRT_CHECK(t.width == tw && t.height == th, invalid_argument,
                    "compose_grid: tiles of {}x{} and {}x{}", tw, th, t.width, t.height);
    constexpr int kGap = 2;
    const int n = int(tiles.size());
    const int cols = std::min(columns, n), rows = (n + columns - 1) / columns;
    Image out = Image::make(cols * tw + (cols - 1) * kGap, rows * th + (rows - 1) * kGap);
    const int s = tw >= 240 ? 2 : 1;
    for (int i = 0; i < n; ++i) {
        const int ox = (i % columns) * (tw + kGap), oy = (i / columns) * (th + kGap);
        for (int y = 0; y < th; ++y)
            for (int x = 0; x < tw; ++x)
                for (int c = 0; c < 3; ++c)
                    out.pixel(ox + x, oy + y)[c] = tiles[i].pixel(x, y)[c] * scale;
        draw_label(out, ox + 2, oy + 2, labels[i], s);
    }
    return out;
}

Image half_size(const Image& image) {
    SHPRT_CHECK(image.width >= 2 && image.height >= 2, invalid_argument,
                "half_size: a {}x{} image is too small", image.width, image.height);
    Image out = Image::make(image.width / 2, image.height / 2);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < 3; ++c)
                out.pixel(x, y)[c] =
                    0.25f *
                    (image.pixel(2 * x, 2 * y)[c] + image.pixel(2 * x + 1, 2 * y)[c] +
                     image.pixel(2 * x, 2 * y + 1)[c] + image.pixel(2 * x + 1, 2 * y + 1)[c]);
    return out;
}

}  // namespace shprt::paper
