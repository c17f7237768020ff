// Scene loading through Assimp (https://github.com/assimp/assimp), without vertex welding so a
// PLY file's vertex order survives (checked on Assimp 5.2.5; see DESIGN.md).
#include "shprt/scene/load.hpp"

#include "isolated_import.hpp"
#include "ply_header.hpp"
#include "shprt/core/colour.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/log.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/polygon.hpp"
#include "texture_albedo.hpp"

#include <assimp/DefaultIOSystem.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <optional>
#include <string_view>
#include <vector>

namespace shprt {
namespace {

using detail::check_off_header;
using detail::check_ply_header;
using detail::kMaxPlyHeader;
using detail::looks_like_ply;
using detail::PlyHeader;

constexpr std::string_view kBuiltinPrefix = "builtin:";
constexpr float kUnitSlack = 1e-6f;

// Reads the first bytes of a file (at most kMaxPlyHeader).
std::string file_prefix(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string buffer(kMaxPlyHeader, '\0');
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    buffer.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
    return buffer;
}

struct Instance {
    unsigned mesh;
    aiMatrix4x4 transform;
};

// Mesh instances of the node graph with their accumulated transforms, iteratively (no recursion
// depth limit on deep graphs), then ordered by mesh index (stable: node order within a mesh).
std::vector<Instance> collect_instances(const aiScene& scene) {
    std::vector<Instance> out;
    if (!scene.mRootNode) {
        for (unsigned m = 0; m < scene.mNumMeshes; ++m) out.push_back({m, aiMatrix4x4()});
        return out;
    }
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{
        {scene.mRootNode, scene.mRootNode->mTransformation}};
    std::size_t visited = 0;
    while (!stack.empty()) {
        auto [node, transform] = stack.back();
        stack.pop_back();
        if (++visited > 10'000'000) break;  // a cyclic graph from a corrupt file
        for (unsigned i = 0; i < node->mNumMeshes; ++i)
            if (node->mMeshes && node->mMeshes[i] < scene.mNumMeshes)
                out.push_back({node->mMeshes[i], transform});
        // Push children in reverse so they are visited in order.
        for (unsigned c = node->mNumChildren; c-- > 0;)
            if (node->mChildren && node->mChildren[c])
                stack.push_back(
                    {node->mChildren[c], transform * node->mChildren[c]->mTransformation});
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const Instance& a, const Instance& b) { return a.mesh < b.mesh; });
    return out;
}

// The material's diffuse colour, or the default grey (`found` says which).
Vec3f material_albedo(const aiScene& scene, const aiMesh& mesh, bool& found) {
    found = false;
    const Vec3f grey{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo};
    if (!scene.mMaterials || mesh.mMaterialIndex >= scene.mNumMaterials) return grey;
    const aiMaterial* material = scene.mMaterials[mesh.mMaterialIndex];
    if (!material) return grey;
    aiString name;
    if (material->Get(AI_MATKEY_NAME, name) == AI_SUCCESS &&
        std::strcmp(name.C_Str(), AI_DEFAULT_MATERIAL_NAME) == 0)
        return grey;  // Assimp's placeholder for files without materials
    aiColor4D c;
    if (aiGetMaterialColor(material, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
        aiGetMaterialColor(material, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS) {
        found = true;
        return {c.r, c.g, c.b};
    }
    return grey;
}

// A colour clamped into [0, 1] (non-finite channels to 0): what check_brdf accepts.
Vec3f unit_colour(float r, float g, float b) {
    const auto unit = [](float x) { return std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 0.0f; };
    return {unit(r), unit(g), unit(b)};
}

// The specular colour of a metallic-roughness material: white for a dielectric, its base colour
// factor for a metal, mixed by the metallic factor (glTF's own default metallic factor is 1).
// Textures are not sampled: the colour is the factors'.
Vec3f metallic_specular(const aiMaterial& material) {
    aiColor4D base(1, 1, 1, 1);
    if (aiGetMaterialColor(&material, AI_MATKEY_BASE_COLOR, &base) != AI_SUCCESS)
        aiGetMaterialColor(&material, AI_MATKEY_COLOR_DIFFUSE, &base);
    float metallic = 0;
    if (material.Get(AI_MATKEY_METALLIC_FACTOR, metallic) != AI_SUCCESS || !std::isfinite(metallic))
        metallic = 0;
    metallic = std::clamp(metallic, 0.0f, 1.0f);
    const auto mix = [metallic](float c) { return 1 - metallic + metallic * c; };
    return unit_colour(mix(base.r), mix(base.g), mix(base.b));
}

// The material's glossy lobe and its specular colour, or none:
//  * GGX with the material's roughness factor (glTF's metallic-roughness, and other PBR materials
//    Assimp reads), coloured by metallic_specular;
//  * else a Phong lobe with its shininess exponent (Blinn–Phong for a Blinn shading model) where
//    the exponent is positive (OBJ's Ns, Collada's and FBX's shininess), coloured by the
//    material's specular colour (OBJ's Ks) where it has one, else white.
// Parameters and colours are clamped into check_brdf's ranges.
std::optional<Brdf> material_brdf(const aiScene& scene, const aiMesh& mesh) {
    if (!scene.mMaterials || mesh.mMaterialIndex >= scene.mNumMaterials) return std::nullopt;
    const aiMaterial* material = scene.mMaterials[mesh.mMaterialIndex];
    if (!material) return std::nullopt;
    aiString name;
    if (material->Get(AI_MATKEY_NAME, name) == AI_SUCCESS &&
        std::strcmp(name.C_Str(), AI_DEFAULT_MATERIAL_NAME) == 0)
        return std::nullopt;
    float value = 0;
    if (material->Get(AI_MATKEY_ROUGHNESS_FACTOR, value) == AI_SUCCESS && std::isfinite(value))
        return Brdf{BrdfModel::ggx, std::clamp(double(value), kMinGgxRoughness, 1.0),
                    metallic_specular(*material)};
    if (material->Get(AI_MATKEY_SHININESS, value) == AI_SUCCESS && std::isfinite(value) &&
        value > 0) {
        int model = 0;
        const bool blinn = material->Get(AI_MATKEY_SHADING_MODEL, model) == AI_SUCCESS &&
                           model == aiShadingMode_Blinn;
        aiColor4D ks(1, 1, 1, 1);
        aiGetMaterialColor(material, AI_MATKEY_COLOR_SPECULAR, &ks);
        return Brdf{blinn ? BrdfModel::blinn_phong : BrdfModel::phong,
                    std::min(double(value), kMaxBrdfExponent), unit_colour(ks.r, ks.g, ks.b)};
    }
    return std::nullopt;
}

bool usable_normal(const aiVector3D& n) {
    return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) &&
           (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f);
}

// The importer's scene as arrays, in the child process of run_isolated_import: no logging, and
// only the checks that must happen before an index is read.
detail::ImportedMesh extract(const aiScene& scene, const std::string& path,
                             const PlyHeader* ply_header, int uv_set) {
    const bool is_ply = ply_header != nullptr;
    detail::ImportedMesh result;
    Mesh& out = result.mesh;
    std::vector<std::size_t> base(scene.mNumMeshes + 1, 0);
    for (unsigned m = 0; m < scene.mNumMeshes; ++m)
        base[m + 1] = base[m] + (scene.mMeshes[m] ? scene.mMeshes[m]->mNumVertices : 0);

    const PlyHeader ply = is_ply ? *ply_header : PlyHeader{};
    const bool srgb_colours = ply.colours_8bit;
    const bool use_material = !is_ply || ply.has_material;
    bool& all_normals = result.all_normals;
    std::uint64_t& skipped_faces = result.skipped_faces;
    std::vector<std::uint32_t> polygon;
    detail::AlbedoTextures textures(scene, path);
    bool all_uvs = true;  // every mesh has UV set `uv_set` (else no UVs are kept)
    // The arrays are reserved at their final size (the triangles' at one per face, what a
    // triangle mesh needs): grown by push_back they end up to twice that, and each doubling holds
    // the old and the new array at once (an 80 MB OBJ of 10 M faces makes 30 M vertices). Normals
    // and BRDF indices are stored only once a mesh has one: until then `out.normals` and
    // `out.brdf_index` stay empty and are filled in with the defaults when the first comes.
    const std::vector<Instance> instances = collect_instances(scene);
    {
        std::size_t vertices = 0, faces = 0;
        for (const Instance& inst : instances)
            if (const aiMesh* mesh = scene.mMeshes[inst.mesh]; mesh && mesh->mVertices) {
                vertices += mesh->mNumVertices;
                faces += mesh->mNumFaces;
            }
        vertices = std::min<std::size_t>(vertices, std::numeric_limits<std::uint32_t>::max());
        out.positions.reserve(vertices);
        out.albedo.reserve(vertices);
        out.source_vertex.reserve(vertices);
        out.triangles.reserve(faces);
    }
    bool any_normal = false, any_brdf = false;
    for (const Instance& inst : instances) {
        const aiMesh* mesh = scene.mMeshes[inst.mesh];
        if (!mesh || !mesh->mVertices || mesh->mNumVertices == 0) continue;
        const std::size_t first = out.positions.size();
        SHPRT_CHECK(first + mesh->mNumVertices <= std::numeric_limits<std::uint32_t>::max(), format,
                    "{}: more than 2^32 - 1 vertices", path);
        const auto offset = static_cast<std::uint32_t>(first);
        const aiMatrix4x4& m = inst.transform;
        aiMatrix3x3 normal_matrix(m);
        const float det = normal_matrix.Determinant();
        const bool singular = !(std::abs(det) > 0.0f) || !std::isfinite(det);
        if (!singular) normal_matrix.Inverse().Transpose();
        const bool mirrored = det < 0.0f;
        const bool identity = m == aiMatrix4x4();  // exact: identity keeps every bit

        bool from_material = false;
        const Vec3f flat = use_material ? material_albedo(scene, *mesh, from_material)
                                        : Vec3f{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo};
        // The material's BRDF, as an index into out.brdfs (each distinct BRDF once).
        std::uint32_t brdf = Mesh::kNoBrdf;
        if (const std::optional<Brdf> b =
                use_material ? material_brdf(scene, *mesh) : std::nullopt) {
            const auto found = std::find(out.brdfs.begin(), out.brdfs.end(), *b);
            brdf = static_cast<std::uint32_t>(found - out.brdfs.begin());
            if (found == out.brdfs.end()) out.brdfs.push_back(*b);
        }
        const aiColor4D* colours = mesh->mColors[0];
        const aiVector3D* uvs = mesh->mTextureCoords[uv_set];
        all_uvs = all_uvs && uvs != nullptr;
        // A colour texture, when there are no vertex colours and the mesh has the texture's UV
        // set (the material names it; it may differ from the set kept in Mesh::uvs).
        const detail::AlbedoTexture* texture = nullptr;
        const aiVector3D* texture_uvs = nullptr;
        Vec3f factor{1, 1, 1};
        if (!colours && use_material && scene.mMaterials &&
            mesh->mMaterialIndex < scene.mNumMaterials && scene.mMaterials[mesh->mMaterialIndex]) {
            unsigned texture_uv_set = 0;
            bool failed = false;
            texture = textures.find(*scene.mMaterials[mesh->mMaterialIndex], texture_uv_set, factor,
                                    failed);
            if (failed) result.albedo_sources |= detail::kAlbedoTextureUnreadable;
            texture_uvs = texture_uv_set < AI_MAX_NUMBER_OF_TEXTURECOORDS
                              ? mesh->mTextureCoords[texture_uv_set]
                              : nullptr;
            if (!texture_uvs) texture = nullptr;
        }
        result.albedo_sources |=
            colours   ? detail::kAlbedoVertexColours
            : texture ? detail::kAlbedoTexture
                      : (from_material ? detail::kAlbedoMaterial : detail::kAlbedoDefault);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D p = identity ? mesh->mVertices[v] : m * mesh->mVertices[v];
            out.positions.push_back({p.x, p.y, p.z});
            aiVector3D n = mesh->mNormals ? mesh->mNormals[v] : aiVector3D();
            if (!identity) n = singular ? aiVector3D() : normal_matrix * n;
            const bool usable = usable_normal(n);
            if (usable && !any_normal) {  // the first: the vertices before it get the default
                any_normal = true;
                out.normals.reserve(out.positions.capacity());
                out.normals.assign(out.positions.size() - 1, {0, 1, 0});
            }
            if (usable) {
                // Renormalise only what is visibly off unit length, so unit normals written by
                // write_ply come back bit for bit.
                if (std::abs(n.Length() - 1.0f) > kUnitSlack) n.Normalize();
                out.normals.push_back({n.x, n.y, n.z});
            } else {
                all_normals = false;
                if (any_normal) out.normals.push_back({0, 1, 0});
            }
            if (colours) {
                const aiColor4D& c = colours[v];
                out.albedo.push_back(srgb_colours ? Vec3f{srgb_to_linear(c.r), srgb_to_linear(c.g),
                                                          srgb_to_linear(c.b)}
                                                  : Vec3f{c.r, c.g, c.b});
            } else if (texture) {
                const Vec3f t = texture->sample(texture_uvs[v].x, texture_uvs[v].y);
                out.albedo.push_back({t.x * factor.x, t.y * factor.y, t.z * factor.z});
            } else {
                out.albedo.push_back(flat);
            }
            out.source_vertex.push_back(static_cast<std::uint32_t>(base[inst.mesh] + v));
            if (brdf != Mesh::kNoBrdf && !any_brdf) {
                any_brdf = true;
                out.brdf_index.reserve(out.positions.capacity());
                out.brdf_index.assign(out.positions.size() - 1, Mesh::kNoBrdf);
            }
            if (any_brdf) out.brdf_index.push_back(brdf);
            if (all_uvs) out.uvs.push_back({uvs[v].x, uvs[v].y});
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices < 3 || !face.mIndices) {
                ++skipped_faces;
                continue;
            }
            polygon.clear();
            for (unsigned c = 0; c < face.mNumIndices; ++c) {
                const unsigned i = face.mIndices[c];
                SHPRT_CHECK(i < mesh->mNumVertices, format,
                            "{}: face {} of mesh {} has vertex index {} out of range (the mesh has "
                            "{} vertices)",
                            path, f, inst.mesh, i, mesh->mNumVertices);
                polygon.push_back(offset + i);
            }
            const std::size_t first_triangle = out.triangles.size();
            triangulate_polygon(out.positions, polygon, out.triangles);
            if (mirrored)
                for (std::size_t t = first_triangle; t < out.triangles.size(); ++t)
                    std::swap(out.triangles[t][1], out.triangles[t][2]);
        }
    }
    if (!all_uvs) out.uvs.clear();
    // No vertex with a usable normal: none are sent, finish() computes them all.
    if (!any_normal) all_normals = false;
    result.files.insert(result.files.end(), textures.files().begin(), textures.files().end());
    return result;
}

// The rest of the conversion, in the caller's process: warnings, the checks, normals.
Mesh finish(detail::ImportedMesh imported, const std::string& path, const PlyHeader* ply_header) {
    const bool is_ply = ply_header != nullptr;
    const PlyHeader ply = is_ply ? *ply_header : PlyHeader{};
    Mesh out = std::move(imported.mesh);
    out.source = path;
    {
        std::string sources;
        const std::pair<std::uint8_t, const char*> names[] = {
            {detail::kAlbedoVertexColours, "vertex colours"},
            {detail::kAlbedoTexture, "diffuse texture"},
            {detail::kAlbedoMaterial, "material diffuse colour"},
            {detail::kAlbedoDefault, "default 0.8 grey"}};
        for (const auto& [bit, name] : names)
            if (imported.albedo_sources & bit)
                sources += (sources.empty() ? "" : " + ") + std::string(name);
        out.albedo_source = sources;
    }
    const std::uint64_t skipped = imported.skipped_faces;
    const std::string skipped_text =
        fmt::format("{} point or line primitive{}", skipped, skipped == 1 ? "" : "s");
    // A failure says everything in its one line: no warning before it.
    SHPRT_CHECK(!out.positions.empty() && !out.triangles.empty(), format,
                "{}: empty mesh (no triangles in the file{})", path,
                skipped > 0 ? "; skipped " + skipped_text : "");

    // PLY promises output vertex i = file vertex i; make sure the importer kept every vertex.
    SHPRT_CHECK(!is_ply || out.vertex_count() == ply.vertices, format,
                "{}: the importer returned {} vertices for the file's {}", path, out.vertex_count(),
                ply.vertices);
    validate_mesh(out, path);  // before normals: they need indices in range
    if (skipped > 0) log_warn("{}: skipped {}", path, skipped_text);
    if (imported.albedo_sources & detail::kAlbedoTextureUnreadable)
        log_warn(
            "{}: a material's colour texture could not be read (missing, corrupt, or larger "
            "than {} texels a side); the material's colour is used instead",
            path, detail::kMaxTextureSide);
    if (!imported.all_normals) {
        if (is_ply)
            compute_vertex_normals(out);
        else
            compute_vertex_normals_by_position(out);
    }
    return out;
}

// Assimp's file system, recording the name of every file an importer opens (the scene, its
// materials, external buffers): the files the scene reads, which no output may overwrite.
class RecordingIOSystem : public Assimp::DefaultIOSystem {
public:
    explicit RecordingIOSystem(std::vector<std::string>& opened) : m_opened(opened) {}
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        Assimp::IOStream* stream = DefaultIOSystem::Open(file, mode);
        if (stream != nullptr &&
            std::find(m_opened.begin(), m_opened.end(), file) == m_opened.end())
            m_opened.emplace_back(file);
        return stream;
    }

private:
    std::vector<std::string>& m_opened;
};

// Reads the file with Assimp and extracts its arrays (in the child process: see load_file).
detail::ImportedMesh import_with_assimp(const std::string& path, const std::string& ext,
                                        const PlyHeader* ply, int uv_set) {
    Assimp::Importer importer;
    std::vector<std::string> opened;
    importer.SetIOHandler(new RecordingIOSystem(opened));  // the importer owns and deletes it
    // Some importers invent a mesh to show a skeleton when a file has none; we want real geometry.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
    // No aiProcess_JoinIdenticalVertices (it would reorder PLY vertices), no normal generation
    // (ours are angle-weighted), no pre-transform (it merges meshes); validation catches
    // out-of-range indices before we read them.
    // Polygons are triangulated by triangulate_polygon: Assimp 5.2.5's aiProcess_Triangulate
    // aborts on an assertion for some truncated PLY files.
    const unsigned flags = aiProcess_ValidateDataStructure;
    const aiScene* scene = nullptr;
    try {
        scene = importer.ReadFile(path, flags);
    } catch (const std::exception& e) {
        fail(ErrorCode::format, "{}: cannot read the scene: {}", path, library_message(e.what()));
    } catch (...) {
        fail(ErrorCode::format, "{}: cannot read the scene (the importer failed)", path);
    }
    if (!scene) {
        std::string why = importer.GetErrorString();
        if (!why.empty() && why.back() == '\n') why.pop_back();
        // Assimp catches a failed allocation and reports it as text: the memory limit of the
        // importer child (run_isolated_import) was reached.
        if (why.find("bad_alloc") != std::string::npos) throw std::bad_alloc();
        SHPRT_CHECK(ext.empty() || importer.IsExtensionSupported(ext) ||
                        why.find("No suitable reader") == std::string::npos,
                    unsupported, "{}: unsupported format '{}'", path, ext);
        // Assimp's validator reports files without geometry in its own words.
        const bool empty = why.find("no faces") != std::string::npos ||
                           why.find("no vertices") != std::string::npos ||
                           why.find("least one mesh") != std::string::npos;
        SHPRT_CHECK(!empty, format, "{}: empty mesh ({})", path, library_message(why));
        fail(ErrorCode::format, "{}: cannot read the scene: {}", path,
             why.empty() ? "unknown importer error" : library_message(why));
    }
    SHPRT_CHECK(scene->mNumMeshes > 0 && scene->mMeshes, format, "{}: empty mesh (no geometry)",
                path);
    detail::ImportedMesh result = extract(*scene, path, ply, uv_set);
    result.files.insert(result.files.begin(), opened.begin(), opened.end());
    return result;
}

Mesh load_file(const std::string& path, int uv_set) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    SHPRT_CHECK(fs::exists(status), io, "{}: no such file", path);
    SHPRT_CHECK(!fs::is_directory(status), io, "{}: is a directory, not a scene file", path);
    {
        std::ifstream probe(path, std::ios::binary);
        SHPRT_CHECK(probe.good(), io, "{}: cannot open: {}", path, std::strerror(errno));
    }
    const auto size = fs::file_size(path, ec);
    SHPRT_CHECK(!ec && size > 0, format, "{}: empty file", path);

    const std::string ext = lower_extension(path);
    // Assimp 5.2.5 hangs or allocates without bound on some corrupt PLY headers, so check them
    // here (for .ply files and for anything Assimp would recognise as PLY by its first line).
    std::optional<PlyHeader> ply;
    // The same for the counts on an OFF file's first lines, which Assimp allocates before it reads
    // a vertex.
    const std::string prefix = file_prefix(path);
    if (ext == ".ply" || looks_like_ply(prefix)) ply = check_ply_header(path, prefix, size);
    if (ply && ply->unknown_lines > 0)
        log_warn("{}: PLY header line {}: '{}' is no PLY keyword; read as a comment{}", path,
                 ply->first_unknown_line, ply->first_unknown,
                 ply->unknown_lines > 1 ? fmt::format(" ({} such lines)", ply->unknown_lines) : "");
    check_off_header(path, prefix, size);
    // Assimp runs in a child process: a crash in one of its importers (fuzzing found a Collada
    // one) becomes an error naming the file, not the end of the program.
    const PlyHeader* ply_header = ply ? &*ply : nullptr;
    detail::ImportedMesh imported = detail::run_isolated_import(
        path, importer_memory_budget(size),
        [&] { return import_with_assimp(path, ext, ply_header, uv_set); },
        importer_time_limit(size));
    // The scene and every file its importer opened are inputs: no output may overwrite them.
    note_input_file(path);
    for (const std::string& file : imported.files) note_input_file(file);
    return finish(std::move(imported), path, ply_header);
}

}  // namespace

std::uint64_t importer_memory_budget(std::uint64_t file_bytes) {
    constexpr double kGiB = double(1ull << 30);
    if (const char* text = std::getenv("SHPRT_IMPORT_MEMORY_GIB"); text && *text) {
        double gib = 0;
        SHPRT_CHECK(parse_number(text, gib) && gib > 0 && gib <= 1 << 20, invalid_argument,
                    "SHPRT_IMPORT_MEMORY_GIB='{}': expected a positive number of GiB", text);
        return static_cast<std::uint64_t>(gib * kGiB);
    }
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    const std::uint64_t physical =
        pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : 0;
    const std::uint64_t floor = 2ull << 30;
    std::uint64_t budget =
        std::max<std::uint64_t>(floor, file_bytes > (~0ull >> 7) ? ~0ull : 64 * file_bytes);
    if (physical > 0) budget = std::min(budget, physical / 2);
    return budget;
}

unsigned importer_time_limit(std::uint64_t file_bytes) {
    if (const char* text = std::getenv("SHPRT_IMPORT_SECONDS"); text && *text) {
        double seconds = 0;
        SHPRT_CHECK(parse_number(text, seconds) && seconds >= 1 && seconds <= kMaxImportSeconds,
                    invalid_argument,
                    "SHPRT_IMPORT_SECONDS='{}': expected a number of seconds from 1 to {}", text,
                    kMaxImportSeconds);
        return static_cast<unsigned>(std::ceil(seconds));
    }
    const std::uint64_t per_file = kImportSecondsFloor + file_bytes / kImportBytesPerSecond;
    return static_cast<unsigned>(std::min<std::uint64_t>(per_file, kMaxImportSeconds));
}

bool is_builtin_spec(const std::string& spec) { return spec.rfind(kBuiltinPrefix, 0) == 0; }

Mesh load_scene(const std::string& spec, int uv_set) {
    SHPRT_CHECK(uv_set >= 0 && uv_set < AI_MAX_NUMBER_OF_TEXTURECOORDS, invalid_argument,
                "--uv-set {}: must be 0 to {}", uv_set, AI_MAX_NUMBER_OF_TEXTURECOORDS - 1);
    if (is_builtin_spec(spec)) {
        Mesh mesh = make_builtin(spec.substr(kBuiltinPrefix.size()));
        mesh.source = spec;
        mesh.albedo_source = "builtin scene colours";
        validate_mesh(mesh, spec);
        return mesh;
    }
    SHPRT_CHECK(!spec.empty(), invalid_argument, "scene path is empty");
    return load_file(spec, uv_set);
}

}  // namespace shprt
