// Display-rate stage of the paper study (display_rate.hpp).
#include "paper/display_rate.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/shade/camera.hpp"

#if SHPRT_HAS_VIEWER
#include "viewer.hpp"
#endif

#include <fmt/format.h>

#include <string>

namespace shprt::paper {

void measure_display_rate(const Mesh& mesh, const TransferSet& largest, const Lights& lights,
                          const Options& o, bool opengl, Results& res, const StageLog& stage) {
#if SHPRT_HAS_VIEWER
    if (!opengl) return;
    stage.say(
        fmt::format("display: {} frames per K' (viewer benchmark, orbiting camera)", o.frames));
    try {
        viewer::LightRig rig(largest.layout.K);
        LightSetup setup;
        setup.specs = lights.sun_specs;
        rig.set_source(setup);
        viewer::FrameConfig config;
        config.msaa = 4;  // on every machine, so that rows compare (the viewer's default
                          // drops to 1 sample on a software rasteriser)
        if (o.quick) config.width = 320, config.height = 180;
        config.draw.camera = default_camera(mesh, float(config.width) / float(config.height));
        viewer::BenchmarkOptions bo;
        bo.frames = o.frames;
        bo.K_values.clear();
        for (const KRow& r : res.rows) bo.K_values.push_back(r.K);
        const viewer::BenchmarkReport report =
            viewer::run_benchmark(mesh, largest, rig, config, bo);
        for (const viewer::BenchmarkRow& b : report.rows)
            for (KRow& r : res.rows)
                if (r.K == b.K_used && !b.skipped) r.fps = b.fps, r.frame_ms = b.mean_ms;
        res.gl_context = fmt::format("{}, {}x{}, {}x MSAA", report.context, report.width,
                                     report.height, report.msaa);
    } catch (const Error& e) {
        res.warnings.push_back(std::string("display benchmark failed: ") + e.what());
        stage.say("warning: " + res.warnings.back());
    }
#else
    (void)mesh, (void)largest, (void)lights, (void)o, (void)opengl, (void)stage;
    res.warnings.push_back("this build has no OpenGL viewer: frames/s not measured");
#endif
}

}  // namespace shprt::paper
