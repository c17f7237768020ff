// Image grids for the paper study: tiles side by side with a small bitmap label in each.
#pragma once

#include "shprt/light/image.hpp"

#include <string>
#include <vector>

namespace shprt::paper {

// Lays out `tiles` (all the same size, linear RGB) in rows of `columns`, 2-pixel black gaps, each
// tile multiplied by `scale` and labelled in its top-left corner with `labels[i]` (upper-case
// letters, digits, '=', '\'' and spaces; other characters are drawn as blanks) in white on a
// black box. The result is linear: save it with exposure 1. Throws Error(invalid_argument) for no
// tiles, tiles of different sizes, columns < 1 or a label count that differs from the tile count.
Image compose_grid(const std::vector<Image>& tiles, const std::vector<std::string>& labels,
                   int columns, float scale);

// The image at half size (each output pixel the mean of a 2×2 block; an odd last row or column
// is dropped), for documentation-sized copies. Throws Error(invalid_argument) below 2×2.
Image half_size(const Image& image);

}  // namespace shprt::paper
