// Writing meshes as PLY, the exchange format whose vertex order shprt keeps exactly.
#pragma once

#include "shprt/scene/mesh.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

// Writes `mesh` to `path` as binary little-endian PLY through AtomicFile (the target appears
// complete or not at all). Vertex properties: float x, y, z; float nx, ny, nz when the mesh has
// normals; uchar red, green, blue: `colours` when given (one per vertex), else the albedo encoded
// as 8-bit sRGB when the mesh has albedo. Faces: "list uchar uint vertex_indices". Vertex i of the
// file is vertex i of the mesh, so load_scene gives the same vertices back in the same order.
// A comment line records mesh.source. Throws Error(invalid_argument) when colours, normals or
// albedo have the wrong count, Error(io) when the file cannot be written.
void write_ply(const Mesh& mesh, const std::string& path,
               const std::vector<std::array<std::uint8_t, 3>>* colours = nullptr);

}  // namespace shprt
