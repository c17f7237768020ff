// glTF 2.0 binary (.glb) export: Khronos glTF 2.0 specification, §4.4 (GLB: a 12-byte header,
// a JSON chunk padded with spaces and a BIN chunk padded with zeros, both to 4 bytes), §3.6-3.7
// (buffer views and accessors; every vertex attribute here has its own tightly packed view, so no
// byteStride is needed), §3.11 (custom attributes start with an underscore), KHR_materials_unlit.
// Layout and conventions: include/shprt/shade/gltf_export.hpp.
#include "shprt/shade/gltf_export.hpp"

#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/shade/shade.hpp"
#include "shprt/shade/sun_shade.hpp"

#include "shade/sh_convention.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

namespace shprt {
namespace {

using Json = nlohmann::ordered_json;

// glTF enumerations (specification §5).
constexpr int kFloat = 5126, kShort = 5122, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kTriangles = 4;

// The BIN chunk and the JSON arrays describing it, built together.
struct GlbBuilder {
    std::vector<unsigned char> bin;
    Json buffer_views = Json::array(), accessors = Json::array();

    // Appends `bytes` as a new buffer view (4-byte aligned) and an accessor of `count` elements
    // of `type` over it; returns the accessor's index.
    int add(const void* bytes, std::size_t size, int target, int component, const char* type,
            std::size_t count, bool normalized = false) {
        while (bin.size() % 4 != 0) bin.push_back(0);
        const std::size_t offset = bin.size();
        bin.resize(offset + size);
        std::memcpy(bin.data() + offset, bytes, size);
        buffer_views.push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}, {"target", target}});
        Json a = {{"bufferView", buffer_views.size() - 1},
                  {"componentType", component},
                  {"count", count},
                  {"type", type}};
        if (normalized) a["normalized"] = true;
        accessors.push_back(std::move(a));
        return static_cast<int>(accessors.size() - 1);
    }
};

Json vec3_json(Vec3f v) { return Json::array({v.x, v.y, v.z}); }

void check_finite(const std::string& path, std::size_t v, Vec3f c, const char* what) {
    SHPRT_CHECK(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z), invalid_argument,
                "cannot write {}: vertex {} has a non-finite {}", path, v, what);
}

void append_u32(std::vector<unsigned char>& out, std::uint32_t x) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(x >> (8 * i)));
}

// Every check before the file exists; returns the K exported.
int check_exportable(const std::string& path, const Mesh& mesh, const TransferSet& transfer,
                     const GltfExportOptions& options) {
    check_shadable(mesh, transfer);
    {
        const std::uint32_t one = 1;
        unsigned char b;
        std::memcpy(&b, &one, 1);
        SHPRT_CHECK(b == 1, unsupported, "glTF export needs a little-endian host");
    }
    const int file_K = transfer.layout.K;
    SHPRT_CHECK(options.exposure > 0 && std::isfinite(options.exposure), invalid_argument,
                "exposure {}: must be positive", options.exposure);
    SHPRT_CHECK(options.K >= 0 && options.K <= file_K, invalid_argument,
                "cannot export {} coefficients: the file has K = {}", options.K, file_K);
    const int K = options.K > 0 ? options.K : file_K;
    SHPRT_CHECK(K <= kMaxLightK, invalid_argument,
                "cannot export K = {}: lights have at most {} coefficients ({} bands); export "
                "fewer bands",
                K, kMaxLightK, kMaxComputeBands);
    // TEXCOORD_n and COLOR_n may be float or unsigned normalized integers only: signed
    // coefficients in 16 bits need the custom attributes.
    SHPRT_CHECK(!options.half || options.attributes == GltfAttributes::custom, invalid_argument,
                "cannot write {}: 16-bit coefficients (--half) need the custom attributes; glTF's "
                "TEXCOORD_n and COLOR_n hold floats or unsigned integers, and coefficients are "
                "signed",
                path);
    const int floats = transfer.layout.channels * K;
    SHPRT_CHECK(options.attributes == GltfAttributes::custom ||
                    floats <= kStandardTexcoordFloats + 4 * kMaxStandardColors,
                invalid_argument,
                "cannot write {}: {} coefficients per vertex do not fit the standard attributes "
                "({} in TEXCOORD_0..7 and {} in COLOR_1..{}); export fewer bands",
                path, floats, kStandardTexcoordFloats, 4 * kMaxStandardColors, kMaxStandardColors);
    const std::size_t V = mesh.vertex_count();
    for (std::size_t v = 0; v < V; ++v)
        for (int c = 0; c < transfer.layout.channels; ++c) {
            const float* t = transfer.receiver(v, c);
            for (int i = 0; i < K; ++i)
                SHPRT_CHECK(std::isfinite(t[i]), invalid_argument,
                            "cannot write {}: vertex {} has a non-finite transfer coefficient",
                            path, v);
        }
    for (std::size_t v = 0; v < V; ++v) {
        check_finite(path, v, mesh.positions[v], "position");
        check_finite(path, v, mesh.normals[v], "normal");
        check_finite(path, v, mesh.albedo[v], "albedo");
    }
    return K;
}

// COLOR_0: exposure × the radiance under `light`, clamped to [0, 1]. glTF requires float colours
// in [0, 1] (the validator's ACCESSOR_NON_CLAMPED is an error), as a display without a tone map
// would show them; the exact radiance is what relighting with the transfer gives.
// With a sun kept out of the SH sum: the sky through the transfer plus the sun traced at every
// vertex (and its bounced light from T − T_0), what `shprt shade --sun` gives (sun_shade.hpp).
std::vector<Vec3f> baked_colours(const std::string& path, const Mesh& mesh,
                                 const TransferSet& transfer, const ShLight& light,
                                 const PreparedSun* sun, float exposure, std::size_t& clipped) {
    ShadeOptions shade_options;
    shade_options.K_used = light.K;
    const ShadeResult shaded =
        sun ? shade_with_sun(mesh, transfer, light, *sun, shade_options, SunShadeOptions{})
            : shade_vertices(mesh, transfer, light, shade_options);
    std::vector<Vec3f> colour(mesh.vertex_count());
    clipped = 0;
    const auto clamp01 = [](float x) { return std::clamp(x, 0.0f, 1.0f); };
    for (std::size_t v = 0; v < colour.size(); ++v) {
        check_finite(path, v, shaded.radiance[v], "colour (the light overflows float)");
        const Vec3f L = shaded.radiance[v] * exposure;
        colour[v] = {clamp01(L.x), clamp01(L.y), clamp01(L.z)};
        if (std::max({L.x, L.y, L.z}) > 1.0f) ++clipped;
    }
    return colour;
}

// POSITION (with its bounds), NORMAL, COLOR_0 and _SHPRT_ALBEDO.
Json add_geometry(GlbBuilder& glb, const Mesh& mesh, const std::vector<Vec3f>& colour) {
    const std::size_t V = mesh.vertex_count();
    Json attributes = Json::object();
    const int position =
        glb.add(mesh.positions.data(), V * sizeof(Vec3f), kArrayBuffer, kFloat, "VEC3", V);
    Vec3f lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
             std::numeric_limits<float>::max()};
    Vec3f hi = lo * -1.0f;
    for (const Vec3f p : mesh.positions) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    glb.accessors[position]["min"] = vec3_json(lo);  // POSITION must have min and max
    glb.accessors[position]["max"] = vec3_json(hi);
    attributes["POSITION"] = position;
    attributes["NORMAL"] =
        glb.add(mesh.normals.data(), V * sizeof(Vec3f), kArrayBuffer, kFloat, "VEC3", V);
    attributes["COLOR_0"] =
        glb.add(colour.data(), V * sizeof(Vec3f), kArrayBuffer, kFloat, "VEC3", V);
    attributes["_SHPRT_ALBEDO"] =
        glb.add(mesh.albedo.data(), V * sizeof(Vec3f), kArrayBuffer, kFloat, "VEC3", V);
    return attributes;
}

// _SHPRT_T<j>, float32 or 16-bit normalized with a scale per channel and coefficient; returns the
// scales (empty for float32).
Json add_custom_transfer(GlbBuilder& glb, Json& attributes, const TransferSet& transfer, int K,
                         bool half) {
    const std::size_t V = transfer.receiver_count();
    const int per_channel = (K + 3) / 4;  // VEC4 attributes per channel
    Json scales = Json::array();
    std::vector<float> f32(V * 4);
    std::vector<std::int16_t> i16(V * 4);
    for (int c = 0; c < transfer.layout.channels; ++c) {
        std::vector<double> scale(std::size_t(K), 1.0);
        if (half) {
            for (int i = 0; i < K; ++i) {
                double m = 0;
                for (std::size_t v = 0; v < V; ++v)
                    m = std::max(m, std::abs(double(transfer.receiver(v, c)[i])));
                // Rounded to float: the scale a reader sees in the JSON is the one used here.
                scale[i] = m > 0 ? double(static_cast<float>(m)) : 1.0;
            }
            scales.push_back(Json::array());
            for (int i = 0; i < K; ++i) scales.back().push_back(static_cast<float>(scale[i]));
        }
        for (int a = 0; a < per_channel; ++a) {
            for (std::size_t v = 0; v < V; ++v) {
                const float* t = transfer.receiver(v, c);
                for (int j = 0; j < 4; ++j) {
                    const int i = 4 * a + j;
                    const float x = i < K ? t[i] : 0.0f;
                    f32[4 * v + j] = x;
                    if (half) {
                        const double q = std::round(double(x) / scale[std::min(i, K - 1)] * 32767);
                        i16[4 * v + j] =
                            static_cast<std::int16_t>(std::clamp(q, -32767.0, 32767.0));
                    }
                }
            }
            const std::string name = "_SHPRT_T" + std::to_string(c * per_channel + a);
            attributes[name] =
                half ? glb.add(i16.data(), V * 4 * sizeof(std::int16_t), kArrayBuffer, kShort,
                               "VEC4", V, true)
                     : glb.add(f32.data(), V * 4 * sizeof(float), kArrayBuffer, kFloat, "VEC4", V);
        }
    }
    return scales;
}

// The standard attributes: the vertex's coefficients, channel after channel (n = channels·K
// floats), in TEXCOORD_0 … TEXCOORD_7 (two each), then COLOR_1 … (four each); float32, zeros past
// n. Returns the attribute names in order.
Json add_standard_transfer(GlbBuilder& glb, Json& attributes, const TransferSet& transfer, int K) {
    const std::size_t V = transfer.receiver_count();
    const int channels = transfer.layout.channels;
    const int n = channels * K;
    const auto coefficient = [&](std::size_t v, int f) {
        return f < n ? transfer.receiver(v, f / K)[f % K] : 0.0f;
    };
    Json names = Json::array();
    std::vector<float> values;
    for (int f = 0, set = 0; f < n; ++set) {
        const bool texcoord = f < kStandardTexcoordFloats;
        const int width = texcoord ? 2 : 4;
        values.assign(V * width, 0.0f);
        for (std::size_t v = 0; v < V; ++v)
            for (int j = 0; j < width; ++j) values[v * width + j] = coefficient(v, f + j);
        const std::string name = texcoord ? "TEXCOORD_" + std::to_string(set)
                                          : "COLOR_" + std::to_string(set - 7);  // COLOR_1 on
        attributes[name] = glb.add(values.data(), values.size() * sizeof(float), kArrayBuffer,
                                   kFloat, texcoord ? "VEC2" : "VEC4", V);
        names.push_back(name);
        f += width;
    }
    return names;
}

// The glTF node rotation that turns the light's local −Z (KHR_lights_punctual: a directional light
// shines along −Z) into −s, s the unit direction toward the sun: the rotation taking +Z to s, by
// acos(s_z) about +Z × s (about +X for s = −Z). Quaternion (x, y, z, w), glTF's order.
Json sun_node_rotation(Vec3d s) {
    const Vec3d axis{-s.y, s.x, 0.0};  // +Z × s
    const double sine = std::sqrt(axis.x * axis.x + axis.y * axis.y);
    const double angle = std::atan2(sine, s.z);
    if (sine < 1e-12) return s.z > 0 ? Json::array({0, 0, 0, 1}) : Json::array({1, 0, 0, 0});
    const double h = std::sin(angle / 2) / sine;
    return Json::array({axis.x * h, axis.y * h, 0.0, std::cos(angle / 2)});
}

// KHR_lights_punctual's light of the sun: colour = E / max(E) (glTF wants it in [0, 1]),
// intensity = max(E) in lux, E the disc's irradiance at normal incidence (sun_irradiance). The
// sky's coefficients are in the same radiometric unit (radiance·sr), so an engine lights with
// both as written: 1 unit of shprt irradiance = 1 lux (gltf_export.hpp).
Json sun_light_json(const Sun& sun) {
    const Vec3d E = sun_irradiance(sun);
    const double peak = std::max({E.x, E.y, E.z});
    const Vec3d colour = peak > 0 ? E / peak : Vec3d{1, 1, 1};
    return {{"type", "directional"},
            {"name", "sun"},
            {"color", Json::array({colour.x, colour.y, colour.z})},
            {"intensity", peak}};
}

// extras.shprt.sun: the sun as shprt models it, and what is and is not in the file.
Json sun_extras(const Sun& sun) {
    const Vec3d E = sun_irradiance(sun);
    return {{"direction", Json::array({sun.direction.x, sun.direction.y, sun.direction.z})},
            {"radius_deg", sun.radius_deg},
            {"radiance", Json::array({sun.radiance.x, sun.radiance.y, sun.radiance.z})},
            {"irradiance", Json::array({E.x, E.y, E.z})},
            {"solid_angle_sr", sun_solid_angle(sun)},
            {"light",
             "KHR_lights_punctual light 0 (node 1): directional, intensity = max "
             "irradiance in lux, color = irradiance / intensity"},
            {"sky", "light.coeffs hold the sky only: the sun is not in the SH sum"},
            {"color_0",
             "sky through the transfer + the sun traced at every vertex (and its "
             "bounced light for an interreflected bake), as shprt shade --sun"},
            {"direct",
             "E_sun = irradiance * max(0, n . direction) * visibility; radiance = "
             "albedo / pi * E_sun"}};
}

// extras.shprt: everything a relighting engine needs (gltf_export.hpp).
Json convention_block(const Mesh& mesh, const TransferSet& transfer, int K,
                      const GltfExportOptions& options, const ShLight& full, std::size_t clipped,
                      Json layout) {
    Json light_coeffs = Json::array();
    for (int c = 0; c < 3; ++c)
        light_coeffs.push_back(Json(std::vector<float>(full.channel(c), full.channel(c) + full.K)));
    const Camera camera = default_camera(mesh, 16.0f / 9.0f);
    const Vec3d ypr = options.light.yaw_pitch_roll_deg;
    return {
        {"format", "shprt-gltf"},
        {"version", 1},
        {"generator", std::string("shprt ") + SHPRT_VERSION_STRING},
        {"sh", detail::sh_convention_json()},
        {"K", K},
        {"bands", sh_bands_for(K)},
        {"full_bands", K == sh_count(sh_bands_for(K))},
        {"channels", transfer.layout.channels},
        {"transfer", to_string(transfer.kind)},
        {"sampler", to_string(transfer.sampler)},
        {"samples", transfer.samples},
        {"attributes", std::move(layout)},
        {"encoding", options.half ? "int16_normalized" : "float32"},
        {"radiometry",
         {{"irradiance",
           "E_c = sum_{i<K'} T_c[i] * L_c[i] (T_0 for every colour when channels = 1)"},
          {"radiance", "albedo_c / pi * E_c"},
          {"color_0",
           "exposure * linear radiance under `light` (K coefficients), clamped to "
           "[0, 1] (glTF colours)"},
          {"color_0_exposure", options.exposure},
          {"color_0_clipped_vertices", clipped},
          {"white_furnace",
           "a constant sky of radiance 1 has L[0] = sqrt(4 pi), E = pi unoccluded"}}},
        {"light",
         {{"specs",
           options.light.specs.empty() ? std::vector<std::string>{"builtin"} : options.light.specs},
          {"rotate_yaw_pitch_roll_deg", Json::array({ypr.x, ypr.y, ypr.z})},
          {"window", to_string(options.light.window)},
          {"K", full.K},
          {"coeffs", light_coeffs}}},
        {"camera",
         {{"eye", vec3_json(camera.eye)},
          {"target", vec3_json(camera.target)},
          {"fov_y_deg", camera.fov_y_deg},
          {"aspect", 16.0 / 9.0}}},
    };
}

// The GLB container (§4.4), written atomically.
void write_container(const std::string& path, const Json& gltf, std::vector<unsigned char>& bin) {
    std::string json = gltf.dump();
    while (json.size() % 4 != 0) json.push_back(' ');
    while (bin.size() % 4 != 0) bin.push_back(0);
    const std::uint64_t total = 12 + 8 + json.size() + 8 + bin.size();
    SHPRT_CHECK(total <= 0xffffffffu, invalid_argument,
                "cannot write {}: {} bytes exceed the 4 GiB a .glb can hold (export fewer bands "
                "or use --half)",
                path, total);
    std::vector<unsigned char> head;
    append_u32(head, 0x46546C67u);  // "glTF"
    append_u32(head, 2);
    append_u32(head, static_cast<std::uint32_t>(total));
    append_u32(head, static_cast<std::uint32_t>(json.size()));
    append_u32(head, 0x4E4F534Au);  // "JSON"
    AtomicFile out(path);
    out.write(head.data(), head.size());
    out.write(json);
    head.clear();
    append_u32(head, static_cast<std::uint32_t>(bin.size()));
    append_u32(head, 0x004E4942u);  // "BIN\0"
    out.write(head.data(), head.size());
    out.write(bin.data(), bin.size());
    out.commit();
}

}  // namespace

const char* to_string(GltfAttributes attributes) {
    return attributes == GltfAttributes::standard ? "standard" : "custom";
}

GltfAttributes parse_gltf_attributes(const std::string& name) {
    if (name == "custom") return GltfAttributes::custom;
    if (name == "standard") return GltfAttributes::standard;
    fail(ErrorCode::invalid_argument, "--attributes '{}': expected custom or standard", name);
}

void write_glb(const std::string& path, const Mesh& mesh, const TransferSet& transfer,
               const GltfExportOptions& options) {
    const int K = check_exportable(path, mesh, transfer, options);
    // The light: its full-band source turned by --rotate (what the extras carry, so a viewer can
    // rotate it further exactly), and the same cut to K for COLOR_0 — prepare_light's path.
    const ShLight source = light_source(options.light, K);
    const ShLight full = rotated_light(source, light_rotation(options.light), source.K);
    const ShLight light = rotated_light(full, Mat3d::identity(), K);
    // A --sun stays out of the SH sum (light_source never includes it): the file's light is the
    // sky, the sun a KHR_lights_punctual directional light beside it.
    std::optional<PreparedSun> sun;
    if (options.light.sun) sun = prepare_sun(options.light, K);
    std::size_t clipped = 0;
    const std::vector<Vec3f> colour = baked_colours(
        path, mesh, transfer, light, sun ? &*sun : nullptr, options.exposure, clipped);

    GlbBuilder glb;
    Json attributes = add_geometry(glb, mesh, colour);
    Json layout, scales;
    if (options.attributes == GltfAttributes::custom) {
        scales = add_custom_transfer(glb, attributes, transfer, K, options.half);
        layout = {{"prefix", "_SHPRT_T"},
                  {"per_channel", (K + 3) / 4},
                  {"layout",
                   "_SHPRT_T<c*per_channel + a> holds coefficients 4a..4a+3 of channel c "
                   "(0 beyond K)"},
                  {"albedo", "_SHPRT_ALBEDO"}};
    } else {
        layout = {{"standard", add_standard_transfer(glb, attributes, transfer, K)},
                  {"layout",
                   "the coefficients of channel 0, then channel 1, ... (channels * K floats), "
                   "two per TEXCOORD_n, then four per COLOR_n, in the order listed (0 beyond "
                   "channels * K)"},
                  {"albedo", "_SHPRT_ALBEDO"}};
    }
    const int indices =
        glb.add(mesh.triangles.data(), mesh.triangle_count() * 3 * 4, kElementArrayBuffer,
                kUnsignedInt, "SCALAR", mesh.triangle_count() * 3);
    // Index buffer views carry no byteStride; targets are given so loaders need not guess.
    Json shprt = convention_block(mesh, transfer, K, options, full, clipped, std::move(layout));
    if (sun) shprt["sun"] = sun_extras(sun->sun);
    if (options.half) {
        shprt["scale"] = scales;
        shprt["decode"] = "T_c[i] = max(q / 32767, -1) * scale[c][i] (what normalized SHORT gives)";
    }
    // The block sits on the primitive (three.js: geometry.userData), and on the mesh and the node,
    // where Blender's importer reads extras (custom properties).
    const Json extras = {{"shprt", shprt}};
    Json gltf = {
        {"asset",
         {{"version", "2.0"}, {"generator", std::string("shprt ") + SHPRT_VERSION_STRING}}},
        {"extensionsUsed", {"KHR_materials_unlit"}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}, {"name", "shprt"}, {"extras", extras}}}},
        {"materials",
         {{{"name", "baked (COLOR_0)"},
           {"pbrMetallicRoughness",
            {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
           {"doubleSided", true},
           {"extensions", {{"KHR_materials_unlit", Json::object()}}}}}},
        {"meshes",
         {{{"name", "shprt"},
           {"primitives",
            {{{"attributes", attributes},
              {"indices", indices},
              {"material", 0},
              {"mode", kTriangles},
              {"extras", extras}}}},
           {"extras", extras}}}},
        {"buffers", {{{"byteLength", glb.bin.size()}}}},
        {"bufferViews", glb.buffer_views},
        {"accessors", glb.accessors},
    };
    if (sun) {
        gltf["extensionsUsed"].push_back("KHR_lights_punctual");
        gltf["extensions"] = {{"KHR_lights_punctual", {{"lights", {sun_light_json(sun->sun)}}}}};
        gltf["nodes"].push_back({{"name", "sun"},
                                 {"rotation", sun_node_rotation(sun->sun.direction)},
                                 {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
        gltf["scenes"][0]["nodes"].push_back(1);
    }
    write_container(path, gltf, glb.bin);
}

}  // namespace shprt
