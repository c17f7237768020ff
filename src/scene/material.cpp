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
}

Brdf parse_brdf(const std::string& spec) {
    const std::size_t colon = spec.find(':');
    SHPRT_CHECK(colon != std::string::npos, invalid_argument,
                "--brdf '{}': expected phong:E, blinn:E or ggx:R", spec);
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
    b.parameter = parse_numbers(spec.substr(colon + 1), 1, "--brdf " + spec)[0];
    check_brdf(b);
    return b;
}

std::string to_string(const Brdf& b) {
    const char* name = b.model == BrdfModel::phong         ? "phong"
                       : b.model == BrdfModel::blinn_phong ? "blinn"
                                                           : "ggx";
    return fmt::format("{}:{}", name, b.parameter);
}

}  // namespace shprt
