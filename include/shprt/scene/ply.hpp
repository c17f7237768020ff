// Writing meshes as PLY, the exchange format whose vertex order shprt keeps exactly. The one
// binary PLY writer: `shprt scene` writes meshes with it, `shprt shade` its per-vertex colours.
#pragma once

#include "shprt/scene/mesh.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace shprt {

// Writes `mesh` to `path` as binary little-endian PLY through AtomicFile (the target appears
// complete or not at all). Vertex properties: float x, y, z; float nx, ny, nz when the mesh has
// normals; uchar red, green, blue: `colours` when given (one per vertex, written as given), else
// the albedo encoded as 8-bit sRGB when the mesh has albedo; float s, t when the mesh has one UV
// per vertex (load_scene reads them back as UV set 0). Faces: "list uchar uint
// vertex_indices" — uint because Mesh indices are uint32 (no cast, no 2³¹ limit); PLY readers
// (Assimp, MeshLab, Blender, load_scene's header check) accept uint and int alike. Vertex i of the
// file is vertex i of the mesh, so load_scene gives the same vertices back in the same order.
// Comment lines record mesh.source and, when not empty, `comment` (one line; control characters
// become '?'), e.g. what the colours mean. Throws Error(invalid_argument) when colours, normals or
// albedo have the wrong count, Error(io) when the file cannot be written.
// `floats`: more per-vertex float properties, after the others, in order (each `values` holds
// one number per vertex), e.g. the exact shaded values beside display colours.
struct PlyFloatProperty {
    std::string name;
    std::vector<float> values;
};
void write_ply(const Mesh& mesh, const std::string& path,
               const std::vector<std::array<std::uint8_t, 3>>* colours = nullptr,
               std::string_view comment = {}, const std::vector<PlyFloatProperty>& floats = {});

}  // namespace shprt
