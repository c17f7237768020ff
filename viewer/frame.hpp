// One displayed frame, the same in the window and in --benchmark: the scene is drawn by the shared
// Renderer into a multisampled float target, then presented (the resolve, exposure, ACES filmic
// tone map, sRGB: Renderer::present, the GPU twin of save_image's PNG encoding) into an 8-bit
// framebuffer — the window's, or a DisplayTarget when headless. (--screenshot draws the same
// scene through render_image and save_image instead: screenshot.hpp.)
// Every function needs a current OpenGL 4.3 core context.
#pragma once

#include "shprt/render/renderer.hpp"
#include "shprt/render/save_image.hpp"

#include <cstddef>
#include <cstdint>
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

// What the command line and the panel decide about a frame, besides the light.
struct FrameConfig {
    DrawSettings draw;   // camera, k, gloss, K', view, wireframe, background
    float exposure = 1;  // > 0
    int width = 1280, height = 720;
    int msaa = kAutoMsaa;  // samples of the float target; kAutoMsaa: see choose_samples
};

// What the GPU holds of glossy transfer, for the panel and the benchmark: "25x25 matrices:
// 1300 B/vertex on the GPU", or the CPCA code's clusters, vectors and bytes per vertex
// (`bytes_per_vertex`: Renderer::transfer_bytes_per_vertex). Empty for vector transfer.
std::string describe_gpu_transfer(const TransferSet& transfer, double bytes_per_vertex);

// Draws the scene into `target` (bind, Renderer::draw), then presents it (resolving) into
// `framebuffer` (0 = the window's default framebuffer) with viewport (0, 0, width, height) of
// the target's size.
void draw_frame(Renderer& renderer, RenderTarget& target, const DrawSettings& settings,
                float exposure, unsigned framebuffer);

// An offscreen RGBA8 framebuffer standing in for a window's: the present pass writes display
// values into it.
class DisplayTarget {
public:
    // Throws Error(unsupported) if the framebuffer is incomplete.
    DisplayTarget(int width, int height);
    ~DisplayTarget();
    DisplayTarget(const DisplayTarget&) = delete;
    DisplayTarget& operator=(const DisplayTarget&) = delete;

    unsigned framebuffer() const { return m_fbo; }
    int width() const { return m_width; }
    int height() const { return m_height; }

private:
    int m_width, m_height;
    unsigned m_fbo = 0, m_color_rb = 0;
};

// Reads the colour buffer of `framebuffer` (0 = the default framebuffer's back buffer), rows top
// first, for save_png (render/save_image.hpp). Waits for rendering to finish.
Rgb8Image read_framebuffer(unsigned framebuffer, int width, int height);

// The first `count` floats of the OpenGL buffer object `buffer` (e.g. Renderer::transfer_buffer()),
// read back to the host: for tests and diagnostics. Throws Error(invalid_argument) if the buffer
// is smaller.
std::vector<float> read_gl_buffer(unsigned buffer, std::size_t count);

}  // namespace shprt::viewer
