// The paper study's run (paper_study.hpp): the stages in order, each in its own file — the room
// and its lights, the ground truth, per basis size the bakes, their quality and their images, then
// the display rate, the sampling study and the reports. Definitions in docs/paper_table.md.
#include "paper/bake_sweep.hpp"
#include "paper/display_rate.hpp"
#include "paper/ground_truth.hpp"
#include "paper/lights.hpp"
#include "paper/paper_study.hpp"
#include "paper/quality.hpp"
#include "paper/renders.hpp"
#include "paper/sampling_study.hpp"
#include "paper/stage_log.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/host.hpp"
#include "shprt/light/light.hpp"
#include "shprt/scene/room.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <optional>

namespace shprt::paper {
namespace {}  // namespace

const PaperColumn* paper_column(int K) {
    for (const PaperColumn& c : kPaperColumns)
        if (c.K == K) return &c;
    return nullptr;
}

Results run(const Options& o, const std::string& command_line, const Reporter& reporter) {
    const StageLog stage(reporter);
    Results res;
    res.options = o;
    res.command = command_line;
    res.machine = host_cpu();
    res.cpu_threads = o.threads > 0 ? fmt::format("{} threads used", o.threads) : "all used";
    const Devices devices = choose_devices(o);
    res.gpu = devices.gpu_description;
    std::filesystem::create_directories(o.out_dir);

    // Scene and lights.
    stage.say(fmt::format("room: generating ({} triangles requested)", o.triangles));
    RoomOptions room;
    room.triangles = o.triangles;
    const Mesh mesh = generate_room(room);
    res.vertices = mesh.vertex_count();
    res.triangles = mesh.triangle_count();
    const Lights lights = make_lights();
    res.sky_spec = quote_specs(lights.sky_specs);
    res.sun_spec = quote_specs(lights.sun_specs);
    stage.say(fmt::format("room: {} vertices, {} triangles", res.vertices, res.triangles));

    const Truth truth = compute_ground_truth(mesh, lights, o, res, stage);

    // OpenGL for the images, when it works here.
    std::optional<Renders> renders;
    bool gl_ok = false;  // OpenGL works here (renders, then the display benchmark)
    if (o.images) {
        try {
            renders.emplace(mesh, lights.sun_dir, o.quick, res);
            gl_ok = true;
            stage.say("OpenGL: " + res.gl_context);
        } catch (const Error& e) {
            renders.reset();
            res.warnings.push_back(std::string("no OpenGL, images and frames/s skipped: ") +
                                   e.what());
            stage.say("warning: " + res.warnings.back());
        }
    }

    // Per basis size: bakes, quality, images.
    const std::vector<int> Ks = table_sizes(o.extended);
    const int K_max = Ks.back();
    TransferSet largest;  // kept for the display benchmark
    for (int K : Ks) {
        KRow row;
        row.K = K;
        row.paper_size = paper_column(K) != nullptr;
        RowBakes bakes = bake_row(mesh, o, devices, row, stage);
        const ShLight sky = make_light(lights.sky_specs, K);
        const ShLight sun = make_light(lights.sun_specs, K);
        score_row(row, mesh, bakes.paper, bakes.improved, sky, sun, truth);
        if (renders) {
            // A driver may refuse a large transfer buffer: that K then has no images.
            try {
                renders->render_row(row, bakes.paper, bakes.improved, sky, sun);
            } catch (const Error& e) {
                res.warnings.push_back(fmt::format("K = {}: not rendered: {}", K, e.what()));
                stage.say("warning: " + res.warnings.back());
            }
        }
        stage.say(fmt::format(
            "K = {}: {}sky RMSE {:.2f} %, sun RMSE {:.2f} %, saturation {:.2f}, negative {:.2f} "
            "%; improved: sky {:.2f} %, sun {:.2f} %",
            K, row.cpu.ran ? fmt::format("{:.2f} s, ", row.cpu.stats.seconds_total) : "",
            100 * row.sky.error.relative_rmse(), 100 * row.sun.error.relative_rmse(),
            row.sun.has_contrast ? row.sun.contrast.saturation : kNaN,
            100 * row.sun.ringing.negative_fraction, 100 * row.sky_improved.error.relative_rmse(),
            100 * row.sun_improved.error.relative_rmse()));
        if (K == K_max) largest = std::move(bakes.paper);
        res.rows.push_back(std::move(row));
    }

    // The ground truth's images and the grids; the display benchmark makes its own context.
    if (renders) {
        renders->finish(truth, res, o.out_dir);
        renders.reset();
    }
    measure_display_rate(mesh, largest, lights, o, gl_ok, res, stage);
    largest = TransferSet{};

    if (o.study) run_sampling_study(mesh, lights, truth, o, res, stage);

    res.seconds_total = stage.elapsed();
    write_reports(res, reporter);
    res.seconds_total = stage.elapsed();
    stage.say(fmt::format("done in {:.1f} s; files in {}", res.seconds_total, o.out_dir));
    return res;
}

}  // namespace shprt::paper
