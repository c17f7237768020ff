// GLSL 4.30 sources of the texel pass (texel_pass.hpp): the per-fragment twin of shade_texels
// (shade/texel_shade.hpp) — E = Σ_i T_i L_i with T read from the coefficient planes at the
// fragment's UV (bilinear inside a chart) instead of interpolated from vertices.
#include "texel_pass.hpp"

namespace shprt::gl {

const char* const kTexelVertexShader = R"glsl(
#version 430 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec2 a_uv;
layout(location = 2) in vec3 a_albedo;
layout(location = 3) in vec3 a_normal;
layout(location = 0) uniform mat4 u_view_proj;
out vec2 v_uv;
out vec3 v_albedo;
out vec3 v_position;
out vec3 v_normal;
void main() {
    gl_Position = u_view_proj * vec4(a_position, 1.0);
    v_uv = a_uv;
    v_albedo = a_albedo;
    v_position = a_position;
    v_normal = a_normal;
}
)glsl";

const char* const kTexelFragmentShader = R"glsl(
#version 430 core
in vec2 v_uv;
in vec3 v_albedo;
in vec3 v_position;
in vec3 v_normal;
// The Renderer's light block (gl_shaders.cpp): channel c's coefficient i at c · u_light_stride
// + i, u_light_stride a multiple of 4.
layout(std140, binding = 0) uniform LightBlock { vec4 light4[768]; };
// Layer c · u_layers + j holds coefficients 4j … 4j+3 of channel c (zero past the stored K).
layout(binding = 0) uniform sampler2DArray u_planes;
layout(location = 1) uniform int u_K;       // K' used (≤ stored K, ≤ light K)
layout(location = 2) uniform int u_channels;  // 1 or 3
layout(location = 3) uniform int u_layers;  // layers per channel: ⌈stored K / 4⌉
layout(location = 4) uniform int u_light_stride;
layout(location = 5) uniform int u_view;    // 0 radiance, 1 irradiance, 2 transfer only
layout(location = 0) out vec4 frag_color;
const float kPi = 3.14159265358979324;
// @output
// @sun

vec4 plane(int layer, vec2 st) { return textureLod(u_planes, vec3(st, float(layer)), 0.0); }

void main() {
    // Texel (x, y), row 0 at the top, has its centre at u = (x + ½)/W, v = 1 − (y + ½)/H and is
    // GL texel (x, y): t = 1 − v.
    vec2 st = vec2(v_uv.x, 1.0 - v_uv.y);
    if (u_view == 2) {
        // E under a uniform sky of radiance 1 (c_0 = sqrt(4π)), over π: T_0 · 2/sqrt(π).
        frag_color = output_colour(vec3(plane(0, st).x * 1.12837916709551257));
        return;
    }
    int s = u_light_stride >> 2;
    vec3 E = vec3(0.0);
    for (int j = 0; 4 * j < u_K; ++j) {
        // The last group may hold coefficients past K': mask them out of the light.
        vec4 mask = vec4(lessThan(vec4(4 * j) + vec4(0.0, 1.0, 2.0, 3.0), vec4(float(u_K))));
        vec4 r = light4[j] * mask, g = light4[s + j] * mask, b = light4[2 * s + j] * mask;
        vec4 t = plane(j, st);
        if (u_channels == 1)
            E += vec3(dot(t, r), dot(t, g), dot(t, b));
        else
            E += vec3(dot(t, r), dot(plane(u_layers + j, st), g),
                      dot(plane(2 * u_layers + j, st), b));
    }
    frag_color = output_colour((u_view == 1 ? E : v_albedo / kPi * E) +
                               sun_term(v_position, v_normal, v_albedo, 0u));
}
)glsl";

const char* const kTexelColourFragmentShader = R"glsl(
#version 430 core
in vec2 v_uv;
in vec3 v_albedo;
// One colour per receiver (texel), as the Renderer's glossy vertex pass writes them.
layout(std430, binding = 5) readonly buffer ColorBuffer { vec4 colors[]; };
// Texel (x, y) (row 0 at the top) is GL texel (x, y): its receiver, or −1 (dilate_texels).
layout(binding = 1) uniform isampler2D u_receiver;
layout(location = 0) out vec4 frag_color;
// @output

vec3 texel_colour(ivec2 p, ivec2 size) {
    int r = texelFetch(u_receiver, clamp(p, ivec2(0), size - 1), 0).x;
    return r >= 0 ? colors[r].rgb : vec3(0.0);
}

void main() {
    // The bilinear filter of the four texels around the fragment's UV (texel centres at
    // ((x + ½)/W, 1 − (y + ½)/H)), as the planes are filtered for vector transfer.
    ivec2 size = textureSize(u_receiver, 0);
    vec2 f = vec2(v_uv.x, 1.0 - v_uv.y) * vec2(size) - 0.5;
    ivec2 p = ivec2(floor(f));
    vec2 a = f - vec2(p);
    vec3 top = mix(texel_colour(p, size), texel_colour(p + ivec2(1, 0), size), a.x);
    vec3 bottom = mix(texel_colour(p + ivec2(0, 1), size), texel_colour(p + ivec2(1, 1), size), a.x);
    frag_color = output_colour(mix(top, bottom, a.y));
}
)glsl";

}  // namespace shprt::gl
