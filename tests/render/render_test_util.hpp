// Helpers of the rendering tests: a headless OpenGL context or a skip, and the display-draw check;
// with everything of the shading tests' helpers (tests/shade/shade_test_util.hpp).
#pragma once

#include "shade/shade_test_util.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"

#include <epoxy/gl.h>

// Opens a headless OpenGL 4.3 context named `context` for the rest of the test, or SKIPs it with
// the reason (no EGL, an older OpenGL).
#define REQUIRE_GL(context)                                                        \
    std::unique_ptr<HeadlessGlContext> context;                                    \
    try {                                                                          \
        context = std::make_unique<HeadlessGlContext>();                           \
    } catch (const Error& e) {                                                     \
        GTEST_SKIP() << "no headless OpenGL 4.3 core context (EGL): " << e.what(); \
    }

namespace shprt::test {

// The single-sample frame `renderer` draws straight into an 8-bit framebuffer
// (Renderer::draw_to_display) against the same frame drawn into a float target and presented:
// the same codes but for one-level roundings in at most 0.1 % of them, and not a blank frame.
inline void expect_display_draw_matches_present(Renderer& renderer, const DrawSettings& settings,
                                                int width, int height, float exposure) {
    RenderTarget target(width, height, 1);
    target.bind();
    renderer.draw(settings, width, height);
    DisplayTarget presented(width, height), direct(width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, presented.framebuffer());
    renderer.present(target, exposure);
    glBindFramebuffer(GL_FRAMEBUFFER, direct.framebuffer());
    renderer.draw_to_display(settings, width, height, exposure);
    const Rgb8Image a = read_framebuffer(presented.framebuffer(), width, height);
    const Rgb8Image b = read_framebuffer(direct.framebuffer(), width, height);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    int worst = 0;
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        const int d = std::abs(int(a.rgb[i]) - int(b.rgb[i]));
        worst = std::max(worst, d);
        differ += d != 0;
    }
    EXPECT_LE(worst, 1);
    EXPECT_LE(differ, a.rgb.size() / 1000) << "codes that differ by one";
    std::vector<bool> seen(256, false);
    int levels = 0;
    for (unsigned char c : b.rgb)
        if (!seen[c]) seen[c] = true, ++levels;
    EXPECT_GT(levels, 20) << "distinct codes on screen";
}

}  // namespace shprt::test
