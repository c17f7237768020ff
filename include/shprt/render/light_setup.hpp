// The light as the shading tools use it: the `--light`, `--rotate` and `--window` options of
// `shprt shade`, `shprt render` and the viewer, turned into one ShLight by one function, so that
// every tool gets the same light from the same options.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"
#include "shprt/sh/window.hpp"

#include <string>
#include <vector>

namespace shprt {

struct LightSetup {
    std::vector<std::string> specs;  // light specs (light/light.hpp), summed; empty = {"builtin"}
    Vec3d yaw_pitch_roll_deg{0, 0,
                             0};  // rotation R = Ry(yaw)·Rx(pitch)·Rz(roll) (core/rotation3.hpp)
    WindowKind window = WindowKind::none;
    double window_strength = 0;  // as apply_window (sh/window.hpp)
};

// Projects the specs with full bands (n = sh_bands_for(K), n² coefficients), applies the window,
// rotates (SH rotation, never re-projection), then keeps the first K coefficients; so rotation is
// exact even when K is not a square. Throws the errors of make_light (naming the spec or file) and
// Error(invalid_argument) for K outside [1, kMaxLightK].
ShLight prepare_light(const LightSetup& setup, int K);

// Parses "YAW,PITCH,ROLL" in degrees (three finite numbers, core/parse.hpp); throws
// Error(invalid_argument) naming `text`.
Vec3d parse_yaw_pitch_roll(const std::string& text);

}  // namespace shprt
