// The OpenGL renderer of baked PRT scenes (render/renderer.hpp), the frame driver: the scene's
// pass chosen from the kind table (scene_pass.hpp), the light and its uniform blocks, the frame's
// state, the light's background and the tone-mapped presentation.
#include "shprt/render/renderer.hpp"

#include "gl_util.hpp"
#include "object_pass.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parallel.hpp"
#include "shprt/light/equirect.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/zonal.hpp"
#include "shprt/shade/texel_shade.hpp"
#include "shprt/shade/tonemap.hpp"
#include "shprt/transfer/kind_table.hpp"
#include "sun_pass.hpp"
#include "texel_pass.hpp"
#include "vertex_pass.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace shprt {

DrawSettings draw_settings(const ShadingPlan& plan, ShadeView view) {
    DrawSettings settings;
    settings.view = view;
    settings.k = plan.options.k;
    settings.gloss = plan.options.gloss;
    settings.K_used = plan.options.K_used;
    if (plan.glossy) {  // transfer matrices, shaded on the GPU
        settings.brdf = plan.glossy->brdf;
        settings.material_brdfs = plan.glossy->material_brdfs;
        settings.albedo = plan.glossy->albedo;
    }
    return settings;
}
namespace {

// Size of the equirect texture the background is drawn from: the light is band-limited (at most
// 32 bands, features ≳ 5°), so 256 × 128 texels (1.4° each) resolve it.
constexpr int kBackgroundWidth = 256, kBackgroundHeight = 128;

using gl::kLightBlockBytes;
using gl::light_stride;
static_assert(gl::kLightBlockVec4s * 4 == 3 * kMaxLightK, "light block: 3 padded channels");
static_assert(gl::kRecurrenceBlockVec4s * 2 == kMaxLightK, "recurrence block: (a, b) per index");

using gl::delete_buffer;

// The pass that draws a scene of the kind table's `pass`.
std::unique_ptr<ScenePass> make_pass(ShadingPass pass, SunFilter filter) {
    if (pass == ShadingPass::texels) return std::make_unique<TexelPass>(filter);
    return std::make_unique<VertexPass>();
}

}  // namespace

Renderer::Renderer() {
    require_gl43();
    m_software = is_software_renderer();
    for (int display = 0; display < 2; ++display) {
        m_background_program[display] = gl::compile_program(
            gl::kFullscreenVertexShader,
            gl::fragment_shader(gl::kBackgroundFragmentShader, display == 1).c_str(), "background");
    }
    m_present_program =
        gl::compile_program(gl::kFullscreenVertexShader, gl::present_shader().c_str(), "present");
    glGenVertexArrays(1, &m_empty_vao);
    GLint max_block = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &max_block);
    SHPRT_CHECK(max_block >= kLightBlockBytes, unsupported,
                "this OpenGL's uniform blocks hold {} bytes; the light needs {}", max_block,
                kLightBlockBytes);
    // Enough bands for any K' (K' ≤ light K ≤ kMaxLightK).
    const std::vector<float> table = gl::recurrence_table(sh_bands_for(kMaxLightK));
    m_recurrence_ubo = gl::make_buffer(GL_UNIFORM_BUFFER, table.size() * sizeof(float),
                                       table.data(), GL_STATIC_DRAW);
    m_light_ubo = gl::make_buffer(GL_UNIFORM_BUFFER, kLightBlockBytes, nullptr, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    gl::check("Renderer");
}

Renderer::~Renderer() {
    m_pass.reset();
    delete_buffer(m_light_ubo);
    delete_buffer(m_recurrence_ubo);
    delete_buffer(m_sun_ubo);
    delete_buffer(m_sky_sun_ubo);
    if (m_background_texture) glDeleteTextures(1, &m_background_texture);
    if (m_empty_vao) glDeleteVertexArrays(1, &m_empty_vao);
    for (unsigned p : {m_background_program[0], m_background_program[1], m_present_program})
        if (p) glDeleteProgram(p);
    for (const auto& by_code : m_scene_program)
        for (const auto& programs : by_code)
            for (unsigned p : programs)
                if (p) glDeleteProgram(p);
}

unsigned Renderer::scene_program(int display, int sun_code) {
    unsigned& program = m_scene_program[display][sun_code][static_cast<int>(m_sun_filter)];
    if (!program)
        program = gl::compile_program(
            gl::kSceneVertexShader,
            gl::fragment_shader(gl::kSceneFragmentShader, display == 1,
                                static_cast<gl::SunCode>(sun_code), m_sun_filter)
                .c_str(),
            "scene");
    return program;
}

void Renderer::set_scene(const Mesh& mesh, const TransferSet& transfer) {
    SHPRT_CHECK(!m_sun_source || !is_matrix(transfer.layout) || !is_texel(transfer.layout),
                unsupported,
                "a sun kept out of the SH sum lights glossy matrices per vertex only: texel "
                "matrices are not drawn with it; a sun: light projects the sun into SH for them");
    // The sun's shadow map covers the scene's bounding sphere.
    const Bounds bounds = mesh_bounds(mesh);
    m_bounds_centre = (bounds.lo + bounds.hi) * 0.5f;
    m_bounds_radius = 0.5f * length(bounds.hi - bounds.lo);
    ++m_geometry_generation;
    // The scene's pass, once per scene, from the kind table (the CPU's shade_receivers asks the
    // same): full matrices have none (the vertex pass refuses them as shade_vertices does).
    const ShadingPass pass = shading_pass(transfer.layout);
    if (pass != ShadingPass::texels)
        SHPRT_CHECK(mesh.triangle_count() > 0, invalid_argument, "mesh {} has no triangles to draw",
                    mesh.source);
    // The two pass classes; a scene of the same class reuses the pass (and its programs). A
    // pass checks before it releases anything, so a refused scene leaves the last one drawn.
    const int kind = pass == ShadingPass::texels ? 1 : 0;
    if (m_pass && m_pass_kind == kind) {
        m_pass->set_scene(mesh, transfer);
    } else {
        std::unique_ptr<ScenePass> fresh = make_pass(pass, m_sun_filter);
        fresh->set_scene(mesh, transfer);
        m_pass = std::move(fresh);
        m_pass_kind = kind;
    }
    m_layout = transfer.layout;
    m_K = transfer.layout.K;
    m_channels = transfer.layout.channels;
}

void Renderer::update_transfer(std::size_t first_vertex, std::size_t vertex_count,
                               const float* coeffs) {
    SHPRT_CHECK(m_pass != nullptr, invalid_argument, "update_transfer before set_scene");
    m_pass->update_transfer(first_vertex, vertex_count, coeffs);
}

unsigned Renderer::transfer_buffer() const { return m_pass ? m_pass->transfer_buffer() : 0; }

bool Renderer::last_shading_on_host() const { return m_pass && m_pass->last_shading_on_host(); }

bool Renderer::scene_has_material_brdfs() const { return m_pass && m_pass->has_material_brdfs(); }

std::size_t Renderer::vertex_count() const { return m_pass ? m_pass->receiver_count() : 0; }

double Renderer::transfer_bytes_per_vertex() const {
    return m_pass ? m_pass->bytes_per_receiver() : 0;
}

void Renderer::set_vertex_shading(VertexShading where) { m_vertex_shading = where; }

void Renderer::set_light(const ShLight& light, const Mat3d& rotation) {
    SHPRT_CHECK(
        light.K > 0 && light.K <= kMaxLightK && light.coeffs.size() == 3 * std::size_t(light.K),
        invalid_argument, "light has K = {} and {} coefficients (expected 3 × K, K ≤ {})", light.K,
        light.coeffs.size(), kMaxLightK);
    if (!m_has_light || light.K != m_light_source.K || light.coeffs != m_light_source.coeffs) {
        m_light_source = light;
        ++m_source_generation;
    }
    m_light_rotation = rotation;
    // The coefficients to shade with come from the one light path; only the background keeps
    // its shortcut for full bands (upload_background).
    m_light = rotated_light(light, rotation, light.K);
    // The uniform block's layout: each channel padded to a multiple of 4 coefficients.
    const int stride = light_stride(m_light.K);
    std::vector<float> padded(3 * std::size_t(stride), 0.0f);
    for (int c = 0; c < 3; ++c)
        std::copy_n(m_light.channel(c), m_light.K, padded.begin() + std::ptrdiff_t(c) * stride);
    glBindBuffer(GL_UNIFORM_BUFFER, m_light_ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, static_cast<GLsizeiptr>(padded.size() * sizeof(float)),
                    padded.data());
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    m_has_light = true;
    ++m_light_generation;
    update_world_sun();
    gl::check("Renderer::set_light");
}

int Renderer::effective_K(int K_used) const {
    SHPRT_CHECK(K_used >= 0, invalid_argument, "basis size K' = {} is negative", K_used);
    int K = std::min(m_K, m_light.K);
    if (K_used > 0) K = std::min(K, K_used);
    return K;
}

Mat3d Renderer::upload_background(int K) {
    // A full band is rotation invariant: the unrotated source's texture, looked up along R^T·d,
    // shows the rotated light exactly, and turning the light costs nothing here. A partial last
    // band is not: the texture is then made from the rotated (then truncated) light.
    const bool from_source = sh_count(sh_bands_for(K)) == K;
    const BackgroundKey key{K, from_source, from_source ? m_source_generation : m_light_generation};
    const Mat3d lookup = from_source ? m_light_rotation : Mat3d::identity();
    if (m_background_texture && m_background_key == key) return lookup;
    const ShLight& light = from_source ? m_light_source : m_light;
    // The light's SH reconstruction over the equirect grid, rows from the zenith down.
    std::vector<float> texels(std::size_t(kBackgroundWidth) * kBackgroundHeight * 3);
    parallel_for(
        0, kBackgroundHeight, 1, Split::automatic, [&](std::size_t first, std::size_t last) {
            std::vector<float> y(K);
            for (int row = int(first); row != int(last); ++row)
                for (int x = 0; x < kBackgroundWidth; ++x) {
                    const Vec3f d = equirect_pixel_direction<float>(x, row, kBackgroundWidth,
                                                                    kBackgroundHeight);
                    sh_eval_k(K, d.x, d.y, d.z, y.data());
                    float* out = texels.data() + (std::size_t(row) * kBackgroundWidth + x) * 3;
                    for (int c = 0; c < 3; ++c) {
                        const float* l = light.channel(c);
                        double s = 0;
                        for (int i = 0; i < K; ++i) s += double(l[i]) * y[i];
                        out[c] = static_cast<float>(s);
                    }
                }
        });
    if (!m_background_texture) {
        glGenTextures(1, &m_background_texture);
        glBindTexture(GL_TEXTURE_2D, m_background_texture);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGB32F, kBackgroundWidth, kBackgroundHeight);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);  // u wraps around
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, m_background_texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kBackgroundWidth, kBackgroundHeight, GL_RGB, GL_FLOAT,
                    texels.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    m_background_key = key;
    ++m_background_builds;
    gl::check("Renderer::upload_background");
    return lookup;
}

void Renderer::draw(const DrawSettings& s, int width, int height) {
    draw_scene(s, width, height, 0.0f);
}

void Renderer::draw_to_display(const DrawSettings& s, int width, int height, float exposure) {
    SHPRT_CHECK(exposure > 0 && std::isfinite(exposure), invalid_argument,
                "exposure {} must be positive", exposure);
    draw_scene(s, width, height, exposure);
}

void Renderer::draw_scene(const DrawSettings& s, int width, int height, float exposure) {
    SHPRT_CHECK(m_pass && m_has_light, invalid_argument,
                "Renderer::draw before set_scene and set_light");
    SHPRT_CHECK(width >= 1 && height >= 1, invalid_argument, "viewport {}x{} is empty", width,
                height);
    SHPRT_CHECK(s.k >= 0 && s.k <= 1, invalid_argument, "diffuse share k = {} is outside [0, 1]",
                s.k);
    const int K = effective_K(s.K_used);
    const Mat4f view_proj = view_projection_matrix(s.camera, float(width) / float(height));
    // The sun: drawn in the radiance and irradiance views (the transfer view has no light).
    const SunMode sun_mode = !m_sun_source                     ? SunMode::none
                             : s.view == ShadeView::radiance   ? SunMode::radiance
                             : s.view == ShadeView::irradiance ? SunMode::irradiance
                                                               : SunMode::none;
    const bool matrices = is_glossy_matrix(m_layout);
    SHPRT_CHECK(sun_mode != SunMode::radiance || s.k == 1 || matrices, unsupported,
                "a sun kept out of the SH sum lights diffuse receivers only (k = 1, got {}) or "
                "glossy matrices: the paper's glossy term is not linear in the light, so the sun "
                "cannot be taken out of it; a sun: light projects the sun into SH",
                s.k);
    if (sun_mode != SunMode::none) update_sun_map();

    glViewport(0, 0, width, height);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);  // rooms are seen from inside: both sides of every triangle
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    const int display = exposure > 0 ? 1 : 0;
    if (display) {
        glDisable(GL_FRAMEBUFFER_SRGB);  // the shaders encode sRGB themselves, as present does
        // The code present would write for the clear colour (exactly k/255 in the 8-bit target).
        auto code = [&](float c) { return float(display_encode8(c, exposure)) / 255.0f; };
        glClearColor(code(s.clear_color.x), code(s.clear_color.y), code(s.clear_color.z), 1.0f);
    } else {
        glClearColor(s.clear_color.x, s.clear_color.y, s.clear_color.z, 1.0f);
    }
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    // The scene's pass shades (when what its colours depend on changed) ...
    PassFrame frame;
    frame.settings = &s;
    frame.K = K;
    frame.view_proj = view_proj;
    frame.exposure = exposure;
    frame.light.sky = &m_light;
    frame.light.ubo = m_light_ubo;
    frame.light.recurrence_ubo = m_recurrence_ubo;
    frame.light.stride = light_stride(m_light.K);
    frame.light.generation = m_light_generation;
    frame.light.sun_sh = &m_world_sun_sh;
    frame.light.sun_ubo = m_sun_ubo;
    frame.light.sky_sun_ubo = m_sky_sun_ubo;
    frame.light.sun_generation = m_sun_generation;
    frame.sun_mode = sun_mode;
    frame.sun = sun_mode != SunMode::none ? m_sun_map : nullptr;
    frame.bounced_sun = sun_mode != SunMode::none && sun_bounced();
    frame.host = m_vertex_shading == VertexShading::host ||
                 (m_vertex_shading == VertexShading::automatic && m_software);
    frame.stats = &m_stats;
    m_pass->shade(frame);

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    // The scene's program with the frame's matrix, exposure and sun: for the scene, and again for
    // the object after a texel scene (whose pass has its own program).
    // Without a sun the program carries no sun code; glossy matrices may need the BRDF lobes.
    const gl::SunCode sun_code = sun_mode == SunMode::none ? gl::SunCode::none
                                 : matrices                ? gl::SunCode::full
                                                           : gl::SunCode::diffuse;
    const auto use_scene_program = [&] {
        glUseProgram(scene_program(display, static_cast<int>(sun_code)));
        glUniformMatrix4fv(gl::loc::kViewProj, 1, GL_FALSE, view_proj.m);
        if (display) glUniform1f(gl::loc::kDisplayExposure, exposure);
        if (sun_mode != SunMode::none) m_sun_map->bind(sun_mode, sun_code);
    };
    // ... and draws, with the scene program in use (a pass with its own program unbinds it).
    use_scene_program();
    glPolygonMode(GL_FRONT_AND_BACK, s.wireframe ? GL_LINE : GL_FILL);
    m_pass->draw(frame);
    if (m_object) {
        // The object through the scene's program: its colours and the sun's direct term.
        // Attributes 4 and 5 are off in its vertex array and read 0.
        if (m_pass->own_program()) use_scene_program();
        m_object->draw();
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glBindVertexArray(0);
    glActiveTexture(GL_TEXTURE0 + gl::kShadowMapUnit);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);

    if (s.background) {
        const Mat3d rotation = upload_background(K);
        // After the scene, at depth 1 with LEQUAL: only the pixels the scene left empty run the
        // (transcendental-heavy) lookup.
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
        glDepthMask(GL_FALSE);
        glUseProgram(m_background_program[display]);
        if (display) glUniform1f(gl::loc::kDisplayExposure, exposure);
        const Mat4f inv = inverse(view_proj);
        glUniformMatrix4fv(gl::loc::kInvViewProj, 1, GL_FALSE, inv.m);
        glUniform3f(gl::loc::kBgEye, s.camera.eye.x, s.camera.eye.y, s.camera.eye.z);
        // GLSL reads column-major: R's rows, given as columns, are the matrix R^T.
        float rows[9];
        for (int i = 0; i < 9; ++i) rows[i] = static_cast<float>(rotation.m[i / 3][i % 3]);
        glUniformMatrix3fv(gl::loc::kBgLightToTexture, 1, GL_FALSE, rows);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, m_background_texture);
        glBindVertexArray(m_empty_vao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindVertexArray(0);
        glDepthMask(GL_TRUE);
        glDepthFunc(GL_LESS);
    }
    glUseProgram(0);
    gl::check("Renderer::draw");
}

void Renderer::present(const RenderTarget& target, float exposure) {
    SHPRT_CHECK(exposure > 0 && std::isfinite(exposure), invalid_argument,
                "exposure {} must be positive", exposure);
    glViewport(0, 0, target.width(), target.height());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_FRAMEBUFFER_SRGB);  // the shader encodes sRGB itself, as the PNG writer does
    glUseProgram(m_present_program);
    glUniform1f(gl::loc::kExposure, exposure);
    glUniform1i(gl::loc::kSamples, target.samples());
    // Units 0 and 1 hold the two sampler types; the one the shader does not read stays empty.
    const bool multisampled = target.samples() > 1;
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, multisampled ? 0 : target.color_texture());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, multisampled ? target.color_texture() : 0);
    glBindVertexArray(m_empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
    glActiveTexture(GL_TEXTURE0);
    glUseProgram(0);
    gl::check("Renderer::present");
}

}  // namespace shprt
