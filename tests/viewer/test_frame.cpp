// The viewer's frame without a window: --screenshot is `shprt render`'s picture (the same
// render_image drawing, bit for bit, then the same save_image), and the benchmark measures one row
// per K' it can and skips the others.
#include "benchmark.hpp"
#include "light_rig.hpp"
#include "screenshot.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/host.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/shade/tonemap.hpp"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

namespace shprt::viewer {
namespace {

#define SKIP_WITHOUT_GL()                                                              \
    do {                                                                               \
        try {                                                                          \
            HeadlessGlContext probe;                                                   \
        } catch (const Error& e) {                                                     \
            GTEST_SKIP() << "no headless OpenGL 4.3 core context (EGL): " << e.what(); \
        }                                                                              \
    } while (0)

struct Scene {
    Mesh mesh;
    TransferSet transfer;
};

const Scene& box_scene(int K) {
    static std::unique_ptr<Scene> cache[2];
    auto& slot = cache[K == 64 ? 1 : 0];
    if (!slot) {
        slot = std::make_unique<Scene>();
        slot->mesh = load_scene("builtin:box_on_plane");
        BakeOptions o;
        o.K = K;
        o.samples = 256;
        o.seed = 3;
        slot->transfer = bake(slot->mesh, o);
    }
    return *slot;
}

TEST(Screenshot, IsRenderImageBitForBit) {
    SKIP_WITHOUT_GL();
    const Scene& s = box_scene(20);  // not a full band
    struct Case {
        double k;
        int K_used;
        float exposure;
        ShadeView view;
    };
    const Case cases[] = {{1.0, 0, 1.0f, ShadeView::radiance},
                          {0.4, 0, 1.7f, ShadeView::radiance},
                          {1.0, 9, 0.8f, ShadeView::irradiance},
                          {1.0, 0, 1.0f, ShadeView::transfer}};
    LightSetup setup;
    setup.specs = {"builtin"};
    setup.yaw_pitch_roll_deg = {30, 0, 0};
    LightRig rig(s.transfer.layout.K);
    rig.set_source(setup);
    const ShLight light = rig.light();
    for (const Case& c : cases) {
        FrameConfig config;
        config.width = 96;
        config.height = 64;
        config.exposure = c.exposure;
        config.draw.camera = default_camera(s.mesh, 96.0f / 64.0f);
        config.draw.k = c.k;
        config.draw.K_used = c.K_used;
        config.draw.view = c.view;
        std::string context;
        const Image shot =
            render_screenshot(s.mesh, s.transfer, light, config, OffscreenBackend::egl, &context);
        EXPECT_NE(context.find("OpenGL"), std::string::npos) << context;
        ASSERT_EQ(shot.width, 96);
        ASSERT_EQ(shot.height, 64);
        const Image linear = render_image(
            s.mesh, s.transfer, prepare_light(setup, s.transfer.layout.K), config.draw, 96, 64);
        // The same drawing in the same kind of context: the same floats, so save_image writes the
        // same file for any exposure.
        EXPECT_EQ(shot.rgb, linear.rgb) << "k=" << c.k << " K'=" << c.K_used;
        int lit = 0;
        for (float v : linear.rgb) lit += display_encode8(v, c.exposure) > 10;
        EXPECT_GT(lit, int(linear.rgb.size() / 10))
            << "the scene covers a good part of the picture";
    }
}

TEST(Frame, AutomaticMsaaDropsOnlyContinuousFramesOnASoftwareRasteriser) {
    SKIP_WITHOUT_GL();
    HeadlessGlContext context;
    EXPECT_EQ(choose_samples(2, true), 2);
    EXPECT_EQ(choose_samples(8, false), 8);
    EXPECT_EQ(choose_samples(kAutoMsaa, false), 4) << "a screenshot samples as `shprt render`";
    const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const bool llvmpipe = renderer.find("llvmpipe") != std::string::npos;
    EXPECT_EQ(is_software_renderer(), llvmpipe) << renderer;
    EXPECT_EQ(choose_samples(kAutoMsaa, true), llvmpipe ? 1 : 4) << renderer;
}

// A single-sample frame goes straight into a framebuffer with a depth buffer, and through a float
// target into one without (the depth test needs one); both show the same picture, and so does a
// 4-sample frame up to its edge pixels.
TEST(Frame, SingleSampleFramesAreDrawnDirectWhereTheFramebufferHasDepth) {
    SKIP_WITHOUT_GL();
    HeadlessGlContext context;
    const Scene& s = box_scene(20);
    const int w = 80, h = 60;
    Renderer renderer;
    renderer.set_scene(s.mesh, s.transfer);
    renderer.set_light(make_light({"builtin"}, 20));
    DrawSettings settings;
    settings.camera = default_camera(s.mesh, float(w) / float(h));
    settings.k = 0.5;

    DisplayTarget with_depth(w, h);
    FrameTarget direct;
    direct.prepare(w, h, 1, with_depth.framebuffer());
    EXPECT_EQ(direct.float_target(), nullptr);
    EXPECT_EQ(direct.samples(), 1);
    draw_frame(renderer, direct, settings, 1.3f, with_depth.framebuffer(), w, h);
    const Rgb8Image a = read_framebuffer(with_depth.framebuffer(), w, h);

    // A colour-only framebuffer.
    GLuint fbo = 0, colour = 0;
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(1, &colour);
    glBindRenderbuffer(GL_RENDERBUFFER, colour);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    ASSERT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    FrameTarget through_float;
    through_float.prepare(w, h, 1, fbo);
    ASSERT_NE(through_float.float_target(), nullptr);
    EXPECT_EQ(through_float.float_target()->samples(), 1);
    draw_frame(renderer, through_float, settings, 1.3f, fbo, w, h);
    const Rgb8Image b = read_framebuffer(fbo, w, h);
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &colour);
    int worst = 0, lit = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        worst = std::max(worst, std::abs(int(a.rgb[i]) - int(b.rgb[i])));
        lit += a.rgb[i] > 10;
    }
    EXPECT_LE(worst, 1);
    EXPECT_GT(lit, int(a.rgb.size() / 10)) << "the scene covers a good part of the picture";

    FrameTarget multisampled;
    multisampled.prepare(w, h, 4, with_depth.framebuffer());
    if (multisampled.samples() > 1) {
        ASSERT_NE(multisampled.float_target(), nullptr);
        draw_frame(renderer, multisampled, settings, 1.3f, with_depth.framebuffer(), w, h);
        const Rgb8Image m = read_framebuffer(with_depth.framebuffer(), w, h);
        double sum = 0;
        for (std::size_t i = 0; i < a.rgb.size(); ++i)
            sum += std::abs(int(a.rgb[i]) - int(m.rgb[i]));
        EXPECT_LT(sum / double(a.rgb.size()), 2.0) << "the same picture, antialiased";
        EXPECT_GT(sum, 0.0) << "the edges are antialiased";
    }
}

TEST(Benchmark, MeasuresEachBasisSizeTheFileHasAndSkipsTheRest) {
    SKIP_WITHOUT_GL();
    const Scene& s = box_scene(64);
    LightRig rig(s.transfer.layout.K);
    rig.set_source(LightSetup{});
    FrameConfig config;
    config.width = 64;
    config.height = 48;
    config.msaa = 1;
    config.draw.camera = default_camera(s.mesh, 64.0f / 48.0f);
    BenchmarkOptions options;
    options.frames = 4;
    options.warmup_frames = 1;
    options.backend = OffscreenBackend::egl;
    for (bool rotate : {false, true}) {
        options.rotate_light = rotate;
        const BenchmarkReport r = run_benchmark(s.mesh, s.transfer, rig, config, options);
        EXPECT_EQ(r.K, 64);
        EXPECT_EQ(r.vertices, s.mesh.vertex_count());
        ASSERT_EQ(r.rows.size(), 5u);
        const int want_K[] = {32, 48, 64, 128, 256};
        for (int i = 0; i < 5; ++i) {
            const BenchmarkRow& row = r.rows[static_cast<std::size_t>(i)];
            EXPECT_EQ(row.K_used, want_K[i]);
            EXPECT_EQ(row.skipped, want_K[i] > 64);
            if (row.skipped) continue;
            EXPECT_EQ(row.frames, 4);
            EXPECT_GT(row.fps, 0.0);
            EXPECT_GT(row.mean_ms, 0.0);
            EXPECT_LE(row.min_ms, row.mean_ms * (1 + 1e-9));
            EXPECT_GE(row.max_ms, row.mean_ms * (1 - 1e-9));
            EXPECT_NEAR(row.fps * row.mean_ms, 1000.0, 1e-6);
        }
        EXPECT_EQ(r.ratio_256_32, 0.0) << "no K'=256 in a K=64 file";
        const std::string text = format_benchmark(r);
        EXPECT_NE(text.find("K'=48   frames=4  fps="), std::string::npos) << text;
        EXPECT_NE(text.find("K'=256  skipped"), std::string::npos) << text;
        EXPECT_NE(text.find("n/a"), std::string::npos) << text;
        EXPECT_NE(text.find("1x MSAA, drawn straight to 8 bits, k="), std::string::npos)
            << "asked for, not automatic; no float target";
        EXPECT_TRUE(r.direct);
        // The CPU it ran on, since the hosts of one machine kind differ (core/host.hpp).
        EXPECT_EQ(r.host, host_cpu());
        EXPECT_NE(text.find("; host " + host_cpu() + "\n"), std::string::npos) << text;
    }
    // With MSAA (where the implementation has it) the frames go through the float target.
    config.msaa = 4;
    options.rotate_light = false;
    const BenchmarkReport msaa = run_benchmark(s.mesh, s.transfer, rig, config, options);
    if (msaa.msaa > 1) {
        EXPECT_FALSE(msaa.direct);
        EXPECT_NE(format_benchmark(msaa).find("x MSAA, float target + present, k="),
                  std::string::npos);
    }
    options.frames = 0;
    EXPECT_THROW(run_benchmark(s.mesh, s.transfer, rig, config, options), Error);
}

}  // namespace
}  // namespace shprt::viewer
