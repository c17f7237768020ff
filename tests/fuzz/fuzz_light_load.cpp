// Fuzz target: the light loaders (light/image.hpp, light/light.hpp): Radiance .hdr (stb_image),
// OpenEXR (tinyexr), PNG (stb_image), each as an equirect map or a cube cross. The first byte
// picks the format and layout; the rest is the file. A light either loads with finite
// coefficients or is refused with shprt::Error.
#include "fuzz_util.hpp"

#include "shprt/core/error.hpp"
#include "shprt/light/light.hpp"

#include <cmath>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {".hdr", ".exr", ".png"};
    static const char* const kLayout[] = {"", "equirect:", "cross:"};
    const int ext = data[0] % 3, layout = (data[0] / 3) % 3;
    const std::string path = shprt::fuzz::write_input(data + 1, size - 1, kExt[ext]);
    try {
        const shprt::ShLight light = shprt::parse_light(kLayout[layout] + path, 9);
        if (light.K != 9 || light.coeffs.size() != 27) std::abort();
        for (float c : light.coeffs)
            if (!std::isfinite(c)) std::abort();  // a light is finite, or an error
    } catch (const shprt::Error&) {
    }
    return 0;
}
