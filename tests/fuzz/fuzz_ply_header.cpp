// Fuzz target: the strict PLY header check (and the OFF counts' bound, ply_header.hpp) that runs
// before Assimp sees a PLY file (src/scene/ply_header.hpp). The input is the file: its first 64 KiB
// are the prefix, its size the file size. It must accept or throw shprt::Error, and an accepted
// header's vertex count must fit in the file (that is what keeps Assimp from allocating a corrupt
// count).
#include "scene/ply_header.hpp"
#include "shprt/core/error.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string prefix(reinterpret_cast<const char*>(data),
                             std::min(size, shprt::detail::kMaxPlyHeader));
    (void)shprt::detail::looks_like_ply(prefix);
    try {
        const auto h = shprt::detail::check_ply_header("fuzz.ply", prefix, size);
        if (h.vertices > size) std::abort();  // every vertex needs at least one byte
    } catch (const shprt::Error&) {
    }
    try {  // the OFF counts' bound (same header)
        shprt::detail::check_off_header("fuzz.off", prefix, size);
    } catch (const shprt::Error&) {
    }
    return 0;
}
