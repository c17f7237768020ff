// The light as the front ends take it (light_setup.hpp: LightChoice) and its table.
#include "shprt/core/error.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/sh/window.hpp"

namespace shprt {

const std::vector<OptionRow<LightChoice>>& light_option_table() {
    static const std::vector<OptionRow<LightChoice>> table = [] {
        using C = LightChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "light", &C::light,
                "Light spec, repeatable and summed: FILE.hdr|.exr, constant[:R,G,B], "
                "gradient, sun:X,Y,Z[,RADIUS[,R,G,B]], builtin (default)");
        add_row(t, "sun", &C::sun,
                "X,Y,Z[,RADIUS_DEG[,R,G,B]]: a sun kept out of the SH sum, its direct light "
                "traced (shade) or shadow-mapped (render, view): sharp shadows; its bounces from "
                "an interreflected file; without --light, no sky; export writes it as a glTF "
                "KHR_lights_punctual light");
        add_row(t, "rotate", &C::rotate, "Rotate the light: YAW,PITCH,ROLL in degrees");
        add_row(t, "window", &C::window, "SH window of the light: none, hann, lanczos, sloan");
        add_row(t, "window_strength", &C::window_strength,
                "Window width (hann, lanczos) or lambda (sloan); 0 = default");
        return complete_rows(std::move(t));
    }();
    return table;
}

LightSetup light_setup_from(const LightChoice& choice) {
    LightSetup setup;
    setup.specs = choice.light;
    if (!choice.sun.empty())
        setup.sun =
            parse_sun(choice.sun, "--sun '" + choice.sun + "'", "X,Y,Z[,RADIUS_DEG[,R,G,B]]");
    setup.window = parse_window_kind(choice.window);
    setup.window_strength = choice.window_strength;
    if (!choice.rotate.empty()) setup.yaw_pitch_roll_deg = parse_yaw_pitch_roll(choice.rotate);
    return setup;
}

std::vector<std::string> input_files(const std::string& file, const LightChoice& choice) {
    std::vector<std::string> files{file};
    for (const std::string& spec : choice.light)
        for (std::string& f : light_spec_files(spec)) files.push_back(std::move(f));
    return files;
}

std::string describe_light_choice(const LightChoice& choice) {
    std::string out;
    for (const std::string& spec : choice.light)
        out += (out.empty() ? "--light " : " --light ") + spec;
    if (!choice.sun.empty()) out += " (the sun of --sun " + choice.sun + " kept out of the SH sum)";
    return out;
}

}  // namespace shprt
