// The sun's shadow map and its per-fragment filter (sun_pass.hpp). PCSS: R. Fernando, "Percentage-
// closer soft shadows", SIGGRAPH 2005 sketch; taps on a Vogel (golden-angle) disc; receiver-plane
// depth bias from the surface normal (the plane's depth slope in map space).
#include "sun_pass.hpp"

#include "gl_util.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/shade/glossy.hpp"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <cmath>

namespace shprt {

namespace gl {

namespace {

const char* const kSunFunctionsSource = R"glsl(
layout(binding = 2) uniform sampler2D u_shadow_map;  // depth in [0, 1], 0 nearest the sun
layout(location = 20) uniform int u_sun_mode;        // 0 none, 1 radiance, 2 irradiance
layout(location = 21) uniform mat3 u_sun_basis;      // columns: the map's u and v, toward the sun
layout(location = 24) uniform vec3 u_sun_irradiance;  // E_n: the disc's, at normal incidence
layout(location = 25) uniform mat4 u_sun_to_map;     // world → (s, t, depth)
// x: a texel's width (world), y: tan(angular radius), z: the depth range (world), w: texels a side
layout(location = 29) uniform vec4 u_sun_filter;
#ifndef SHPRT_SUN_DIFFUSE
// Glossy matrices (SunPass::bind_glossy): the exit radiance k·ρ_d/π·E + (1 − k)·ρ_s·L·Ω·f(r·s)·V
// with f the vertex's BRDF lobe profile (shade/glossy.hpp, brdf_profile) about its reflection.
layout(location = 30) uniform int u_sun_glossy;          // 0: diffuse (ρ/π · E)
layout(location = 31) uniform vec3 u_sun_eye;
layout(location = 32) uniform float u_sun_k;
layout(location = 33) uniform vec4 u_sun_albedo;         // xyz replaces both colours when w > 0
layout(location = 34) uniform vec3 u_sun_radiance_omega;  // L · Ω per channel
layout(location = 35) uniform vec4 u_sun_brdf[32];       // model, parameter, scale (brdf_table)
layout(location = 67) uniform vec3 u_sun_specular[32];   // each BRDF's specular colour
#endif

// @sun_taps

// The fraction of the sun's disc the point sees, through the map.
float sun_visibility(vec3 p, vec3 n) {
    float texel = u_sun_filter.x, tan_r = u_sun_filter.y, range = u_sun_filter.z;
    vec3 q = (u_sun_to_map * vec4(p + n * texel, 1.0)).xyz;
    if (any(lessThan(q, vec3(0.0))) || any(greaterThan(q, vec3(1.0)))) return 1.0;
    // The receiver's plane in map space: depth(q.xy + o) = q.z + dot(slope, o).
    float ns = max(dot(n, u_sun_basis[2]), 0.1);
    vec2 slope = vec2(dot(n, u_sun_basis[0]), dot(n, u_sun_basis[1])) / ns;
    float bias = texel / range;
    float uv_per_world = 1.0 / range;  // the map is as wide as it is deep
    // Blockers lie between the map's near side and the receiver: search the disc the sun's
    // radius opens over that distance.
    float search = max(q.z * range * tan_r, texel) * uv_per_world;
    float sum = 0.0;
    int count = 0;
    for (int i = 0; i <= kSunBlockerTaps; ++i) {
        vec2 o = i == kSunBlockerTaps ? vec2(0.0) : search * kSunBlockerTap[i];
        float d = textureLod(u_shadow_map, q.xy + o, 0.0).r;
        if (d < q.z + dot(slope, o) - bias) {
            sum += d;
            ++count;
        }
    }
    // Nothing or everything in the way over the whole search disc, which holds the filter's
    // (Fernando's early outs): lit, or in the umbra, without the filter's taps.
    if (count == 0) return 1.0;
    if (count == kSunBlockerTaps + 1) return 0.0;
    float distance = max(q.z - sum / float(count), 0.0) * range;
    float radius = max(distance * tan_r, 0.5 * texel) * uv_per_world;
    float lit = 0.0;
    for (int i = 0; i < kSunFilterTaps; ++i) {
        vec2 o = radius * kSunFilterTap[i];
        float d = textureLod(u_shadow_map, q.xy + o, 0.0).r;
        lit += d >= q.z + dot(slope, o) - bias ? 1.0 : 0.0;
    }
    return lit / float(kSunFilterTaps);
}

#ifndef SHPRT_SUN_DIFFUSE
// The normalised lobe profile f(x) of brdf_profile (shade/glossy.cpp), x = cos θ from the axis.
float sun_lobe(vec4 b, float x) {
    if (!(x > 0.0)) return 0.0;
    int model = int(b.x);
    float e = b.y, scale = b.z;
    if (model == 0) return scale * (e + 1.0) / (2.0 * kPi) * pow(x, e);
    if (model == 1) return scale * pow(0.5 * (1.0 + x), 0.5 * e);
    float a2 = e * e * e * e, c2 = 0.5 * (1.0 + x), d = c2 * (a2 - 1.0) + 1.0;
    return scale * a2 / (kPi * d * d);
}
#endif

vec3 sun_term(vec3 p, vec3 n_in, vec3 albedo, uint brdf) {
    if (u_sun_mode == 0) return vec3(0.0);
    vec3 n = normalize(n_in);
    float c = dot(n, u_sun_basis[2]);
    if (!(c > 0.0)) return vec3(0.0);
    float V = sun_visibility(p, n);
    vec3 E = u_sun_irradiance * (c * V);
    if (u_sun_mode == 2) return E;
#ifdef SHPRT_SUN_DIFFUSE
    return albedo / kPi * E;
#else
    if (u_sun_glossy == 0) return albedo / kPi * E;
    vec3 rd = u_sun_albedo.w > 0.0 ? u_sun_albedo.xyz : albedo;
    vec3 rs = u_sun_albedo.w > 0.0 ? u_sun_albedo.xyz : u_sun_specular[brdf];
    vec3 to_eye = u_sun_eye - p;
    vec3 w = dot(to_eye, to_eye) > 0.0 ? normalize(to_eye) : n;
    vec3 r = 2.0 * dot(n, w) * n - w;
    // The lobe's mean over the disc: the centre (weight 1/4) and six points at sqrt(2/3) of its
    // radius (1/8 each), a rule exact for polynomials of degree 3 over the disc.
    vec4 b = u_sun_brdf[brdf];
    vec3 s = u_sun_basis[2];
    float f = 0.25 * sun_lobe(b, dot(r, s));
    float ring = 0.816496580927726 * u_sun_filter.y;  // sqrt(2/3) · tan(radius)
    for (int i = 0; i < 6; ++i) {
        float a = float(i) * 1.04719755119659775;
        vec3 d = normalize(s + ring * (cos(a) * u_sun_basis[0] + sin(a) * u_sun_basis[1]));
        f += 0.125 * sun_lobe(b, dot(r, d));
    }
    return u_sun_k * rd / kPi * E + (1.0 - u_sun_k) * rs * u_sun_radiance_omega * (f * V);
#endif
}
)glsl";

// `const vec2 name[n]`: tap i of n on the unit disc, evenly spread (a golden-angle spiral),
// r = sqrt((i + 1/2)/n), angle i · 2.39996…; constants, so that no fragment computes them.
std::string disc_taps(const char* name, int n) {
    std::string out = fmt::format("const vec2 {}[{}] = vec2[](", name, n);
    for (int i = 0; i < n; ++i) {
        const double r = std::sqrt((i + 0.5) / n), a = i * 2.39996322972865332;
        out +=
            fmt::format("{}vec2({:.9g}, {:.9g})", i ? ", " : "", r * std::cos(a), r * std::sin(a));
    }
    return out + ");\n";
}

}  // namespace

// The filter's taps: the blocker search's (and the receiver's own texel), the PCF's; and
// SunFilter::interactive's, half as many. Constants of the shader (a variant per filter): taps
// chosen by a uniform cost llvmpipe most of the saving (74 against 60 CPU ms a frame).
constexpr int kSunBlockerTaps = 16, kSunFilterTaps = 32;
constexpr int kSunBlockerTapsInteractive = 8, kSunFilterTapsInteractive = 16;

std::string sun_functions(SunFilter filter) {
    const bool full = filter == SunFilter::full;
    const int blocker = full ? kSunBlockerTaps : kSunBlockerTapsInteractive;
    const int pcf = full ? kSunFilterTaps : kSunFilterTapsInteractive;
    return splice(
        kSunFunctionsSource, "// @sun_taps",
        fmt::format("const int kSunBlockerTaps = {}, kSunFilterTaps = {};\n", blocker, pcf) +
            disc_taps("kSunBlockerTap", blocker) + disc_taps("kSunFilterTap", pcf));
}

namespace {

const char* const kDepthVertexShader = R"glsl(
#version 430 core
layout(location = 0) in vec3 a_position;
layout(location = 0) uniform mat4 u_light_clip;
void main() { gl_Position = u_light_clip * vec4(a_position, 1.0); }
)glsl";

const char* const kDepthFragmentShader = R"glsl(
#version 430 core
void main() {}
)glsl";

}  // namespace
}  // namespace gl

SunPass::SunPass(int size) : m_size(size) {
    m_program = gl::compile_program(gl::kDepthVertexShader, gl::kDepthFragmentShader, "sun depth");
    // Nearest, no compare mode: the filter compares depths itself (PCF over its own taps).
    m_map = gl::make_texture_2d(m_size, m_size, GL_DEPTH_COMPONENT32F);
    GLint bound = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    glGenFramebuffers(1, &m_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, m_map, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(bound));
    SHPRT_CHECK(status == GL_FRAMEBUFFER_COMPLETE, unsupported,
                "the sun's {}x{} shadow map framebuffer is incomplete (status 0x{:x})", m_size,
                m_size, status);
    gl::check("SunPass");
}

SunPass::~SunPass() {
    if (m_fbo) glDeleteFramebuffers(1, &m_fbo);
    if (m_map) glDeleteTextures(1, &m_map);
    if (m_program) glDeleteProgram(m_program);
}

bool SunPass::drawn_for(const Sun& sun, Vec3f centre, float radius, std::uint64_t geometry) const {
    return m_builds > 0 && sun.direction == m_sun.direction && sun.radius_deg == m_sun.radius_deg &&
           centre == m_centre && radius == m_radius && geometry == m_geometry;
}

void SunPass::update(const Sun& sun, Vec3f centre, float radius, std::uint64_t geometry,
                     const std::function<void()>& draw_triangles) {
    if (drawn_for(sun, centre, radius, geometry)) {
        m_sun = sun;  // its radiance does not change the map
        return;
    }
    m_sun = sun;
    m_centre = centre;
    m_radius = radius;
    m_geometry = geometry;
    // The map's axes: u and v across the sun's direction s, in double.
    const Vec3d s = normalize(sun.direction);
    const Vec3d helper = std::abs(s.y) < 0.9 ? Vec3d{0, 1, 0} : Vec3d{1, 0, 0};
    const Vec3d u = normalize(cross(helper, s)), v = cross(s, u);
    // A margin so that the sphere's own rim is inside, and never a zero-size map.
    const double R = std::max(double(radius) * 1.01, 1e-6);
    const Vec3d c = cast<double>(centre);
    // Clip space: x = u·(p − c)/R, y = v·(p − c)/R, z = −s·(p − c)/R (−1 nearest the sun).
    float clip[16] = {};
    const Vec3d rows[3] = {u / R, v / R, -s / R};
    for (int r = 0; r < 3; ++r) {
        clip[0 * 4 + r] = float(rows[r].x);
        clip[1 * 4 + r] = float(rows[r].y);
        clip[2 * 4 + r] = float(rows[r].z);
        clip[3 * 4 + r] = float(-dot(rows[r], c));
    }
    clip[15] = 1.0f;
    // The map's coordinates: (clip + 1)/2 on each axis.
    for (int col = 0; col < 4; ++col)
        for (int r = 0; r < 3; ++r)
            m_to_map[col * 4 + r] = 0.5f * clip[col * 4 + r] + (col == 3 ? 0.5f : 0.0f);
    m_to_map[15] = 1.0f;
    const Vec3d basis[3] = {u, v, s};
    for (int col = 0; col < 3; ++col) {
        m_basis[col * 3 + 0] = float(basis[col].x);
        m_basis[col * 3 + 1] = float(basis[col].y);
        m_basis[col * 3 + 2] = float(basis[col].z);
    }

    GLint bound = 0, viewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    glGetIntegerv(GL_VIEWPORT, viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glViewport(0, 0, m_size, m_size);
    glDisable(GL_CULL_FACE);  // both faces cast
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(m_program);
    glUniformMatrix4fv(0, 1, GL_FALSE, clip);
    draw_triangles();
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(bound));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    ++m_builds;
    gl::check("SunPass::update");
}

double SunPass::texel_size(float radius, int size) {
    return 2 * std::max(double(radius) * 1.01, 1e-6) / size;
}

void SunPass::bind(SunMode mode, gl::SunCode code) const {
    if (code == gl::SunCode::full) glUniform1i(gl::sun_loc::kGlossy, 0);
    const double R = std::max(double(m_radius) * 1.01, 1e-6);
    const Vec3d E = sun_irradiance(m_sun);
    glUniform1i(gl::sun_loc::kMode, static_cast<int>(mode));
    glUniformMatrix3fv(gl::sun_loc::kBasis, 1, GL_FALSE, m_basis);
    glUniform3f(gl::sun_loc::kIrradiance, float(E.x), float(E.y), float(E.z));
    glUniformMatrix4fv(gl::sun_loc::kToMap, 1, GL_FALSE, m_to_map);
    glUniform4f(gl::sun_loc::kFilter, float(texel_size(m_radius, m_size)),
                float(std::tan(m_sun.radius_deg * kPi / 180)), float(2 * R), float(m_size));
    glActiveTexture(GL_TEXTURE0 + gl::kShadowMapUnit);
    glBindTexture(GL_TEXTURE_2D, m_map);
    glActiveTexture(GL_TEXTURE0);
}

void SunPass::bind_none() { glUniform1i(gl::sun_loc::kMode, 0); }

void SunPass::bind_glossy(Vec3f eye, double k, const std::optional<Vec3f>& albedo,
                          const std::vector<Brdf>& brdfs) const {
    SHPRT_CHECK(!brdfs.empty() && brdfs.size() <= std::size_t(gl::kSunMaxBrdfs), unsupported,
                "{} distinct BRDFs under a sun kept out of the SH sum (at most {} are drawn)",
                brdfs.size(), gl::kSunMaxBrdfs);
    std::vector<float> table(4 * brdfs.size(), 0.0f), specular(3 * brdfs.size());
    for (std::size_t b = 0; b < brdfs.size(); ++b) {
        table[4 * b] = float(static_cast<int>(brdfs[b].model));
        table[4 * b + 1] = float(brdfs[b].parameter);
        // Phong's profile is normalised as written; the others by brdf_profile's scale.
        table[4 * b + 2] = float(brdf_profile(brdfs[b]).scale);
        specular[3 * b] = brdfs[b].specular.x;
        specular[3 * b + 1] = brdfs[b].specular.y;
        specular[3 * b + 2] = brdfs[b].specular.z;
    }
    const Vec3d LO = m_sun.radiance * sun_solid_angle(m_sun);
    glUniform1i(gl::sun_loc::kGlossy, 1);
    glUniform3f(gl::sun_loc::kEye, eye.x, eye.y, eye.z);
    glUniform1f(gl::sun_loc::kDiffuseShare, float(k));
    const Vec3f a = albedo.value_or(Vec3f{0, 0, 0});
    glUniform4f(gl::sun_loc::kAlbedo, a.x, a.y, a.z, albedo ? 1.0f : 0.0f);
    glUniform3f(gl::sun_loc::kRadianceOmega, float(LO.x), float(LO.y), float(LO.z));
    glUniform4fv(gl::sun_loc::kBrdfs, GLsizei(brdfs.size()), table.data());
    glUniform3fv(gl::sun_loc::kSpecular, GLsizei(brdfs.size()), specular.data());
}

}  // namespace shprt
