// GLSL 4.30 sources of the renderer's glossy matrix shading: the GPU twin of shade_glossy
// (shade/glossy.hpp), in float. Two compute passes:
//
//   cluster pass   (CPCA files only) one invocation per cluster mean and basis matrix: its
//                  product with the light, B·L_c for the three colours. Runs when the light or
//                  K' changes (Sloan, Hall, Hart & Snyder 2003: the light is transformed once
//                  per cluster, not per vertex).
//   vertex pass    one invocation per vertex: T_c = M_v·L_c (raw matrices), or
//                  T_c = mean·L_c + Σ_i w_i (B_i·L_c) from the cluster pass (CPCA); then
//                  E = ⟨a(n), T⟩ and the lobe term ⟨g(r), T⟩ with both zonal lobes rotated by
//                  the recurrence of sh/basis.hpp (as kShadeComputeShader does), and
//                  L = k·ρ_d/π·E + (1−k)·ρ_s·⟨g(r), T⟩. Runs when the eye moves (glossy
//                  shading depends on it), the light turns, or a setting changes.
//
// Both passes share the packed-matrix product below (the upper triangle of a symmetric K×K
// matrix, row by row, as the file stores it), so a matrix is read once per product.
//
// K' (KP) and the CPCA code's vector count (NV; 0 = raw matrices) are compile-time constants: a
// program is compiled per (K', N) the first time it is drawn with. With constant trip counts the
// compiler unrolls the coefficient loops, and T[] lives in registers instead of memory indexed
// per lane.
#include "gl_util.hpp"

#include <string>

namespace shprt::gl {
namespace {

// What both passes declare: the light, the matrices, the settings they share, and the product.
const char* const kGlossyCommon = R"glsl(
layout(local_size_x = 64) in;

// Packed symmetric matrices, K(K+1)/2 floats each: per vertex (raw matrices) or, for CPCA,
// per cluster its mean then its basis matrices.
layout(std430, binding = 0) readonly buffer MatrixBuffer { float matrices[]; };
// The light as kShadeComputeShader reads it: channel c's coefficient i at c·u_light_stride + i.
layout(std140, binding = 0) uniform LightBlock { vec4 light4[768]; };

layout(location = 5) uniform int u_light_stride;  // K of the light rounded up to 4
layout(location = 7) uniform int u_view;          // 0 radiance, 1 irradiance, 2 transfer only

const float kPi = 3.14159265358979324;
const float kSqrt4Pi = 3.54490770181103205;

// The shadowed incident radiance of the three colours, K' coefficients (8 bands at most).
vec3 T[64];

// The light's coefficient i; the transfer-only view shades under a white sky of radiance 1.
vec3 light3(int i) {
    if (u_view == 2) return vec3(i == 0 ? kSqrt4Pi : 0.0);
    int g = u_light_stride + i, b = 2 * u_light_stride + i;
    return vec3(light4[i >> 2][i & 3], light4[g >> 2][g & 3], light4[b >> 2][b & 3]);
}

// @transform_light (generated for K' and the stored K: transform_light_source)
)glsl";

const char* const kClusterMain = R"glsl(
// Output: per product p (cluster c, matrix b: p = c·(1 + N) + b), T of the three colours:
// coefficient i at cluster_light[c·u_cluster_stride + b·K' + i].rgb (u_cluster_stride ≥ (1 + N)·K'
// vec4s, so that each cluster starts where a uniform block may be bound).
layout(std430, binding = 1) writeonly buffer ClusterLightBuffer { vec4 cluster_light[]; };
layout(location = 11) uniform uint u_cluster_stride;
layout(location = 10) uniform uint u_count;  // clusters × (1 + N)

void main() {
    uint p = gl_GlobalInvocationID.x;
    if (p >= u_count) return;
    transform_light(p * uint(KD));
    uint c = p / uint(1 + NV), b = p % uint(1 + NV);
    uint at = c * u_cluster_stride + b * uint(KP);
    for (int i = 0; i < KP; ++i) cluster_light[at + uint(i)] = vec4(T[i], 0.0);
}
)glsl";

const char* const kVertexMain = R"glsl(
layout(std430, binding = 1) readonly buffer ClusterLightBuffer { vec4 cluster_light[]; };
layout(std430, binding = 2) readonly buffer PositionBuffer { float positions[]; };
layout(std430, binding = 3) readonly buffer NormalBuffer { float normals[]; };
layout(std430, binding = 4) readonly buffer AlbedoBuffer { float albedos[]; };
layout(std430, binding = 5) writeonly buffer ColorBuffer { vec4 colors[]; };
// CPCA: the vertices of cluster c are cluster_vertices[cluster_start[c] .. cluster_start[c + 1]).
layout(std430, binding = 6) readonly buffer ClusterBuffer { uint cluster_start[]; };
layout(std430, binding = 8) readonly buffer ClusterVertexBuffer { uint cluster_vertices[]; };
layout(std430, binding = 7) readonly buffer WeightBuffer { float weights[]; };
// sh_eval_k's recurrence constants, as kShadeComputeShader reads them.
layout(std140, binding = 1) uniform RecurrenceBlock { vec4 recurrence4[512]; };

layout(location = 0) uniform uint u_first;  // first vertex (raw), or first cluster (CPCA)
layout(location = 11) uniform uint u_cluster_stride;
layout(location = 1) uniform vec3 u_eye;
layout(location = 6) uniform float u_k;           // diffuse share
layout(location = 10) uniform uint u_vertex_count;
layout(location = 12) uniform vec4 u_albedo;      // w = 1: xyz replaces both colours
layout(location = 16) uniform float u_lobe[8];    // g_l of the BRDF's zonal lobe
layout(location = 13) uniform vec3 u_specular;    // the BRDF's specular colour
#if MATERIALS
// Per-material BRDFs: vertex v's BRDF is lobe4[3·brdf_index[v] ..]: 8 band factors, then the
// specular colour.
layout(std430, binding = 9) readonly buffer BrdfIndexBuffer { uint brdf_index[]; };
layout(std140, binding = 3) uniform LobeBlock { vec4 lobe4[LOBE_BLOCK_VEC4S]; };
uint g_lobe_base;
#define LOBE(l) lobe4[g_lobe_base + uint((l) >> 2)][(l) & 3]
#define SPECULAR lobe4[g_lobe_base + 2u].xyz
#else
#define LOBE(l) u_lobe[l]
#define SPECULAR u_specular
#endif
layout(location = 24) uniform float u_cosine[8];  // g_l of the clamped cosine

const float kSqrt2 = 1.41421356237309505;

vec2 recurrence(int i) {
    vec4 pair = recurrence4[i >> 1];
    return (i & 1) == 0 ? pair.xy : pair.zw;
}

// @zonal_dot (generated for K': zonal_dot_source)

// CPCA: the work group's cluster's products (mean·L, then B_i·L). Read through a uniform block
// bound to this dispatch's clusters when they fit one (CL_BLOCK_VEC4S > 0): every invocation of
// a group reads the same addresses, and llvmpipe then loads once per group where a storage
// buffer load is a loop over the lanes (the room's CPCA 256×8: the vertex pass took ~17 instead
// of ~30 ms of CPU per frame on llvmpipe, bench/RESULTS.md "Glossy in the viewer").
#if CL_BLOCK_VEC4S > 0
layout(std140, binding = 2) uniform ClusterLightBlock { vec4 cl_block[CL_BLOCK_VEC4S]; };
#define CLUSTER_LIGHT(i) cl_block[i]
#else
#define CLUSTER_LIGHT(i) cluster_light[i]
#endif
uint g_cluster_base;  // this group's cluster's first product in CLUSTER_LIGHT

void shade_vertex(uint v) {
    if (NV == 0) {
        transform_light(v * uint(KD));
    } else {
        for (int i = 0; i < KP; ++i) T[i] = CLUSTER_LIGHT(g_cluster_base + uint(i)).rgb;
        for (int b = 1; b <= NV; ++b) {
            float w = weights[v * uint(NV) + uint(b - 1)];
            uint at = g_cluster_base + uint(b * KP);
            for (int i = 0; i < KP; ++i) T[i] += w * CLUSTER_LIGHT(at + uint(i)).rgb;
        }
    }
    vec3 p = vec3(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]);
    vec3 n = normalize(vec3(normals[3u * v], normals[3u * v + 1u], normals[3u * v + 2u]));
    vec3 E = zonal_dot(n, true);
    vec3 colour;
    if (u_view == 2) {
        colour = vec3(E.x / kPi);
    } else if (u_view == 1) {
        colour = E;
    } else {
        vec3 albedo = vec3(albedos[3u * v], albedos[3u * v + 1u], albedos[3u * v + 2u]);
        bool override_albedo = u_albedo.w > 0.5;
        colour = u_k * (override_albedo ? u_albedo.xyz : albedo) / kPi * E;
        if (u_k < 1.0) {  // the lobe term: the only part that depends on the eye
            vec3 to_eye = u_eye - p;
            vec3 w = dot(to_eye, to_eye) > 0.0 ? normalize(to_eye) : n;
            vec3 r = 2.0 * dot(n, w) * n - w;
#if MATERIALS
            g_lobe_base = uint(LOBE_VEC4S_PER_BRDF) * brdf_index[v];
#endif
            colour += (1.0 - u_k) * (override_albedo ? u_albedo.xyz : SPECULAR) *
                      zonal_dot(r, false);
        }
    }
    colors[v] = vec4(colour, 1.0);
}

// Raw matrices: one invocation per vertex. CPCA: one work group per cluster, its invocations
// striding over the cluster's vertices.
void main() {
    if (NV == 0) {
        uint v = u_first + gl_GlobalInvocationID.x;
        if (v < u_vertex_count) shade_vertex(v);
        return;
    }
    uint c = u_first + gl_WorkGroupID.x;
#if CL_BLOCK_VEC4S > 0
    g_cluster_base = gl_WorkGroupID.x * u_cluster_stride;  // the block starts at u_first
#else
    g_cluster_base = c * u_cluster_stride;
#endif
    for (uint i = cluster_start[c] + gl_LocalInvocationID.x; i < cluster_start[c + 1u];
         i += gl_WorkGroupSize.x)
        shade_vertex(cluster_vertices[i]);
}
)glsl";

// ⟨lobe rotated to `axis`, T⟩ = Σ_lm g_l y_lm(axis) T_lm over the first K' indices, y_lm from
// sh_eval_k's recurrence (q_mm = K_m^m P_m^m / sin^m θ, (c_m + i s_m) = (x + iy)^m; constants from
// the recurrence block), written out straight for this K': every T index is a constant, so T
// stays in registers (a loop over (m, l ≥ m) is not unrolled by the compiler, and T indexed per
// lane lives in memory: the room's CPCA vertex pass took ~2.5× longer so on llvmpipe).
std::string zonal_dot_source(int K) {
    int bands = 0;
    while (bands * bands < K) ++bands;
    std::string src =
        "vec3 zonal_dot(vec3 a, bool cosine) {\n"
        "    vec3 sum = vec3(0.0);\n"
        "    float q_mm = 0.282094791773878143, c_m = 1.0, s_m = 0.0, c, wc, ws, q_prev, q, "
        "next;\n";
    for (int m = 0; m < bands; ++m) {
        if (m > 0)
            src += "    q_mm *= recurrence(" + std::to_string(m * (m + 2)) +
                   ").x; c = c_m * a.x - s_m * a.y; s_m = c_m * a.y + s_m * a.x; c_m = c;\n"
                   "    wc = kSqrt2 * c_m; ws = kSqrt2 * s_m;\n";
        else
            src += "    wc = 1.0; ws = 0.0;\n";
        src += "    q_prev = 0.0; q = q_mm;\n";
        for (int l = m; l < bands; ++l) {
            const int ip = l * (l + 1) + m, im = l * (l + 1) - m;
            const std::string i = std::to_string(ip);
            if (l > m)
                src += "    next = recurrence(" + i + ").x * (a.z * q - recurrence(" + i +
                       ").y * q_prev); q_prev = q; q = next;\n";
            const std::string g = "(cosine ? u_cosine[" + std::to_string(l) + "] : LOBE(" +
                                  std::to_string(l) + ")) * q";
            if (ip < K) src += "    sum += " + g + " * wc * T[" + i + "];\n";
            if (m > 0 && im < K)
                src += "    sum += " + g + " * ws * T[" + std::to_string(im) + "];\n";
        }
    }
    return src + "    return sum;\n}\n";
}

// T = M·L for the packed matrix (K_stored wide) at matrices[base]: each stored entry M_ij
// (j ≥ i, i and j < K') adds to T_i and, off the diagonal, to T_j. Written out straight, as
// zonal_dot_source, so that T stays in registers.
std::string transform_light_source(int K, int K_stored) {
    std::string src = "void transform_light(uint base) {\n    float m;\n";
    for (int i = 0; i < K; ++i) {
        const std::string n = std::to_string(i);
        src += "    vec3 l" + n + " = light3(" + n + ");\n    T[" + n + "] = vec3(0.0);\n";
    }
    int row = 0;  // packed index of (i, i)
    for (int i = 0; i < K; ++i) {
        for (int j = i; j < K; ++j) {
            const std::string si = std::to_string(i), sj = std::to_string(j);
            src += "    m = matrices[base + " + std::to_string(row + j - i) + "u]; T[" + si +
                   "] += m * l" + sj + ";";
            if (j > i) src += " T[" + sj + "] += m * l" + si + ";";
            src += "\n";
        }
        row += K_stored - i;
    }
    return src + "}\n";
}

std::string glossy_header(int K, int K_stored, int vectors, int block_vec4s, bool materials) {
    int bands = 0;
    while (bands * bands < K) ++bands;
    return "#version 430 core\n#define KP " + std::to_string(K) + "\n#define KD " +
           std::to_string(K_stored * (K_stored + 1) / 2) + "\n#define KB " + std::to_string(bands) +
           "\n#define NV " + std::to_string(vectors) + "\n#define CL_BLOCK_VEC4S " +
           std::to_string(block_vec4s) + "\n#define MATERIALS " + (materials ? "1" : "0") +
           "\n#define LOBE_BLOCK_VEC4S " + std::to_string(kLobeBlockVec4s) +
           "\n#define LOBE_VEC4S_PER_BRDF " + std::to_string(kLobeVec4sPerBrdf) + "\n";
}

}  // namespace

std::string glossy_cluster_shader(int K, int K_stored, int vectors) {
    return glossy_header(K, K_stored, vectors, 0, false) +
           splice(kGlossyCommon, "// @transform_light", transform_light_source(K, K_stored)) +
           kClusterMain;
}
std::string glossy_vertex_shader(int K, int K_stored, int vectors, int block_vec4s,
                                 bool materials) {
    // CPCA: the products come from the cluster pass; no matrix is read here.
    const std::string transform =
        vectors == 0 ? transform_light_source(K, K_stored) : "void transform_light(uint base) {}\n";
    return glossy_header(K, K_stored, vectors, block_vec4s, materials) +
           splice(kGlossyCommon, "// @transform_light", transform) +
           splice(kVertexMain, "// @zonal_dot", zonal_dot_source(K));
}

}  // namespace shprt::gl
