// The SH conventions in words: what `shprt sh info` prints. The same conventions as basis.hpp
// states for the code (and docs/conventions.md for the reader), in one text a user can ask for.
#pragma once

#include <string>

namespace shprt {

// The conventions (basis, phase, index, bands, axes, angles, equirect maps, rotation, radiometry)
// and the most bands the basis evaluates (kMaxBands), in lines of plain text ending in '\n'.
std::string sh_conventions_text();

}  // namespace shprt
