// `shprt view FILE.shprt [options]`: the interactive viewer (GLFW window, OpenGL 4.3 core, ImGui
// panel), and its headless modes:
//   --screenshot OUT.png   one frame without a window (EGL; a hidden GLFW window as fallback),
//                          through render_image and save_image, as `shprt render`
//   --benchmark FRAMES     frames/s against basis size K' = 32, 48, 64, 128, 256, offscreen
//   --bake                 FILE is a scene: bake it in this process and show it while it refines
// Thin: parses the options into the viewer's ViewChoice (viewer.hpp, the viewer's one entry
// header), whose request_from checks every option before any work, runs the request, prints its
// lines on stdout.
#include "shprt/config.hpp"

#if SHPRT_HAS_VIEWER

#include "common/command.hpp"
#include "common/option_table.hpp"
#include "common/progress_bar.hpp"
#include "common/shading_options.hpp"

#include "viewer.hpp"

#include "shprt/bake/bake_option_table.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/interrupt.hpp"

#include <cstdio>
#include <memory>
#include <optional>
#include <string>

namespace shprt::tools {
namespace {

void run(const viewer::ViewChoice& choice) {
    viewer::ViewRequest r = viewer::request_from(choice);
    std::optional<ProgressBar> bar;  // a headless bake's
    r.begin_bake = [&bar] {
        install_interrupt_handler();
        return bar.emplace("bake").callback();
    };
    r.end_bake = [&bar] {
        end_interruptible();  // from here on a signal ends the viewer at once (core/interrupt.hpp)
        bar->finish();
    };
    r.say = [](const std::string& line) { std::fputs(line.c_str(), stdout); };
    try {
        viewer::run_view(r);
    } catch (const Error& e) {
        const std::string what = e.what();
        if (r.windowed() && what.rfind("cannot open a window", 0) == 0)
            fail(e.code(), "{} (without a display, use --screenshot OUT.png or --benchmark N)",
                 what);
        throw;
    }
}

const bool view_registered = register_command(
    {"view", "Interactive viewer (OpenGL window, ImGui panel); --screenshot, --benchmark, --bake",
     70, [](CLI::App& app) {
         auto args = std::make_shared<viewer::ViewChoice>();
         app.add_option("file", args->input, "Baked .shprt file (with --bake: a scene to bake)")
             ->required();
         add_table_options(app, light_option_table(), args->light);
         add_table_options(app, camera_option_table(), args->camera);
         add_table_options(app, object_option_table(), args->object);
         app.get_option("--object")
             ->description(
                 "A mesh (any scene file) lit from the file's transfer probes (docs/probes.md); "
                 "in the window G+drag carries it (left button: over the floor, right: up and "
                 "down), the arrow keys move it horizontally and Page Up/Down vertically, and the "
                 "panel shows and edits its position");
         const auto& view_table = viewer::view_option_table();
         add_table_options(app, view_table, *args, {}, {"size"});
         add_shading_options(app, args->shading, kViewOption | kCoeffsOption,
                             "Exposure multiplier (default 1)",
                             "Interreflected bakes: show the direct light only (the file's T_0; "
                             "the panel toggles it)");
         add_table_options(app, view_table, *args, {},
                           {"background", "wireframe", "msaa", "no_vsync", "bake"});
         add_table_options(app, bake_option_table(), args->bake);
         // Without --bake, --coeffs is the initial K' (deprecated: --shading-coeffs).
         app.get_option("--coeffs")
             ->description(
                 "With --bake: basis size K to bake (1 to 1024, default 16); otherwise the "
                 "deprecated name of --shading-coeffs");
         app.get_option("--albedo")
             ->description(
                 "With --bake, interreflected: the albedo R,G,B of every vertex; without --bake or "
                 "with a glossy bake: the glossy colour override R,G,B");
         add_table_options(app, view_table, *args,
                           {"size", "background", "wireframe", "msaa", "no_vsync", "bake"});
         CLI::App* sub = &app;
         app.callback([args, sub] {
             for (const char* name : {"--transfer", "--bands", "--samples", "--sampler", "--seed",
                                      "--threads", "--device"})
                 if (sub->get_option(name)->count() > 0) args->bake_only_given.push_back(name);
             run(*args);
         });
     }});

}  // namespace
}  // namespace shprt::tools

#endif  // SHPRT_HAS_VIEWER
