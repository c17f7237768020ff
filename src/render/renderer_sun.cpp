// The Renderer's sun kept out of the SH sum (renderer.hpp, Renderer::set_sun): the sun turned
// with the light, its SH projection's uniform blocks for the bounced term, and the shadow map
// pass (sun_pass.hpp) it owns. The draw's use of them is in renderer.cpp (draw_scene).
#include "gl_util.hpp"
#include "object_pass.hpp"
#include "scene_pass.hpp"
#include "shprt/core/error.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/render/renderer.hpp"
#include "sun_pass.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace shprt {

using gl::kLightBlockBytes;
using gl::light_stride;

void Renderer::set_sun(const PreparedSun* sun) {
    if (!sun) {
        m_sun_source.reset();
        ++m_sun_generation;
        return;
    }
    SHPRT_CHECK(!(m_pass && is_texel(m_layout) && is_glossy_matrix(m_layout)), unsupported,
                "a sun kept out of the SH sum lights glossy matrices per vertex only: texel "
                "matrices are not drawn with it; a sun: light projects the sun into SH for them");
    SHPRT_CHECK(sun->sh.K >= 1 && sun->sh.K <= kMaxLightK &&
                    sun->sh.coeffs.size() == 3 * std::size_t(sun->sh.K),
                invalid_argument, "the sun's SH projection has K = {} and {} coefficients",
                sun->sh.K, sun->sh.coeffs.size());
    m_sun_source = *sun;
    if (!m_sun_pass) m_sun_pass = std::make_unique<SunPass>(m_shadow_map_size);
    m_sun_map = nullptr;  // update_sun_map chooses
    update_world_sun();
}

void Renderer::set_sun_filter(SunFilter filter) {
    if (filter == m_sun_filter) return;
    m_sun_filter = filter;  // the scene programs are per filter, the texel pass's rebuilt
    if (m_pass) m_pass->set_sun_filter(filter);
}

void Renderer::set_shadow_map_size(int texels) {
    SHPRT_CHECK(texels >= 64 && texels <= 8192, invalid_argument,
                "a shadow map of {} texels a side (64 to 8192)", texels);
    if (texels == m_shadow_map_size) return;
    m_shadow_map_size = texels;
    if (m_sun_pass) m_sun_pass = std::make_unique<SunPass>(texels);  // redrawn at the next draw
    m_sun_map = nullptr;
}

double Renderer::shadow_texel_size() const {
    return SunPass::texel_size(m_bounds_radius, m_shadow_map_size);
}

bool Renderer::sun_bounced() const { return m_sun_source && m_pass && m_pass->has_direct_part(); }

std::uint64_t Renderer::sun_map_builds() const {
    return (m_sun_pass ? m_sun_pass->map_builds() : 0) +
           (m_sun_pass_moving ? m_sun_pass_moving->map_builds() : 0);
}

void Renderer::update_world_sun() {
    if (!m_sun_source || !m_has_light) return;
    m_world_sun = m_sun_source->sun;
    const bool turned = !(m_light_rotation == Mat3d::identity());
    if (turned) m_world_sun.direction = normalize(m_light_rotation * m_world_sun.direction);
    // Its SH projection in the scene's frame, in the light block's layout for the sky's K; and
    // added to the sky, the light of the pass over T (its T_0 part is taken out again).
    const ShLight sh = turned
                           ? rotated_light(m_sun_source->sh, m_light_rotation, m_sun_source->sh.K)
                           : m_sun_source->sh;
    m_world_sun_sh = sh;
    const int stride = light_stride(m_light.K), K = std::min(sh.K, m_light.K);
    std::vector<float> sun(3 * std::size_t(stride), 0.0f), sum(sun.size(), 0.0f);
    for (int c = 0; c < 3; ++c) {
        std::copy_n(sh.channel(c), K, sun.begin() + std::ptrdiff_t(c) * stride);
        for (int i = 0; i < m_light.K; ++i)
            sum[std::size_t(c) * stride + i] =
                m_light.channel(c)[i] + sun[std::size_t(c) * stride + i];
    }
    for (auto [ubo, data] : {std::pair{&m_sun_ubo, &sun}, std::pair{&m_sky_sun_ubo, &sum}}) {
        if (!*ubo)
            *ubo = gl::make_buffer(GL_UNIFORM_BUFFER, kLightBlockBytes, nullptr, GL_DYNAMIC_DRAW);
        glBindBuffer(GL_UNIFORM_BUFFER, *ubo);
        glBufferSubData(GL_UNIFORM_BUFFER, 0, GLsizeiptr(data->size() * sizeof(float)),
                        data->data());
    }
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    ++m_sun_generation;
    gl::check("Renderer::update_world_sun");
}

void Renderer::set_moving_shadow_map_size(int texels) {
    SHPRT_CHECK(texels == 0 || (texels >= 64 && texels <= 8192), invalid_argument,
                "a moving shadow map of {} texels a side (0: none; 64 to 8192)", texels);
    m_moving_shadow_map_size = texels;
    m_sun_pass_moving.reset();
    m_sun_map = nullptr;
}

void Renderer::update_sun_map() {
    const auto draw = [&] {
        if (m_object) m_object->draw_triangles();  // the object casts too
        m_pass->draw_triangles();
    };
    // Moving: the state differs from the last frame's map (whichever was drawn) — the first
    // frame, with no map yet, is at rest.
    const bool coarse =
        m_moving_shadow_map_size > 0 && m_moving_shadow_map_size < m_sun_pass->size() &&
        m_sun_map != nullptr &&
        !m_sun_map->drawn_for(m_world_sun, m_bounds_centre, m_bounds_radius, m_geometry_generation);
    if (coarse && !m_sun_pass_moving)
        m_sun_pass_moving = std::make_unique<SunPass>(m_moving_shadow_map_size);
    m_sun_map = coarse ? m_sun_pass_moving.get() : m_sun_pass.get();
    m_sun_map->update(m_world_sun, m_bounds_centre, m_bounds_radius, m_geometry_generation, draw);
}

void Renderer::set_object(const Mesh* mesh, const ObjectShading* shading) {
    if (!mesh || !shading) {
        if (m_object) ++m_geometry_generation;  // the sun's map loses the object
        m_object.reset();
        return;
    }
    if (!m_object) m_object = std::make_unique<ObjectPass>();
    m_object->set(mesh->triangles, *shading);
    ++m_geometry_generation;  // the object moved: the sun's map is redrawn (when there is one)
}

}  // namespace shprt
