// Private helpers of the OpenGL renderer: error checks, shader compilation, the GLSL sources.
#pragma once

#include "shprt/render/renderer.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace shprt {
struct DrawSettings;
struct Mesh;
}  // namespace shprt

namespace shprt::gl {

// Throws Error(unsupported) "OpenGL error 0x… in <what>" if glGetError reports one (and drains
// the error queue).
void check(const char* what);

// Compiles and links a vertex + fragment program; throws Error(unsupported) with the driver's
// info log, naming `name`, if either stage fails.
unsigned compile_program(const char* vertex_source, const char* fragment_source, const char* name);
// Compiles and links a compute program; throws as above.
unsigned compile_compute_program(const char* source, const char* name);

// GLSL 4.30 sources (gl_shaders.cpp). The fragment shaders marked "// @output" write their
// colour through output_colour(), which fragment_shader() supplies.
extern const char* const kShadeComputeShader;        // per-vertex PRT shading (shade/shade.hpp)
extern const char* const kSceneVertexShader;         // transforms; passes the vertex colour on
extern const char* const kSceneFragmentShader;       // @output: the interpolated colour
extern const char* const kFullscreenVertexShader;    // one triangle covering the viewport
extern const char* const kBackgroundFragmentShader;  // @output: equirect light along view rays
// The present pass's fragment shader: resolve, exposure, ACES filmic, sRGB.
std::string present_shader();
// `source` (a fragment shader with a "// @output" line) writing linear radiance (display =
// false: into a float target), or (display = true) the code the present pass would write for it:
// radiance × the uniform at loc::kDisplayExposure, tone mapped and sRGB-encoded by the same GLSL
// as present_shader() — for drawing straight into an 8-bit display framebuffer. A "// @sun" line
// (after "// @output") gets the sun's direct light, sun_term (sun_pass.hpp), as `sun` says:
// none, a sun_term that returns 0 and reads nothing (the compiler drops the sun's varyings and
// taps: on llvmpipe a branch on a uniform does not skip the code it guards, so a program without
// a sun must not carry it); diffuse, the diffuse receivers' term (no BRDF lobes); full, every
// mode chosen by uniforms (SunPass::bind and bind_glossy). `filter`: the shadow filter's taps.
enum class SunCode { none, diffuse, full };
std::string fragment_shader(const char* source, bool display, SunCode sun = SunCode::full,
                            SunFilter filter = SunFilter::full);
// `source` with the line that holds `marker` replaced by `code`.
std::string splice(const std::string& source, const char* marker, const std::string& code);
// Glossy transfer matrices (gl_glossy_shaders.cpp), for K' coefficients of matrices stored
// K_stored wide: the per-cluster light products of a CPCA code with `vectors` basis matrices per
// cluster, and the per-vertex shading (shade/glossy.hpp) of raw matrices (vectors = 0) or of
// such a code, which reads the products through a uniform block of `block_vec4s` vec4s (0: from
// the storage buffer).
std::string glossy_cluster_shader(int K, int K_stored, int vectors);

// A new buffer object of `bytes` bytes, bound to `target`, holding `data` (or uninitialised
// storage when null), with the usage hint `usage` (GL_STATIC_DRAW, ...).
unsigned make_buffer(unsigned target, std::size_t bytes, const void* data, unsigned usage);
// Deletes `buffer` if it is a name (not 0) and sets it to 0.
void delete_buffer(unsigned& buffer);
// A width × height 2D texture of one level in `internal_format` (GL_RGBA32F, a depth format...),
// nearest filtering, clamped to the edge; left unbound.
unsigned make_texture_2d(int width, int height, unsigned internal_format);
// The constants of sh_eval_k's recurrence (sh/basis.hpp) for every (l, m ≥ 0), l < bands, two
// floats each at flat index l(l+1)+m: the shading shader's recurrence block.
std::vector<float> recurrence_table(int bands);

// The element buffer of a mesh's draws (bound to the current vertex array): its own triangle
// list, then, where draw_orders_fit, the kDrawOrderCount front-to-back orders of
// render/draw_order.hpp. `lists` is set to how many lists it holds (1 or 1 + kDrawOrderCount).
unsigned upload_draw_orders(const Mesh& mesh, int& lists);
// The byte offset, for glDrawElements, of the list to draw with `settings`: the order nearest
// the camera's view when settings.front_to_back and the buffer has orders; else the mesh's.
const void* draw_order_offset(int lists, std::size_t index_count, const DrawSettings& settings);
// `materials`: the BRDF lobe per vertex from the lobe block (kBrdfIndexBinding,
// kLobeBlockBinding), else the kBrdfLobe uniform for every vertex.
std::string glossy_vertex_shader(int K, int K_stored, int vectors, int block_vec4s, bool materials);

// Uniform locations fixed with layout(location = N) in the shaders, shared with renderer.cpp.
namespace loc {
inline constexpr int kFirstVertex = 0, kEye = 1, kK = 2, kStrideK = 3, kChannels = 4,
                     kLightStride = 5, kDiffuseShare = 6, kView = 7, kMinCosEta = 8, kGlossy = 9,
                     kVertexCount = 10,
                     kLobe = 16;     // shading (compute) program
inline constexpr int kViewProj = 0;  // scene program
inline constexpr int kInvViewProj = 0, kBgEye = 1, kBgLightToTexture = 2;  // background
inline constexpr int kExposure = 0, kSamples = 1;                          // present program
// Fragment programs drawn straight to a display (fragment_shader(…, true)): scene, background,
// texel pass.
inline constexpr int kDisplayExposure = 15;
// Glossy matrix passes: kFirstVertex, kEye, kLightStride, kDiffuseShare, kView and
// kVertexCount as above (the cluster pass reads its product count at kVertexCount's location),
// and these.
inline constexpr int kClusterStride = 11, kAlbedoOverride = 12, kSpecular = 13, kBrdfLobe = 16,
                     kCosineLobe = 24;
}  // namespace loc

// Shader storage buffer bindings of the shading pass.
inline constexpr unsigned kTransferBinding = 0, kPositionBinding = 2, kNormalBinding = 3,
                          kAlbedoBinding = 4, kColorBinding = 5;
// ... and of the glossy matrix passes (kTransferBinding holds the packed matrices).
inline constexpr unsigned kClusterLightBinding = 1, kClusterBinding = 6, kWeightBinding = 7,
                          kClusterVertexBinding = 8,
                          kBrdfIndexBinding = 9;  // per vertex, its BRDF's entry in the lobe block
// Uniform block bindings of the shading pass (and, at 2, of a CPCA dispatch's cluster products),
// and the blocks' sizes in vec4s (the literal array
// sizes of kShadeComputeShader): the light, 3 channels × kMaxLightK padded floats; the recurrence
// table, two floats per (l, m) index of kMaxLightK.
inline constexpr unsigned kLightBlockBinding = 0, kRecurrenceBlockBinding = 1,
                          kClusterLightBlockBinding = 2, kLobeBlockBinding = 3;
// The glossy vertex pass's lobe block (per-material BRDFs): kLobeVec4sPerBrdf vec4s per BRDF (8
// band factors, then the specular colour in xyz), kLobeBlockVec4s in all (16 KiB, the smallest
// GL_MAX_UNIFORM_BLOCK_SIZE).
inline constexpr int kLobeVec4sPerBrdf = 3, kLobeBlockVec4s = 1024;
inline constexpr int kLightBlockVec4s = 768, kRecurrenceBlockVec4s = 512;
// The light's uniform block: per channel, K coefficients padded to a multiple of 4.
inline int light_stride(int K) { return (K + 3) / 4 * 4; }
inline constexpr int kLightBlockBytes = kLightBlockVec4s * 16;

// Invocations per work group of the shading pass (local_size_x in the shader).
inline constexpr unsigned kShadeGroupSize = 64;

}  // namespace shprt::gl
