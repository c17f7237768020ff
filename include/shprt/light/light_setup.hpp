// The one path for a light: load → SH → window → rotate. Every tool and the viewer get their
// light through these functions, so that the same options give the same coefficients everywhere:
//
//   light_source(setup, K)       the specs (`--light`) projected with full bands, windowed
//                                (`--window`): the unrotated source
//   rotated_light(source, R, K)  the source rotated by R (SH rotation, never re-projection), then
//                                truncated to its first K coefficients
//   prepare_light(setup, K)      both, with R from setup.yaw_pitch_roll_deg (`--rotate`)
//
// `shprt shade` and `shprt render` call prepare_light; the viewer keeps the source and calls
// rotated_light whenever the light turns (viewer/light_rig.hpp); the renderer calls rotated_light
// for the coefficients it shades with (Renderer::set_light). Rotating before truncating keeps the
// rotation exact when K is not a square: a full band is rotation invariant, a partial one is not.
#pragma once

#include "shprt/core/options.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/sun.hpp"
#include "shprt/sh/window.hpp"

#include <optional>
#include <string>
#include <vector>

namespace shprt {

struct LightSetup {
    // Light specs (light/light.hpp), summed; empty = {"builtin"}, or no light at all beside a
    // `sun` (the built-in light holds a sun of its own, which would be counted twice).
    std::vector<std::string> specs;
    // A sun kept out of the SH sum (`--sun`, shade/sun_shade.hpp): prepare_sun turns it with the
    // rest; prepare_light and light_source never include it.
    std::optional<Sun> sun;
    Vec3d yaw_pitch_roll_deg{0, 0,
                             0};  // rotation R = Ry(yaw)·Rx(pitch)·Rz(roll) (core/rotation3.hpp)
    WindowKind window = WindowKind::none;
    double window_strength = 0;  // as apply_window (sh/window.hpp)
};

// The unrotated source for lights of basis size K: the specs projected with full bands
// (sh_count(sh_bands_for(K)) coefficients) and windowed. Throws the errors of make_light (naming
// the spec or file) and Error(invalid_argument) for K outside [1, kMaxLightK].
ShLight light_source(const LightSetup& setup, int K);

// setup.yaw_pitch_roll_deg as a matrix; exactly the identity when all three angles are 0.
Mat3d light_rotation(const LightSetup& setup);

// The light `source` turned by the rotation R (a feature at direction s appears at R·s, as
// rotate_light), then truncated to its first K coefficients (3·K floats, channel-major). The
// rotation is skipped when R is exactly the identity. Exact when source.K is a full band (n²);
// otherwise rotate_light pads the last band with zeros, which is only approximate. Throws
// Error(invalid_argument) for a malformed source or K outside [1, source.K].
ShLight rotated_light(const ShLight& source, const Mat3d& R, int K);

// rotated_light(light_source(setup, K), light_rotation(setup), K): the light of basis size K for
// `setup`. Throws what light_source throws.
ShLight prepare_light(const LightSetup& setup, int K);

// setup.sun as it lights the scene: its direction turned by light_rotation(setup) (the rotation
// turns every light), and its SH projection for its bounced light (shade/sun_shade.hpp) through
// the same path as a `sun:` spec: projected with full bands, windowed by setup.window, rotated,
// truncated to K. Throws Error(invalid_argument) when setup.sun is unset or K is outside
// [1, kMaxLightK].
struct PreparedSun {
    Sun sun;     // direction rotated
    ShLight sh;  // basis size K
};
PreparedSun prepare_sun(const LightSetup& setup, int K);

// Parses "YAW,PITCH,ROLL" in degrees (three finite numbers, core/parse.hpp); throws
// Error(invalid_argument) naming `text`.
Vec3d parse_yaw_pitch_roll(const std::string& text);

// The light as the command line's `shade`, `render`, `view`, `export` and `compress` take it, as
// typed: `--light` (repeatable), `--sun X,Y,Z[,RADIUS_DEG[,R,G,B]]`, `--rotate YAW,PITCH,ROLL`,
// `--window`, `--window-strength`; Python's light() takes its window's defaults from it.
struct LightChoice {
    std::vector<std::string> light;  // the specs, summed
    std::string sun;                 // light/sun.hpp, or empty
    std::string rotate, window = "none";
    double window_strength = 0;
};
// One row per option, in the command line's help order (core/options.hpp).
const std::vector<OptionRow<LightChoice>>& light_option_table();
// The LightSetup of the choice; one-line Error(invalid_argument) naming a bad --sun, window or
// rotation. Light files are only read later, by prepare_light.
LightSetup light_setup_from(const LightChoice& choice);
// The files a command with this light reads: `file` (its input) and every file the specs name,
// for check_output_is_not_input (core/file.hpp).
std::vector<std::string> input_files(const std::string& file, const LightChoice& choice);
// "--light a --light b" as given, and the sun kept out of it ("... (the sun of --sun S kept out
// of the SH sum)"); empty without a light.
std::string describe_light_choice(const LightChoice& choice);

}  // namespace shprt
