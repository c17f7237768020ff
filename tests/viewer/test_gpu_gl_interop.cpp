// CUDA–OpenGL interop, the path of `shprt view --bake --device cuda`: the GPU bake writes the
// transfer straight into the renderer's shader storage buffer, mapped into CUDA. The buffer must
// then hold exactly what the GPU bake returns through the host, and the renderer must draw it.
// Needs a CUDA device and an OpenGL context on that same GPU (EGL's device platform on an NVIDIA
// machine); skips with the reason otherwise (on llvmpipe the registration fails).
#include "frame.hpp"

#include "bake/bake_test_util.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/bake/gpu_gl_interop.hpp"
#include "shprt/core/error.hpp"
#include "shprt/light/light.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/sh/sampler.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace shprt::viewer {
namespace {

TEST(GpuGlInterop, TheBakeWritesIntoTheRenderersBuffer) {
    const GpuInfo gpu = query_gpu();
    if (!gpu.available) GTEST_SKIP() << gpu.reason;
    std::unique_ptr<HeadlessGlContext> context;
    try {
        context = std::make_unique<HeadlessGlContext>();
    } catch (const Error& e) {
        GTEST_SKIP() << "no headless OpenGL 4.3 context: " << e.what();
    }
    const Mesh mesh = make_builtin("room");
    const DirectionSet set = make_direction_set(SamplerKind::uniform, 3, 512);
    BakeOptions o;
    o.K = 64;
    o.chunk_receivers = 4096;  // the same chunks both ways: the same SGEMMs, the same bits
    const TransferSet host = test::bake_gpu(mesh, o, set);

    // The renderer's buffer starts as zeros; the bake fills it through CUDA.
    TransferSet zeros = host;
    std::fill(zeros.coeffs.begin(), zeros.coeffs.end(), 0.0f);
    Renderer renderer;
    renderer.set_scene(mesh, zeros);
    std::unique_ptr<GlBufferInterop> interop;
    try {
        interop = std::make_unique<GlBufferInterop>(renderer.transfer_buffer());
    } catch (const Error& e) {
        GTEST_SKIP() << "the OpenGL context is not on the CUDA device (" << context->description()
                     << "): " << e.what();
    }
    std::size_t bytes = 0;
    float* device = interop->map(bytes);
    ASSERT_GE(bytes, host.coeffs.size() * sizeof(float));
    const TransferSet in_place = test::bake_gpu(mesh, o, set, device);
    interop->unmap();
    EXPECT_TRUE(in_place.coeffs.empty()) << "written to the device buffer only";

    const std::vector<float> buffer =
        read_gl_buffer(renderer.transfer_buffer(), host.coeffs.size());
    EXPECT_TRUE(buffer == host.coeffs) << "the GL buffer differs from the GPU bake's result";

    // And the renderer draws from it: a lit picture, the same as from an uploaded transfer.
    renderer.set_light(make_light({"builtin"}, o.K));
    DrawSettings settings;
    settings.camera = default_camera(mesh, 4.0f / 3.0f);
    settings.reshade = true;  // the buffer changed behind the renderer's back
    RenderTarget target(64, 48, 1);
    target.bind();
    renderer.draw(settings, 64, 48);
    const Image via_interop = target.read_pixels();
    renderer.set_scene(mesh, host);
    target.bind();
    renderer.draw(settings, 64, 48);
    EXPECT_EQ(via_interop.rgb, target.read_pixels().rgb);
    double sum = 0;
    for (float v : via_interop.rgb) sum += v;
    EXPECT_GT(sum, 0.0) << "the picture is lit";
}

}  // namespace
}  // namespace shprt::viewer
