// GLSL 4.30 sources of the renderer. The shading compute shader is the GPU twin of
// shade_vertices (shade/shade.cpp): the same formulas, in float, one invocation per vertex
// (each vertex is shaded once however many triangles share it; the draw then only transforms
// and interpolates). The glossy lobe is rotated with
// the zonal identity c_lm = g_l · y_lm(r), g_l = sqrt(4π/(2l+1)) z_l (Sloan, Kautz & Snyder
// 2002), and y_lm(r) comes from the three-term recurrence of sh/basis.hpp (sh_eval_k), ported
// line by line and fused with the two dot products so that no K-sized array is needed.
#include "gl_util.hpp"
#include "sun_pass.hpp"

#include <string>

namespace shprt::gl {

const char* const kShadeComputeShader = R"glsl(
#version 430 core
layout(local_size_x = 64) in;

// Transfer: (vertex · channels + channel) · stride_K + i; read four coefficients at a time
// through the second view of the same buffer when stride_K is a multiple of 4.
layout(std430, binding = 0) readonly buffer TransferBuffer { float transfer[]; };
layout(std430, binding = 0) readonly buffer TransferBuffer4 { vec4 transfer4[]; };
// Mesh data, tightly packed xyz floats per vertex (the vertex buffers themselves).
layout(std430, binding = 2) readonly buffer PositionBuffer { float positions[]; };
layout(std430, binding = 3) readonly buffer NormalBuffer { float normals[]; };
layout(std430, binding = 4) readonly buffer AlbedoBuffer { float albedos[]; };
// Output: linear RGB (and 1) per vertex, read by the draw as a vertex attribute.
layout(std430, binding = 5) writeonly buffer ColorBuffer { vec4 colors[]; };
// Data every invocation reads at the same address lives in uniform blocks: one load per group
// instead of one per invocation (on llvmpipe a storage-buffer load is a loop over the lanes).
// Light: channel c's coefficient i at c · u_light_stride + i, u_light_stride = K rounded up to a
// multiple of 4 (zero padding), so that each channel starts on a vec4. 768 = 3 · kMaxLightK / 4.
layout(std140, binding = 0) uniform LightBlock { vec4 light4[768]; };
// sh_eval_k's recurrence constants per (l, m ≥ 0) at flat index l(l+1)+m, two floats each (two
// entries per vec4), computed on the host in double: for l = m, (the factor taking q_{m−1,m−1} to
// q_mm, 0); for l > m, (a_lm, b_lm) with q_l = a (z q_{l−1} − b q_{l−2}) (b = 0 at l = m+1).
// Saves a sqrt and a division per term. 512 = kMaxLightK / 2.
layout(std140, binding = 1) uniform RecurrenceBlock { vec4 recurrence4[512]; };

layout(location = 0) uniform uint u_first_vertex;  // this dispatch shades u_first_vertex + id
layout(location = 1) uniform vec3 u_eye;
layout(location = 2) uniform int u_K;          // K' used (≤ stride_K, ≤ light_K)
layout(location = 3) uniform int u_stride_K;   // K stored per channel per vertex
layout(location = 4) uniform int u_channels;   // 1 or 3
layout(location = 5) uniform int u_light_stride;  // K of the light rounded up to 4
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

vec3 light3(int i) {
    int g = u_light_stride + i, b = 2 * u_light_stride + i;
    return vec3(light4[i >> 2][i & 3], light4[g >> 2][g & 3], light4[b >> 2][b & 3]);
}

vec2 recurrence(int i) {
    vec4 pair = recurrence4[i >> 1];
    return (i & 1) == 0 ? pair.xy : pair.zw;
}

// Transfer coefficient i of the three colours (one load when the transfer is grey).
vec3 transfer3(uint t0, uint t1, uint t2, uint i) {
    if (u_channels == 1) return vec3(transfer[t0 + i]);
    return vec3(transfer[t0 + i], transfer[t1 + i], transfer[t2 + i]);
}

// One index i of the glossy loop: E gets T_i L_i, and the lobe sums get the rotated lobe's
// coefficient c_i times L_i and T_i.
void term(uint t0, uint t1, uint t2, int i, float c_i, inout vec3 E, inout vec3 lobe_light,
          inout vec3 lobe_transfer) {
    vec3 t = transfer3(t0, t1, t2, uint(i)), lt = light3(i);
    E += t * lt;
    lobe_light += c_i * lt;
    lobe_transfer += c_i * t;
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

    if (u_view == 2) {
        // E under a uniform sky of radiance 1 (c_0 = sqrt(4π)), over π: T_0 · 2/sqrt(π).
        return vec3(transfer[t0] * 1.12837916709551257);
    }

    // E = Σ T_i L_i. The glossy term visits every index once too (in (m, l) order), so it
    // accumulates E on the way instead of reading the transfer twice.
    vec3 E = vec3(0.0);
    if (u_glossy == 0) {
        int i = 0;
        if ((u_stride_K & 3) == 0) {
            uint q0 = t0 >> 2, q1 = t1 >> 2, q2 = t2 >> 2;
            int s = u_light_stride >> 2;
            for (; i + 4 <= u_K; i += 4) {
                int j = i >> 2;
                vec4 r = light4[j], g = light4[s + j], b = light4[2 * s + j];
                if (u_channels == 1) {
                    vec4 t = transfer4[q0 + uint(j)];
                    E += vec3(dot(t, r), dot(t, g), dot(t, b));
                } else {
                    E += vec3(dot(transfer4[q0 + uint(j)], r), dot(transfer4[q1 + uint(j)], g),
                              dot(transfer4[q2 + uint(j)], b));
                }
            }
        }
        for (; i < u_K; ++i) E += transfer3(t0, t1, t2, uint(i)) * light3(i);
        if (u_view == 1) return E;
        return a_albedo / kPi * E;
    }

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
            q_mm *= recurrence(m * (m + 2)).x;  // −sqrt((2m+1)/(2m)), at index (m, m)
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
                vec2 ab = recurrence(ip);
                float next = ab.x * (r.z * q - ab.y * q_prev);
                q_prev = q;
                q = next;
            }
            if (ip < u_K) term(t0, t1, t2, ip, u_lobe[l] * q * wc, E, lobe_light, lobe_transfer);
            int im = l * (l + 1) - m;
            if (m > 0 && im < u_K)
                term(t0, t1, t2, im, u_lobe[l] * q * ws, E, lobe_light, lobe_transfer);
        }
    }
    vec3 L_D = a_albedo / kPi * E;
    vec3 L_S = lobe_light * lobe_transfer / cos_eta;
    return u_k * L_D + (1.0 - u_k) * L_S;
}
)glsl";

const char* const kSceneVertexShader = R"glsl(
#version 430 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_albedo;
layout(location = 3) in vec4 a_color;  // from the shading pass
// From the sun's pass: T_0 · c_sun, the sun's direct light through SH, which the colours of
// T · (c_sky + c_sun) hold and the shadow-mapped sun replaces (0 when there is none).
layout(location = 4) in vec4 a_sun_sh;
layout(location = 5) in uint a_brdf;  // glossy matrices with material BRDFs: the table entry
layout(location = 0) uniform mat4 u_view_proj;
out vec3 v_color;
out vec3 v_position;
out vec3 v_normal;
out vec3 v_albedo;
flat out uint v_brdf;
void main() {
    v_brdf = a_brdf;
    gl_Position = u_view_proj * vec4(a_position, 1.0);
    v_color = a_color.rgb - a_sun_sh.rgb;
    v_position = a_position;
    v_normal = a_normal;
    v_albedo = a_albedo;
}
)glsl";

const char* const kSceneFragmentShader = R"glsl(
#version 430 core
in vec3 v_color;
in vec3 v_position;
in vec3 v_normal;
in vec3 v_albedo;
flat in uint v_brdf;
layout(location = 0) out vec4 frag_color;
const float kPi = 3.14159265358979324;
// @output
// @sun
void main() {
    frag_color = output_colour(v_color + sun_term(v_position, v_normal, v_albedo, v_brdf));
}
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
layout(location = 2) uniform mat3 u_to_texture;  // R^T of the light's rotation R (or identity)
layout(binding = 0) uniform sampler2D u_env;  // equirect, row 0 (v = 0) = zenith at t = 0
layout(location = 0) out vec4 frag_color;
const float kPi = 3.14159265358979324;
// @output
void main() {
    vec4 p = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 d = u_to_texture * normalize(p.xyz / p.w - u_eye);
    // light/equirect.hpp: u = 0.5 + atan2(d.x, −d.z)/(2π), v = acos(d.y)/π.
    float u = 0.5 + atan(d.x, -d.z) / (2.0 * kPi);
    float v = acos(clamp(d.y, -1.0, 1.0)) / kPi;
    frag_color = output_colour(texture(u_env, vec2(u, v)).rgb);
}
)glsl";

namespace {

const char* const kPresentFragmentShader = R"glsl(
#version 430 core
layout(location = 0) uniform float u_exposure;
layout(location = 1) uniform int u_samples;  // 1: read u_image; > 1: average u_image_ms
layout(binding = 0) uniform sampler2D u_image;  // linear radiance, one sample per pixel
layout(binding = 1) uniform sampler2DMS u_image_ms;  // linear radiance, u_samples per pixel
layout(location = 0) out vec4 frag_color;
// @display_encode
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 c;
    if (u_samples == 1) {
        c = texelFetch(u_image, p, 0).rgb;
    } else {
        // The multisample resolve, fused: the mean of the samples, as glBlitFramebuffer takes.
        c = vec3(0.0);
        for (int i = 0; i < u_samples; ++i) c += texelFetch(u_image_ms, p, i).rgb;
        c /= float(u_samples);
    }
    frag_color = display_encode(c * u_exposure);
}
)glsl";

// shade/tonemap.hpp and core/colour.hpp: Narkowicz's ACES fit, then the exact sRGB curve; the
// display code of linear radiance already scaled by the exposure. The one GLSL copy: the present
// pass and every fragment shader drawn straight to a display splice it in.
const char* const kDisplayEncode = R"glsl(
float tonemap_aces(float x) {
    if (!(x > 0.0)) return 0.0;
    return min((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 1.0);
}
float linear_to_srgb(float x) {
    if (!(x > 0.0)) return 0.0;
    if (x >= 1.0) return 1.0;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
vec4 display_encode(vec3 c) {
    return vec4(linear_to_srgb(tonemap_aces(c.r)), linear_to_srgb(tonemap_aces(c.g)),
                linear_to_srgb(tonemap_aces(c.b)), 1.0);
}
)glsl";

}  // namespace

std::string splice(const std::string& source, const char* marker, const std::string& code) {
    const std::size_t at = source.find(marker);
    return source.substr(0, at) + code + source.substr(source.find('\n', at) + 1);
}

std::string present_shader() {
    return splice(kPresentFragmentShader, "// @display_encode", kDisplayEncode);
}

std::string fragment_shader(const char* source, bool display, SunCode sun, SunFilter filter) {
    const std::string output =
        display
            ? std::string(kDisplayEncode) +
                  "layout(location = " + std::to_string(loc::kDisplayExposure) +
                  ") uniform float u_display_exposure;\n"
                  "vec4 output_colour(vec3 c) { return display_encode(c * u_display_exposure); }\n"
            : std::string("vec4 output_colour(vec3 c) { return vec4(c, 1.0); }\n");
    const std::string with_output = splice(source, "// @output", output);
    if (with_output.find("// @sun") == std::string::npos) return with_output;
    switch (sun) {
        case SunCode::none:
            return splice(
                with_output, "// @sun",
                "vec3 sun_term(vec3 p, vec3 n, vec3 albedo, uint brdf) { return vec3(0.0); "
                "}\n");
        case SunCode::diffuse:
            return splice(with_output, "// @sun",
                          "#define SHPRT_SUN_DIFFUSE 1\n" + sun_functions(filter));
        case SunCode::full:
            break;
    }
    return splice(with_output, "// @sun", sun_functions(filter));
}

}  // namespace shprt::gl
