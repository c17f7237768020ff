// Packing a UV atlas's charts (uv_pack.hpp): shelves and a skyline of boxes, and conformal charts
// dropped by their texel footprints.
#include "uv_pack.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"
#include "shprt/scene/texel_raster.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace shprt::detail {
namespace {
// Shelf packing of `boxes` (order: tallest first) into a square of side `side` metres with `gap`
// metres between boxes and gap/2 to the border; returns the height used.
double pack(std::vector<ChartBox>& boxes, const std::vector<std::size_t>& order, double side,
            double gap) {
    double x = gap / 2, y = gap / 2, shelf = 0;
    for (std::size_t i : order) {
        ChartBox& b = boxes[i];
        if (x > gap / 2 && x + b.width() + gap / 2 > side) {
            y += shelf + gap;
            x = gap / 2;
            shelf = 0;
        }
        b.x = x, b.y = y;
        x += b.width() + gap;
        shelf = std::max(shelf, b.height());
    }
    return y + shelf + gap / 2;
}

// Skyline bottom-left packing (J. Jylänki, "A Thousand Ways to Pack the Bin", 2010, §4) of
// `boxes` in `order` into a square of side `side` metres, `gap` metres between boxes and gap/2 to
// the border: each box goes where its top is lowest (then leftmost) on the skyline of those
// before it, which fills the room a shelf leaves above shorter boxes. False when one does not fit.
bool skyline(std::vector<ChartBox>& boxes, const std::vector<std::size_t>& order, double side,
             double gap) {
    struct Segment {
        double x, y, w;  // [x, x + w) at height y
    };
    std::vector<Segment> sky{{0, 0, side}}, next;
    for (std::size_t i : order) {
        ChartBox& b = boxes[i];
        const double w = b.width() + gap, h = b.height() + gap;
        double best_top = std::numeric_limits<double>::infinity(), best_x = 0, best_y = 0;
        for (std::size_t s = 0; s < sky.size(); ++s) {
            const double x = sky[s].x;
            if (x + w > side) break;  // segments run left to right
            double y = 0;
            for (std::size_t k = s; k < sky.size() && sky[k].x < x + w; ++k)
                y = std::max(y, sky[k].y);
            if (y + h <= side && y + h < best_top) best_top = y + h, best_x = x, best_y = y;
        }
        if (!std::isfinite(best_top)) return false;
        b.x = best_x + gap / 2, b.y = best_y + gap / 2;
        // The skyline with [best_x, best_x + w) raised to best_top.
        const double x0 = best_x, x1 = best_x + w;
        next.clear();
        bool placed = false;
        const auto add = [&](Segment g) {
            if (g.w <= 0) return;
            if (!next.empty() && next.back().y == g.y)
                next.back().w = g.x + g.w - next.back().x;
            else
                next.push_back(g);
        };
        for (const Segment& g : sky) {
            const double end = g.x + g.w;
            if (end <= x0) {
                add(g);
                continue;
            }
            if (g.x < x0) add({g.x, g.y, x0 - g.x});
            if (!placed) add({x0, best_top, w}), placed = true;
            if (end > x1) add({std::max(g.x, x1), g.y, end - std::max(g.x, x1)});
        }
        sky.swap(next);
    }
    return true;
}

// How pack_square places boxes: shelves (the generated room's atlas, whose numbers the docs and
// tests quote) or the skyline (conformal atlases).
enum class Packer { shelves, skyline };

// The side (metres) of the square the boxes pack into with `gap` metres between them (fixed
// gap) or gap_share × side between them (gap_share > 0); packs them there.
double pack_square(std::vector<ChartBox>& boxes, double gap, double gap_share, Packer packer) {
    std::vector<std::size_t> order(boxes.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return boxes[a].height() > boxes[b].height();
    });
    double area = 0, widest = 0;
    for (const ChartBox& b : boxes)
        area += b.width() * b.height(), widest = std::max({widest, b.width(), b.height()});
    double side = std::max(std::sqrt(area), widest) * (1 + 2 * gap_share) + gap + 1e-9;
    for (;;) {
        const double g = gap_share > 0 ? gap_share * side : gap;
        if (widest + g <= side && (packer == Packer::skyline ? skyline(boxes, order, side, g)
                                                             : pack(boxes, order, side, g) <= side))
            return side;
        side *= 1.02;
    }
}

}  // namespace

// The image side and scale for `boxes` (metres), packed in place; throws when
// options.texels_per_metre needs more than kMaxTexelSide.
std::pair<int, double> pack_atlas(std::vector<ChartBox>& boxes, const UvAtlasOptions& options,
                                  const std::string& name) {
    // Conformal charts: the skyline, or shelves where they happen to need less room.
    Packer packer = Packer::shelves;
    if (options.layout == ChartLayout::conformal) {
        const double gap =
            options.texels_per_metre > 0 ? options.gutter_texels / options.texels_per_metre : 0;
        const double share =
            options.texels_per_metre > 0 ? 0 : options.gutter_texels / options.resolution;
        const double shelves = pack_square(boxes, gap, share, Packer::shelves);
        packer = pack_square(boxes, gap, share, Packer::skyline) <= shelves ? Packer::skyline
                                                                            : Packer::shelves;
    }
    if (options.texels_per_metre > 0) {
        const double tpm = options.texels_per_metre;
        const double side = pack_square(boxes, options.gutter_texels / tpm, 0, packer);
        const double texels = std::ceil(side * tpm);
        SHPRT_CHECK(texels <= kMaxTexelSide, invalid_argument,
                    "{}: {:g} texels per metre needs a {:.0f}x{:.0f} atlas (its charts pack into "
                    "a {:.3g} m square); the largest is {}x{}: {:g} texels per metre at most",
                    name, tpm, texels, texels, side, kMaxTexelSide, kMaxTexelSide,
                    std::floor(0.98 * kMaxTexelSide / side * 1000) / 1000);
        const int resolution = std::max(1, int(texels));
        if (resolution > kLargeAtlasSide)
            log_warn("{}: {:g} texels per metre gives a {}x{} atlas ({:.0f} M texels)", name, tpm,
                     resolution, resolution, double(resolution) * resolution * 1e-6);
        return {resolution, tpm};
    }
    const double side = pack_square(boxes, 0, options.gutter_texels / options.resolution, packer);
    return {options.resolution, options.resolution / side};
}

namespace {

// --- packing conformal charts by their texels -----------------------------------------------

// A chart's footprint at `scale` texels per metre: the texels its triangles touch (conservatively,
// as the rasteriser covers them) with the chart's box corner at texel (0, 0), v up; per column,
// the lowest and the highest covered row + 1 (kEmpty: none).
struct Footprint {
    static constexpr int kEmpty = std::numeric_limits<int>::min() / 4;
    int width = 0, height = 0;
    std::vector<int> bottom, top;
};

// Whether the texel square [x, x+1] × [y, y+1] overlaps triangle (a, b, c) (texel units,
// closed; the edge functions at the corner most inside: Akenine-Möller & Aila 2005, as
// rasterize_texels), with `slack` texels to spare.
bool touches(const Uv& a, const Uv& b, const Uv& c, double x, double y, double slack) {
    const double area2 = uv_area2(a, b, c);
    const double sign = area2 < 0 ? -1.0 : 1.0;
    const std::array<const Uv*, 3> p{&a, &b, &c};
    for (int e = 0; e < 3; ++e) {
        const Uv& from = *p[e];
        const Uv& to = *p[(e + 1) % 3];
        const double dx = to[0] - from[0], dy = to[1] - from[1];
        const double cx = x + 0.5 - from[0], cy = y + 0.5 - from[1];
        const double f = sign * (dx * cy - dy * cx) + (0.5 + slack) * (std::abs(dx) + std::abs(dy));
        if (f < 0) return false;
    }
    return true;
}

Footprint footprint(const std::vector<std::array<Uv, 3>>& triangles, const ChartBox& box,
                    double scale) {
    Footprint f;
    // One texel more than the box: a corner on the far texel edge touches the next texel.
    f.width = int(std::ceil(box.width() * scale)) + 1;
    f.height = int(std::ceil(box.height() * scale)) + 1;
    f.bottom.assign(std::size_t(f.width), Footprint::kEmpty);
    f.top.assign(std::size_t(f.width), Footprint::kEmpty);
    for (const auto& t : triangles) {
        std::array<Uv, 3> q{};
        double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
        for (int k = 0; k < 3; ++k) {
            q[k] = {(t[k][0] - box.lo_u) * scale, (t[k][1] - box.lo_v) * scale};
            lo_x = std::min(lo_x, q[k][0]), hi_x = std::max(hi_x, q[k][0]);
            lo_y = std::min(lo_y, q[k][1]), hi_y = std::max(hi_y, q[k][1]);
        }
        const int x0 = std::max(0, int(std::floor(lo_x)) - 1);
        const int x1 = std::min(f.width - 1, int(std::floor(hi_x)) + 1);
        const int y0 = std::max(0, int(std::floor(lo_y)) - 1);
        const int y1 = std::min(f.height - 1, int(std::floor(hi_y)) + 1);
        for (int x = x0; x <= x1; ++x)
            for (int y = y0; y <= y1; ++y)
                if (touches(q[0], q[1], q[2], x, y, 1e-3)) {
                    int& b = f.bottom[std::size_t(x)];
                    int& top = f.top[std::size_t(x)];
                    b = b == Footprint::kEmpty ? y : std::min(b, y);
                    top = std::max(top, y + 1);
                }
    }
    return f;
}

// Drops the footprints, largest first, into a width-`side` image from above, each where its top
// stays lowest (then leftmost) over the columns' filled heights — a texel skyline, so a chart
// settles into the dents of those below it — with `gutter` empty texels (Chebyshev) to every
// other chart and gutter/2 to the border. Fills offsets (texels); false past height `side`.
bool drop_pack(const std::vector<Footprint>& prints, const std::vector<std::size_t>& order,
               int side, int gutter, std::vector<std::array<int, 2>>& offsets) {
    const int margin = (gutter + 1) / 2;
    std::vector<int> filled(std::size_t(side), Footprint::kEmpty);
    offsets.assign(prints.size(), {0, 0});
    std::vector<int> low;  // per column of the dilated footprint: its lowest row
    for (std::size_t i : order) {
        const Footprint& f = prints[i];
        if (f.width + 2 * margin > side) return false;
        // The footprint dilated by the gutter: column c − gutter … c + gutter, rows − gutter.
        const int dw = f.width + 2 * gutter;
        low.assign(std::size_t(dw), Footprint::kEmpty);
        for (int c = 0; c < f.width; ++c) {
            if (f.bottom[std::size_t(c)] == Footprint::kEmpty) continue;
            for (int d = 0; d <= 2 * gutter; ++d) {
                int& l = low[std::size_t(c + d)];
                const int b = f.bottom[std::size_t(c)] - gutter;
                l = l == Footprint::kEmpty ? b : std::min(l, b);
            }
        }
        int best_top = std::numeric_limits<int>::max(), best_x = 0, best_y = 0;
        for (int x = margin; x + f.width + margin <= side; ++x) {
            int y = margin;
            for (int d = 0; d < dw; ++d) {
                const int column = x - gutter + d;
                if (column < 0 || column >= side || low[std::size_t(d)] == Footprint::kEmpty)
                    continue;
                y = std::max(y, filled[std::size_t(column)] - low[std::size_t(d)]);
            }
            const int top = y + f.height;
            if (top < best_top) best_top = top, best_x = x, best_y = y;
        }
        if (best_top + margin > side) return false;
        offsets[i] = {best_x, best_y};
        for (int c = 0; c < f.width; ++c)
            if (f.top[std::size_t(c)] != Footprint::kEmpty)
                filled[std::size_t(best_x + c)] =
                    std::max(filled[std::size_t(best_x + c)], best_y + f.top[std::size_t(c)]);
    }
    return true;
}

}  // namespace

// Packs conformal charts by their texels (drop_pack) when that beats the boxes already packed in
// `boxes` at (resolution, texels_per_metre): a larger scale at the same resolution, or the same
// scale in a smaller image. Moves the boxes (x, y: metres) and returns the better pair.
std::pair<int, double> pack_texels(const std::vector<std::vector<std::array<Uv, 3>>>& triangles,
                                   std::vector<ChartBox>& boxes, const UvAtlasOptions& options,
                                   std::pair<int, double> by_boxes) {
    const int gutter = int(std::ceil(options.gutter_texels));
    std::vector<std::array<int, 2>> offsets;
    const auto attempt = [&](double scale, int side, std::vector<std::array<int, 2>>& out) {
        std::vector<Footprint> prints;
        prints.reserve(boxes.size());
        for (std::size_t c = 0; c < boxes.size(); ++c)
            prints.push_back(footprint(triangles[c], boxes[c], scale));
        std::vector<std::size_t> order(prints.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return std::make_pair(prints[a].height, prints[a].width) >
                   std::make_pair(prints[b].height, prints[b].width);
        });
        return drop_pack(prints, order, side, gutter, out);
    };
    std::pair<int, double> best = by_boxes;
    std::vector<std::array<int, 2>> best_offsets;
    // Nothing fits in less than the charts' own area (m²).
    double area = 0;
    for (const auto& chart : triangles)
        for (const auto& t : chart) area += 0.5 * std::abs(uv_area2(t[0], t[1], t[2]));
    if (options.texels_per_metre > 0) {  // the scale is given: the smallest side that holds it
        const double scale = options.texels_per_metre;
        int lo = std::max(1, int(std::sqrt(area) * scale)), hi = by_boxes.first - 1;
        while (lo <= hi) {
            const int side = lo + (hi - lo) / 2;
            if (attempt(scale, side, offsets)) {
                best = {side, scale}, best_offsets = offsets;
                hi = side - 1;
            } else {
                lo = side + 1;
            }
        }
    } else {  // the side is given: the largest scale that fits (bisection to 1 %)
        const int side = options.resolution;
        double lo = by_boxes.second, hi = std::max(lo, side / std::sqrt(area));
        for (int step = 0; step < 8 && hi > lo * 1.01; ++step) {
            const double scale = 0.5 * (lo + hi);
            if (attempt(scale, side, offsets)) {
                best = {side, scale}, best_offsets = offsets;
                lo = scale;
            } else {
                hi = scale;
            }
        }
    }
    if (best_offsets.empty()) return by_boxes;  // the boxes were as good
    for (std::size_t c = 0; c < boxes.size(); ++c) {
        boxes[c].x = best_offsets[c][0] / best.second;
        boxes[c].y = best_offsets[c][1] / best.second;
    }
    return best;
}

}  // namespace shprt::detail
