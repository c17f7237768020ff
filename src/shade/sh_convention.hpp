// The SH convention block that every export states (extras.shprt.sh in a .glb, "sh" in the texel
// images' sidecar): written once here so that the two cannot drift.
#pragma once

#include <nlohmann/json.hpp>

namespace shprt::detail {

inline nlohmann::ordered_json sh_convention_json() {
    return {{"basis", "real spherical harmonics, Green 2003 (the paper's)"},
            {"condon_shortley_phase", true},
            {"index", "i = l*(l+1) + m"},
            {"direction", "unit world vector (x, y, z); theta from +Z, phi from +X toward +Y"},
            {"world", "right-handed, +Y up"},
            {"normalization", "orthonormal over the unit sphere"}};
}

}  // namespace shprt::detail
