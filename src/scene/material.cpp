// Glossy BRDF specs (scene/material.hpp).
#include "shprt/scene/material.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"

#include <cmath>

namespace shprt {

void check_brdf(const Brdf& b) {
    if (b.model == BrdfModel::ggx) {
        SHPRT_CHECK(
            std::isfinite(b.parameter) && b.parameter >= kMinGgxRoughness && b.parameter <= 1,
            invalid_argument, "ggx roughness {} must be in [{}, 1]", b.parameter, kMinGgxRoughness);
    } else {
        SHPRT_CHECK(
            std::isfinite(b.parameter) && b.parameter >= 0 && b.parameter <= kMaxBrdfExponent,
            invalid_argument, "{} exponent {} must be in [0, {}]",
            b.model == BrdfModel::phong ? "phong" : "blinn", b.parameter, kMaxBrdfExponent);
    }
    const Vec3f c = b.specular;
    for (float x : {c.x, c.y, c.z})
        SHPRT_CHECK(std::isfinite(x) && x >= 0 && x <= 1, invalid_argument,
                    "specular colour ({}, {}, {}) must be in [0, 1]", c.x, c.y, c.z);
}

Brdf parse_brdf(const std::string& spec) {
    const std::size_t colon = spec.find(':');
    SHPRT_CHECK(colon != std::string::npos, invalid_argument,
                "--brdf '{}': expected phong:E, blinn:E or ggx:R, then optionally :R,G,B", spec);
    const std::string name = spec.substr(0, colon);
    Brdf b;
    if (name == "phong")
        b.model = BrdfModel::phong;
    else if (name == "blinn")
        b.model = BrdfModel::blinn_phong;
    else if (name == "ggx")
        b.model = BrdfModel::ggx;
    else
        fail(ErrorCode::invalid_argument, "--brdf '{}': unknown model '{}' (phong, blinn or ggx)",
             spec, name);
    const std::size_t colour = spec.find(':', colon + 1);
    b.parameter =
        parse_numbers(spec.substr(colon + 1, colour - (colon + 1)), 1, "--brdf " + spec)[0];
    if (colour != std::string::npos) {
        const std::vector<double> c =
            parse_numbers(spec.substr(colour + 1), 3, "--brdf " + spec + " specular colour");
        b.specular = Vec3f{float(c[0]), float(c[1]), float(c[2])};
    }
    check_brdf(b);
    return b;
}

std::string to_string(const Brdf& b) {
    const char* name = b.model == BrdfModel::phong         ? "phong"
                       : b.model == BrdfModel::blinn_phong ? "blinn"
                                                           : "ggx";
    const Vec3f c = b.specular;
    if (c == Vec3f{1, 1, 1}) return fmt::format("{}:{}", name, b.parameter);
    return fmt::format("{}:{}:{},{},{}", name, b.parameter, c.x, c.y, c.z);
}

}  // namespace shprt
