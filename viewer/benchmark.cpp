// Display speed against basis size, offscreen (benchmark.hpp).
#include "benchmark.hpp"

#include "camera_controller.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/host.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/mesh_ops.hpp"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>

namespace shprt::viewer {
namespace {

// CPU time of the whole process (every thread), seconds.
double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

BenchmarkReport run_benchmark(const Mesh& mesh, const TransferSet& transfer, const LightRig& rig,
                              const FrameConfig& config, const BenchmarkOptions& options) {
    SHPRT_CHECK(options.frames >= 1, invalid_argument, "--benchmark {}: need at least one frame",
                options.frames);
    SHPRT_CHECK(!options.K_values.empty(), invalid_argument,
                "benchmark: no basis sizes to measure");
    OffscreenContext context(options.backend);
    BenchmarkReport report;
    report.context = context.description();
    report.host = host_cpu();
    report.vertices = mesh.vertex_count();
    report.triangles = mesh.triangle_count();
    report.K = std::min(transfer.layout.K, rig.K());
    report.width = config.width;
    report.height = config.height;
    report.k = config.draw.k;
    report.rotate_light = options.rotate_light;

    LightRig light = rig;  // turned when options.rotate_light
    Renderer renderer;
    renderer.set_shadow_map_size(choose_shadow_map_size(true));
    renderer.set_sun_filter(choose_sun_filter(true));
    renderer.set_moving_shadow_map_size(choose_moving_shadow_map_size(true));
    renderer.set_sun(light.sun());
    renderer.set_scene(mesh, transfer);
    renderer.set_light(light.source(), light.rotation());
    if (renderer.scene_has_matrices())
        report.transfer =
            fmt::format("glossy {}, brdf={}",
                        describe_gpu_transfer(transfer, renderer.transfer_bytes_per_vertex()),
                        config.draw.material_brdfs && renderer.scene_has_material_brdfs()
                            ? "materials (" + describe_brdfs(mesh) +
                                  "; none = " + to_string(config.draw.brdf) + ")"
                            : to_string(config.draw.brdf));
    DisplayTarget display(config.width, config.height);
    FrameTarget target;
    target.prepare(config.width, config.height, choose_samples(config.msaa, true),
                   display.framebuffer());
    report.msaa = target.samples();
    if (light.sun()) {
        report.shadow_map = renderer.shadow_map_size();
        report.shadow_texel = renderer.shadow_texel_size();
        report.sun_filter = choose_sun_filter(true);
        report.moving_shadow_map = choose_moving_shadow_map_size(true);
    }
    report.msaa_auto = config.msaa == kAutoMsaa;
    report.direct = target.float_target() == nullptr;
    const Bounds bounds = mesh_bounds(mesh);

    LitObject object(options.object);
    const Vec3f object_start = options.object.pose.position;
    report.object_vertices = object.present() ? options.object.object->mesh.vertex_count() : 0;
    double object_ms = 0;
    int object_frames = 0;

    using Clock = std::chrono::steady_clock;
    for (int K_used : options.K_values) {
        BenchmarkRow row;
        row.K_used = K_used;
        if (K_used > report.K) {
            row.skipped = true;
            report.rows.push_back(row);
            continue;
        }
        CameraController camera(config.draw.camera, bounds);
        DrawSettings settings = config.draw;
        settings.K_used = K_used;
        const float step = 2.0f * kPiF / float(options.frames);
        auto frame = [&] {
            if (options.rotate_light) {
                light.drag(2.0, 0.0, {1, 0, 0});
                renderer.set_light(light.source(), light.rotation());
            }
            camera.orbit_by(step);
            settings.camera = camera.camera();
            if (object.present()) {
                const int f = object_frames++;
                object.pose().position =
                    object_start + Vec3f{0.5f * std::sin(float(f) * step * 2), 0, 0};
                ObjectShadeOptions shading = options.object.options;  // the scene's, at this K′
                shading.K_used = K_used;
                object.update(renderer, light.light(), shading, settings.camera.eye);
                object_ms += object.last_shade_ms();
            }
            draw_frame(renderer, target, settings, config.exposure, display.framebuffer(),
                       config.width, config.height);
            glFinish();
        };
        for (int i = 0; i < options.warmup_frames; ++i) frame();
        double min_s = std::numeric_limits<double>::max(), max_s = 0;
        const double cpu_start = process_cpu_seconds();
        const auto start = Clock::now();
        auto last = start;
        for (int i = 0; i < options.frames; ++i) {
            frame();
            const auto now = Clock::now();
            const double s = std::chrono::duration<double>(now - last).count();
            min_s = std::min(min_s, s);
            max_s = std::max(max_s, s);
            last = now;
        }
        row.cpu_ms = 1e3 * (process_cpu_seconds() - cpu_start) / options.frames;
        row.frames = options.frames;
        row.seconds = std::chrono::duration<double>(last - start).count();
        row.fps = row.seconds > 0 ? row.frames / row.seconds : 0;
        row.mean_ms = 1e3 * row.seconds / row.frames;
        row.min_ms = 1e3 * min_s;
        row.max_ms = 1e3 * max_s;
        report.rows.push_back(row);
    }
    const BenchmarkRow* at32 = nullptr;
    const BenchmarkRow* at256 = nullptr;
    for (const auto& row : report.rows) {
        if (row.skipped) continue;
        if (row.K_used == 32) at32 = &row;
        if (row.K_used == 256) at256 = &row;
    }
    if (object_frames > 0) report.object_ms = object_ms / object_frames;
    if (at32 && at256 && at32->mean_ms > 0) report.ratio_256_32 = at256->mean_ms / at32->mean_ms;
    return report;
}

std::string format_benchmark(const BenchmarkReport& r) {
    std::string out = fmt::format(
        "benchmark: {} vertices, {} triangles, K={}, {}x{}, {}x MSAA{}, {}, k={}{}; {}; host {}\n",
        r.vertices, r.triangles, r.K, r.width, r.height, r.msaa, r.msaa_auto ? " (automatic)" : "",
        r.direct ? "drawn straight to 8 bits" : "float target + present", r.k,
        r.rotate_light ? ", light turned every frame" : "", r.context, r.host);
    if (!r.transfer.empty()) out += r.transfer + "\n";
    if (r.shadow_map > 0)
        out += fmt::format(
            "sun: a {}² shadow map{}, texel {:.1f} mm, {} filter\n", r.shadow_map,
            r.moving_shadow_map > 0 ? fmt::format(" ({}² while it moves)", r.moving_shadow_map)
                                    : std::string(),
            1e3 * r.shadow_texel,
            r.sun_filter == SunFilter::full ? "full (16 + 1 blocker taps, 32 PCF taps)"
                                            : "interactive (8 + 1 blocker taps, 16 PCF taps)");
    if (r.object_vertices > 0)
        out += fmt::format(
            "object: {} vertices moved every frame, lit from the probes: {:.2f} ms "
            "of CPU shading + upload per frame (in the frame times)\n",
            r.object_vertices, r.object_ms);
    for (const auto& row : r.rows) {
        if (row.skipped) {
            out += fmt::format("K'={:<4} skipped: larger than the file's K={}\n", row.K_used, r.K);
            continue;
        }
        out += fmt::format(
            "K'={:<4} frames={}  fps={:.1f}  mean_ms={:.2f}  min_ms={:.2f}  max_ms={:.2f}  "
            "cpu_ms={:.2f}\n",
            row.K_used, row.frames, row.fps, row.mean_ms, row.min_ms, row.max_ms, row.cpu_ms);
    }
    if (r.ratio_256_32 > 0)
        out += fmt::format("frame time K'=256 / K'=32: {:.3f}\n", r.ratio_256_32);
    else
        out += "frame time K'=256 / K'=32: n/a (needs both)\n";
    return out;
}

}  // namespace shprt::viewer
