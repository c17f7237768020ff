// Private helpers of the OpenGL renderer: error checks, shader compilation, the GLSL sources.
#pragma once

namespace shprt::gl {

// Throws Error(unsupported) "OpenGL error 0x… in <what>" if glGetError reports one (and drains
// the error queue).
void check(const char* what);

// Compiles and links a vertex + fragment program; throws Error(unsupported) with the driver's
// info log, naming `name`, if either stage fails.
unsigned compile_program(const char* vertex_source, const char* fragment_source, const char* name);
// Compiles and links a compute program; throws as above.
unsigned compile_compute_program(const char* source, const char* name);

// GLSL 4.30 sources (gl_shaders.cpp).
extern const char* const kShadeComputeShader;        // per-vertex PRT shading (render/shade.hpp)
extern const char* const kSceneVertexShader;         // transforms; passes the vertex colour on
extern const char* const kSceneFragmentShader;       // writes the interpolated colour
extern const char* const kFullscreenVertexShader;    // one triangle covering the viewport
extern const char* const kBackgroundFragmentShader;  // equirect light texture along view rays
extern const char* const kPresentFragmentShader;     // resolve, exposure, ACES filmic, sRGB

// Uniform locations fixed with layout(location = N) in the shaders, shared with renderer.cpp.
namespace loc {
inline constexpr int kFirstVertex = 0, kEye = 1, kK = 2, kStrideK = 3, kChannels = 4,
                     kLightStride = 5, kDiffuseShare = 6, kView = 7, kMinCosEta = 8, kGlossy = 9,
                     kVertexCount = 10,
                     kLobe = 16;     // shading (compute) program
inline constexpr int kViewProj = 0;  // scene program
inline constexpr int kInvViewProj = 0, kBgEye = 1, kBgLightToTexture = 2;  // background
inline constexpr int kExposure = 0, kSamples = 1;                          // present program
}  // namespace loc

// Shader storage buffer bindings of the shading pass.
inline constexpr unsigned kTransferBinding = 0, kPositionBinding = 2, kNormalBinding = 3,
                          kAlbedoBinding = 4, kColorBinding = 5;
// Uniform block bindings of the shading pass, and the blocks' sizes in vec4s (the literal array
// sizes of kShadeComputeShader): the light, 3 channels × kMaxLightK padded floats; the recurrence
// table, two floats per (l, m) index of kMaxLightK.
inline constexpr unsigned kLightBlockBinding = 0, kRecurrenceBlockBinding = 1;
inline constexpr int kLightBlockVec4s = 768, kRecurrenceBlockVec4s = 512;

// Invocations per work group of the shading pass (local_size_x in the shader).
inline constexpr unsigned kShadeGroupSize = 64;

}  // namespace shprt::gl
