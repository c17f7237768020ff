// glTF 2.0 export of a baked scene (`shprt export F.shprt -o scene.glb`): one binary .glb with
// the mesh, its colours baked under a light, and the transfer coefficients as custom vertex
// attributes, so that any engine can show the baked light at once and relight it with its own.
//
// The primitive (one mesh, one node, one scene; vertices in the .shprt file's order):
//
//   POSITION, NORMAL    float VEC3 (NORMAL unit length, as the file stores it)
//   COLOR_0             float VEC3: the linear outgoing radiance L = albedo/π · E under the light
//                       (shade/shade.hpp, shade_vertices, pure diffuse, the first K
//                       coefficients) times `exposure`, clamped to [0, 1] — glTF allows float
//                       colours only in [0, 1], so brighter values are clipped as a display
//                       without a tone map would clip them (extras count the clipped vertices);
//                       the exact radiance is what relighting from the transfer gives
//   _SHPRT_ALBEDO       float VEC3: the diffuse albedo ρ in [0, 1] (what relighting needs)
//   _SHPRT_T<j>         VEC4, j = c·A + a with A = ceil(K/4) attributes per channel: coefficients
//                       4a … 4a+3 of channel c (coefficients at K and beyond are 0)
//   indices             unsigned int, counter-clockwise triangles
//   material            KHR_materials_unlit, white base colour: viewers show COLOR_0 as is
//
// Encodings of the transfer (`--half`): float32, or — glTF 2.0 has no 16-bit float component
// type — 16-bit signed normalized integers (componentType SHORT, normalized: true, decoded by
// every glTF reader to max(q/32767, −1)) with one scale per channel and coefficient:
// c_T = decoded · scale[c][i], scale = the largest |c_T| of that coefficient over the vertices.
// The error is at most scale/65534 per coefficient (≈ 1.5e-5 of the largest value, smaller than
// float16's 4.9e-4 relative), at half the size of float32.
//
// `extras.shprt` (on the primitive, the mesh and the node: three.js reads the primitive's into
// geometry.userData, Blender the mesh's and the node's as custom properties) describes everything a
// relighting engine needs (three.js puts it in geometry.userData.shprt): the SH convention (real SH
// of Green 2003 with the Condon–Shortley phase, index l(l+1)+m, θ from +Z, φ from +X toward +Y, +Y
// up), K, bands, channels, the attribute layout and encoding with its scales, the radiometry (E =
// Σ_i c_T,i · c_L,i is irradiance; radiance = albedo/π · E), the transfer kind and sampling, the
// light of COLOR_0 (its full-band coefficients as 3 lists, already rotated and windowed, so that an
// engine may rotate it further exactly before cutting it to K), and the camera `shprt render` uses
// by default. web/ (the browser viewer) relights from exactly this.
//
// A sun kept out of the SH sum (`--sun`, LightSetup::sun; shade/sun_shade.hpp) is written as a
// KHR_lights_punctual directional light on a second node "sun", whose rotation turns the light's
// −Z (the direction it shines along) into −s, s the unit direction toward the sun after --rotate;
// colour = E / max(E) and intensity = max(E) in lux, E the disc's irradiance at normal incidence
// (sun_irradiance). shprt's light is in relative radiometric units (radiance, and irradiance =
// radiance·sr): the file takes 1 unit of irradiance as 1 lux, the unit of the sky's coefficients
// too, so an engine that lights with both as written keeps their ratio (three.js:
// DirectionalLight.intensity is that lux, and a Lambertian surface of albedo ρ sends ρ/π·E, as
// here). The sun is not in the SH sum: extras.shprt.light is the sky alone, so a viewer that adds
// the directional light counts the sun once; extras.shprt.sun repeats it in shprt's terms.
// COLOR_0 is then the sky plus the sun traced at every vertex (shade_with_sun, as `shprt shade
// --sun`; with an interreflected bake, the sun's bounced light too). The material stays unlit, so
// viewers that show COLOR_0 do not add the light a second time.
#pragma once

#include "shprt/light/light_setup.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <string>

namespace shprt {

// Where the transfer goes (`--attributes`): the custom _SHPRT_T<j> above, or standard attributes:
// the vertex's channels·K coefficients in order, two per TEXCOORD_0 … TEXCOORD_7, then four per
// COLOR_1, COLOR_2, … (float32; extras.shprt.attributes.standard lists them; glTF wants each
// semantic's indices to start at 0 and run on, and COLOR_0 is the baked colour). Measured
// (tests/engines/check_gltf_engines.py, docs/web.md "Engines"): three.js keeps both; Blender 3.4
// drops the custom ones and keeps TEXCOORD_0…7 exactly as UV maps (16 floats: one channel up to
// K = 16, three channels up to K = 5), COLOR_n only as 8-bit colours; gltfpack 0.18 keeps neither.
enum class GltfAttributes { custom, standard };
inline constexpr int kStandardTexcoordFloats = 16;  // TEXCOORD_0 … TEXCOORD_7, two floats each
inline constexpr int kMaxStandardColors = 64;       // COLOR_1 … COLOR_64, four floats each
const char* to_string(GltfAttributes attributes);
// "custom" or "standard"; Error(invalid_argument) naming --attributes.
GltfAttributes parse_gltf_attributes(const std::string& name);

struct GltfExportOptions {
    int K = 0;          // export the first K coefficients; 0 = all of the transfer's
    bool half = false;  // transfer as 16-bit normalized integers with scales (above)
    GltfAttributes attributes = GltfAttributes::custom;
    LightSetup light;       // the light of COLOR_0 and extras.shprt.light (light/light_setup.hpp)
    float exposure = 1.0f;  // COLOR_0 = clamp(exposure · L, 0, 1); > 0
};

// Writes `path` (.glb) atomically (AtomicFile: on any error no file is left). Checks, before the
// file is created: exposure > 0, check_shadable(mesh, transfer) (vertex transfer vectors, normals,
// albedo; Error(invalid_argument) or Error(unsupported) for transfer matrices), 0 ≤ options.K ≤
// transfer.layout.K and K ≤ kMaxLightK (Error(invalid_argument)), half only with the custom
// attributes and channels·K within the standard attributes' room, finite coefficients and
// colours (Error(invalid_argument) naming the vertex); throws what light_source throws for a bad
// light, and with a sun what shade_with_sun throws. CPU only (the shading is shade_vertices, or
// shade_with_sun with its Embree trace).
void write_glb(const std::string& path, const Mesh& mesh, const TransferSet& transfer,
               const GltfExportOptions& options);

}  // namespace shprt
