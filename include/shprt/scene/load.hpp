// Loading scenes: mesh files through Assimp, or built-in scenes by name.
#pragma once

#include "shprt/scene/mesh.hpp"

#include <cstdint>
#include <string>

namespace shprt {

// Loads a scene. `spec` is either "builtin:NAME" (see builtin.hpp) or a file path in any format
// Assimp reads (tested: OBJ, PLY, STL, glTF, Collada; also GLB, FBX, 3DS and the rest).
//
// What the file gives becomes one Mesh, in world space:
//   * every mesh instance of the node graph, with its node's accumulated transform applied to
//     positions and (inverse-transpose) to normals; a mirroring transform also flips the winding
//     so counter-clockwise stays the front face. Meshes come in Assimp's mesh order; instances of
//     one mesh follow in node-graph order;
//   * vertices are never welded or split. PLY keeps its vertex order exactly: output vertex i is
//     the file's vertex i, unused vertices included; Mesh::source_vertex is then the identity.
//     For other formats source_vertex[i] is the index in Assimp's order across its meshes
//     (mesh m's vertices follow those of meshes 0..m-1);
//   * polygons are triangulated by triangulate_polygon (a convex polygon becomes the fan from its
//     first corner); points and lines are skipped (counted in a log_warn);
//   * normals from the file where every vertex has a finite non-zero one; otherwise all are
//     recomputed, area- and angle-weighted (compute_vertex_normals for PLY, whose indexing is the
//     author's; compute_vertex_normals_by_position for other formats, whose importers duplicate
//     vertices per corner);
//   * albedo from the first vertex-colour set (8-bit PLY colours are decoded from sRGB; float
//     colours are taken as linear), else the material's base colour or diffuse texture sampled
//     at the vertex's UV (sRGB texels made linear, bilinear, times the material's colour factor;
//     files next to the model or embedded in it: src/scene/texture_albedo.hpp; a texture that
//     cannot be read gives one warning and the material's colour), else the material's base or
//     diffuse colour, else kDefaultAlbedo grey (also for Assimp's placeholder material);
//     Mesh::albedo_source says which;
//   * glossy BRDFs from the materials (Mesh::brdfs, brdf_index): GGX with the material's
//     roughness factor (glTF's metallic-roughness), else Phong with its shininess exponent
//     (Blinn–Phong for a Blinn shading model) where that is positive (OBJ's Ns); a material with
//     neither gives none (kNoBrdf), and so does Assimp's placeholder;
//   * texture coordinates: UV set `uv_set` (Assimp's mTextureCoords[uv_set], its u and v) when
//     every mesh of the file has that set, else none (Mesh::uvs empty);
//   * the result passes validate_mesh (degenerate triangles dropped with a warning).
// PLY headers are checked strictly before Assimp sees them (Assimp 5.2.5 hangs or allocates
// without bound on some corrupt ones). The counts on an OFF file's first lines are checked
// against the file's size too: Assimp allocates them before it reads a vertex (its own
// invalid/OutOfMemory.off claims 3.5e11 vertices in 309 bytes). Assimp itself runs in a child
// process (fork; see src/scene/isolated_import.hpp): a crafted corrupt file can crash its importers
// (fuzzing found a Collada one; see assimp issues #6507, #6443), and such a crash becomes
// Error(format) naming the file and the signal instead of ending the program. The child's memory is
// bounded by importer_memory_budget (below): a file that needs more (a corrupt count that no header
// check catches: a binary PLY face claiming a list of 4e9 indices) gives Error(out_of_memory)
// "PATH: the importer needed more than N GiB of memory ..." instead of taking the machine's memory.
// Nothing the importer prints reaches stdout or stderr. Mesh::source is `spec`. Throws shprt::Error
// whose message starts with the path and names the problem: Error(io) for a missing or unreadable
// file, Error(unsupported) for a format Assimp does not know, Error(format) for a file it cannot
// parse, an empty mesh, NaN/Inf coordinates or out-of-range indices; Error(invalid_argument) for an
// unknown built-in name.
Mesh load_scene(const std::string& spec, int uv_set = 0);

// How much memory (bytes of address space) the importer child may use to read a file of
// `file_bytes` bytes. The environment variable SHPRT_IMPORT_MEMORY_GIB, when set, gives it in GiB
// (a positive number, e.g. 0.5 or 16; Error(invalid_argument) otherwise). By default it is
// 64 x the file's size, at least 2 GiB, at most half of the machine's physical memory: Assimp
// takes about 10 to 40 times a mesh file's size (an 80 MB OBJ of 10 M faces takes 2.5 GB), the
// floor leaves room for the buffers and textures a small glTF or OBJ file refers to, and the cap
// keeps a corrupt file from pushing the machine into swap or the OOM killer.
std::uint64_t importer_memory_budget(std::uint64_t file_bytes);

// How long the importer child may take to read a file of `file_bytes` bytes: seconds of CPU time
// (and 3 times as many of wall-clock time, for a child that waits rather than computes); past
// that it is ended and load_scene throws Error(format) "PATH: the importer took more than N s of
// CPU time reading this file ...". The environment variable SHPRT_IMPORT_SECONDS, when set, gives
// it (a number from 1 to kMaxImportSeconds; Error(invalid_argument) otherwise). By default it is
// kImportSecondsFloor plus one second per kImportBytesPerSecond bytes of file: Assimp reads every
// model of its own test corpus (Debian's assimp-testmodels, 595 files) in under 0.6 s of CPU time,
// and an 80 MB OBJ of 10 M faces in about 15 s (its limit: 90 s), while a corrupt count that
// makes Assimp run on (a one-byte change to a corpus LWS file ran 67 s) stops at 10 s.
inline constexpr unsigned kImportSecondsFloor = 10;
inline constexpr std::uint64_t kImportBytesPerSecond = 1'000'000;
inline constexpr unsigned kMaxImportSeconds = 1'000'000;
unsigned importer_time_limit(std::uint64_t file_bytes);

// True when `spec` names a built-in scene ("builtin:" prefix).
bool is_builtin_spec(const std::string& spec);

}  // namespace shprt
