// One displayed frame, the same in the window and in --benchmark, drawn by the shared Renderer
// into an 8-bit framebuffer — the window's, or a DisplayTarget when headless. With MSAA the scene
// goes into a multisampled float target, then is presented (the resolve, exposure, ACES filmic
// tone map, sRGB: Renderer::present, the GPU twin of save_image's PNG encoding); with one sample
// (the default on a software rasteriser) it is drawn straight into the framebuffer with the same
// encoding in its fragment shaders (Renderer::draw_to_display). (--screenshot draws the same
// scene through render_image and save_image instead: screenshot.hpp.)
// Every function needs a current OpenGL 4.3 core context.
#pragma once

#include "shprt/render/renderer.hpp"
#include "shprt/shade/save_image.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace shprt::viewer {

// `--msaa` left to the viewer (choose_samples).
inline constexpr int kAutoMsaa = 0;

// Samples of the float target: `requested` when it is > 0. For kAutoMsaa, 4 (as `shprt render
// --samples`), except for frames drawn continuously (`continuous`: the window, --benchmark) on a
// software rasteriser (is_software_renderer()), where it is 1: llvmpipe draws a 1280×720 room
// frame 2.3× slower with 4× MSAA (27 against 61 frames/s; bench/RESULTS.md "Viewer"). Needs a
// current context.
int choose_samples(int requested, bool continuous);

// Texels a side of the sun's shadow map (Renderer::set_shadow_map_size): kShadowMapSize (2048, as
// `shprt render` and --screenshot), except for frames drawn continuously on a software
// rasteriser, where it is 1024 — the map is redrawn whenever the sun or an object moves, and
// llvmpipe's 2048² depth pass cost ~10-15 ms of CPU a frame more (bench/RESULTS.md, "The
// viewer's frame on llvmpipe"). The room's texel is then 8.7 mm (4.35 at 2048; `view
// --benchmark` prints it). Needs a current context.
int choose_shadow_map_size(bool continuous);

// The sun's shadow filter (Renderer::set_sun_filter): SunFilter::full, except for frames drawn
// continuously on a software rasteriser, where it is interactive (half the taps: the full PCSS
// was ~16 + 7 of the 80 CPU ms a frame of the room with the sun moving; bench/RESULTS.md, "The
// sun's filter on llvmpipe"). Needs a current context.
SunFilter choose_sun_filter(bool continuous);

// Texels a side of the sun's map while the sun or an object moves
// (Renderer::set_moving_shadow_map_size): 512 for frames drawn continuously on a software
// rasteriser, where the 1024² map's redraw was ~17 of a moving sun's ~65 CPU ms a frame; 0 (the
// map at rest) otherwise. The first frame at rest redraws the map at its full size.
int choose_moving_shadow_map_size(bool continuous);

// What the command line and the panel decide about a frame, besides the light.
struct FrameConfig {
    DrawSettings draw;   // camera, k, gloss, K', view, wireframe, background
    float exposure = 1;  // > 0
    int width = 1280, height = 720;
    int msaa = kAutoMsaa;  // samples of the float target; kAutoMsaa: see choose_samples
};

// What the GPU holds of glossy transfer, for the panel and the benchmark: the matrices as the
// library describes them (describe_matrices: "25x25 matrices", or the CPCA code's clusters and
// vectors) and "1300 B/vertex on the GPU (float32)" (`bytes_per_vertex`:
// Renderer::transfer_bytes_per_vertex). Empty for vector transfer.
std::string describe_gpu_transfer(const TransferSet& transfer, double bytes_per_vertex);

// Where a displayed frame is drawn before it reaches the framebuffer: a float target when
// `samples` (asked for) resolves to more than one supported sample
// (RenderTarget::supported_samples) or the framebuffer has no depth buffer; else nothing —
// single-sample frames are drawn straight into the framebuffer. Reused while the size, the
// samples asked for and the framebuffer stay.
class FrameTarget {
public:
    // Makes or keeps the target for a width × height frame of `framebuffer` (0 = the window's)
    // with `samples` asked for.
    void prepare(int width, int height, int samples, unsigned framebuffer);
    int samples() const { return m_samples; }                // samples the frame has
    RenderTarget* float_target() { return m_target.get(); }  // nullptr: drawn direct

private:
    std::unique_ptr<RenderTarget> m_target;
    int m_width = 0, m_height = 0, m_requested = -1, m_samples = 1;
    unsigned m_framebuffer = 0;
};

// Draws one frame of width × height (`target` prepared for it) into `framebuffer` (0 = the
// window's default framebuffer): through `target`'s float target and Renderer::present when it
// has one, else with Renderer::draw_to_display.
void draw_frame(Renderer& renderer, FrameTarget& target, const DrawSettings& settings,
                float exposure, unsigned framebuffer, int width, int height);

// The first `count` floats of the OpenGL buffer object `buffer` (e.g. Renderer::transfer_buffer()),
// read back to the host: for tests and diagnostics. Throws Error(invalid_argument) if the buffer
// is smaller.
std::vector<float> read_gl_buffer(unsigned buffer, std::size_t count);

}  // namespace shprt::viewer
