// GLSL 4.30 sources of the renderer. The shading compute shader is the GPU twin of
// shade_vertices (render/shade.cpp): the same formulas, in float, one invocation per vertex
// (each vertex is shaded once however many triangles share it; the draw then only transforms
// and interpolates). The glossy lobe is rotated with
// the zonal identity c_lm = g_l · y_lm(r), g_l = sqrt(4π/(2l+1)) z_l (Sloan, Kautz & Snyder
// 2002), and y_lm(r) comes from the three-term recurrence of sh/basis.hpp (sh_eval_k), ported
// line by line and fused with the two dot products so that no K-sized array is needed.
#include "gl_util.hpp"

namespace shprt::gl {

const char* const kShadeComputeShader = R"glsl(
#version 430 core
layout(local_size_x = 64) in;

// Transfer: (vertex · channels + channel) · stride_K + i. Light: channel · light_K + i.
layout(std430, binding = 0) readonly buffer TransferBuffer { float transfer[]; };
layout(std430, binding = 1) readonly buffer LightBuffer { float light[]; };
// Mesh data, tightly packed xyz floats per vertex (the vertex buffers themselves).
layout(std430, binding = 2) readonly buffer PositionBuffer { float positions[]; };
layout(std430, binding = 3) readonly buffer NormalBuffer { float normals[]; };
layout(std430, binding = 4) readonly buffer AlbedoBuffer { float albedos[]; };
// Output: linear RGB (and 1) per vertex, read by the draw as a vertex attribute.
layout(std430, binding = 5) writeonly buffer ColorBuffer { vec4 colors[]; };
// sh_eval_k's recurrence constants per (l, m ≥ 0) at flat index l(l+1)+m, computed on the host in
// double: for l = m, (the factor taking q_{m−1,m−1} to q_mm, 0); for l > m, (a_lm, b_lm) with
// q_l = a (z q_{l−1} − b q_{l−2}) (b = 0 at l = m+1). Saves a sqrt and a division per term.
layout(std430, binding = 6) readonly buffer RecurrenceBuffer { vec2 recurrence[]; };

layout(location = 0) uniform uint u_first_vertex;  // this dispatch shades u_first_vertex + id
layout(location = 1) uniform vec3 u_eye;
layout(location = 2) uniform int u_K;          // K' used (≤ stride_K, ≤ light_K)
layout(location = 3) uniform int u_stride_K;   // K stored per channel per vertex
layout(location = 4) uniform int u_channels;   // 1 or 3
layout(location = 5) uniform int u_light_K;
layout(location = 6) uniform float u_k;        // diffuse share
layout(location = 7) uniform int u_view;       // 0 radiance, 1 irradiance, 2 transfer only
layout(location = 8) uniform float u_min_cos_eta;
layout(location = 9) uniform int u_glossy;     // 1 when k < 1 and the view is radiance
layout(location = 10) uniform uint u_vertex_count;
layout(location = 16) uniform float u_lobe[64];  // g_l of the Phong lobe, l < bands

const float kPi = 3.14159265358979324;
const float kSqrt2 = 1.41421356237309505;

uint base_of(uint v, int c) {
    int channel = u_channels == 3 ? c : 0;
    return (v * uint(u_channels) + uint(channel)) * uint(u_stride_K);
}

vec3 shade(uint v);

// Transfer coefficient i of the three colours (one load when the transfer is grey).
vec3 transfer3(uint t0, uint t1, uint t2, uint i) {
    if (u_channels == 1) return vec3(transfer[t0 + i]);
    return vec3(transfer[t0 + i], transfer[t1 + i], transfer[t2 + i]);
}

void main() {
    uint v = u_first_vertex + gl_GlobalInvocationID.x;
    if (v >= u_vertex_count) return;
    colors[v] = vec4(shade(v), 1.0);
}

vec3 shade(uint v) {
    vec3 a_position = vec3(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]);
    vec3 a_normal = vec3(normals[3u * v], normals[3u * v + 1u], normals[3u * v + 2u]);
    vec3 a_albedo = vec3(albedos[3u * v], albedos[3u * v + 1u], albedos[3u * v + 2u]);
    uint t0 = base_of(v, 0), t1 = base_of(v, 1), t2 = base_of(v, 2);
    int l1 = u_light_K, l2 = 2 * u_light_K;

    if (u_view == 2) {
        // E under a uniform sky of radiance 1 (c_0 = sqrt(4π)), over π: T_0 · 2/sqrt(π).
        return vec3(transfer[t0] * 1.12837916709551257);
    }

    vec3 E = vec3(0.0);
    for (int i = 0; i < u_K; ++i) {
        E += transfer3(t0, t1, t2, uint(i)) * vec3(light[i], light[l1 + i], light[l2 + i]);
    }
    if (u_view == 1) return E;
    vec3 L = a_albedo / kPi * E;
    if (u_glossy != 0) {
        vec3 n = normalize(a_normal);
        vec3 to_eye = u_eye - a_position;
        vec3 w = dot(to_eye, to_eye) > 0.0 ? normalize(to_eye) : n;
        float nw = dot(n, w);
        vec3 r = 2.0 * nw * n - w;
        float cos_eta = max(nw, u_min_cos_eta);

        int bands = 0;
        while (bands * bands < u_K) ++bands;
        vec3 lobe_light = vec3(0.0), lobe_transfer = vec3(0.0);
        // sh_eval_k: q_mm = K_m^m P_m^m / sin^m θ; (c_m + i s_m) = (x + iy)^m.
        float q_mm = 0.282094791773878143;  // sqrt(1/(4π))
        float c_m = 1.0, s_m = 0.0;
        for (int m = 0; m < bands; ++m) {
            if (m > 0) {
                q_mm *= recurrence[m * (m + 2)].x;  // −sqrt((2m+1)/(2m)), at index (m, m)
                float c = c_m * r.x - s_m * r.y;
                s_m = c_m * r.y + s_m * r.x;
                c_m = c;
            }
            float wc = m == 0 ? 1.0 : kSqrt2 * c_m;
            float ws = kSqrt2 * s_m;
            float q_prev = 0.0, q = q_mm;
            for (int l = m; l < bands; ++l) {
                int ip = l * (l + 1) + m;
                if (l > m) {
                    vec2 ab = recurrence[ip];
                    float next = ab.x * (r.z * q - ab.y * q_prev);
                    q_prev = q;
                    q = next;
                }
                if (ip < u_K) {
                    float cs = u_lobe[l] * q * wc;
                    lobe_light += cs * vec3(light[ip], light[l1 + ip], light[l2 + ip]);
                    lobe_transfer += cs * transfer3(t0, t1, t2, uint(ip));
                }
                if (m > 0) {
                    int im = l * (l + 1) - m;
                    if (im < u_K) {
                        float cs = u_lobe[l] * q * ws;
                        lobe_light += cs * vec3(light[im], light[l1 + im], light[l2 + im]);
                        lobe_transfer += cs * transfer3(t0, t1, t2, uint(im));
                    }
                }
            }
        }
        vec3 L_S = lobe_light * lobe_transfer / cos_eta;
        L = u_k * L + (1.0 - u_k) * L_S;
    }
    return L;
}
)glsl";

const char* const kSceneVertexShader = R"glsl(
#version 430 core
layout(location = 0) in vec3 a_position;
layout(location = 3) in vec4 a_color;  // from the shading pass
layout(location = 0) uniform mat4 u_view_proj;
out vec3 v_color;
void main() {
    gl_Position = u_view_proj * vec4(a_position, 1.0);
    v_color = a_color.rgb;
}
)glsl";

const char* const kSceneFragmentShader = R"glsl(
#version 430 core
in vec3 v_color;
layout(location = 0) out vec4 frag_color;
void main() { frag_color = vec4(v_color, 1.0); }
)glsl";

const char* const kFullscreenVertexShader = R"glsl(
#version 430 core
out vec2 v_ndc;
void main() {
    // One triangle that covers the viewport: (−1,−1), (3,−1), (−1,3).
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    v_ndc = p;
    gl_Position = vec4(p, 1.0, 1.0);
}
)glsl";

const char* const kBackgroundFragmentShader = R"glsl(
#version 430 core
in vec2 v_ndc;
layout(location = 0) uniform mat4 u_inv_view_proj;
layout(location = 1) uniform vec3 u_eye;
layout(binding = 0) uniform sampler2D u_env;  // equirect, row 0 (v = 0) = zenith at t = 0
layout(location = 0) out vec4 frag_color;
const float kPi = 3.14159265358979324;
void main() {
    vec4 p = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 d = normalize(p.xyz / p.w - u_eye);
    // light/equirect.hpp: u = 0.5 + atan2(d.x, −d.z)/(2π), v = acos(d.y)/π.
    float u = 0.5 + atan(d.x, -d.z) / (2.0 * kPi);
    float v = acos(clamp(d.y, -1.0, 1.0)) / kPi;
    frag_color = vec4(texture(u_env, vec2(u, v)).rgb, 1.0);
}
)glsl";

const char* const kPresentFragmentShader = R"glsl(
#version 430 core
layout(location = 0) uniform float u_exposure;
layout(location = 1) uniform vec2 u_size;  // viewport size in pixels
layout(binding = 0) uniform sampler2D u_image;  // linear radiance
layout(location = 0) out vec4 frag_color;
// light/tonemap.hpp: Narkowicz's ACES fit, then the exact sRGB curve.
float tonemap_aces(float x) {
    if (!(x > 0.0)) return 0.0;
    return min((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 1.0);
}
float linear_to_srgb(float x) {
    if (!(x > 0.0)) return 0.0;
    if (x >= 1.0) return 1.0;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
    vec3 c = texture(u_image, gl_FragCoord.xy / u_size).rgb * u_exposure;
    frag_color = vec4(linear_to_srgb(tonemap_aces(c.r)), linear_to_srgb(tonemap_aces(c.g)),
                      linear_to_srgb(tonemap_aces(c.b)), 1.0);
}
)glsl";

}  // namespace shprt::gl
