// Content hashes recorded in .shprt files: the scene hash ties a transfer file to the exact mesh
// it was baked for, so shading code can refuse a mismatched pair.
#pragma once

#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace shprt {

// 64-bit FNV-1a (offset basis 0xcbf29ce484222325, prime 0x100000001b3) over `size` bytes,
// continuing from `state` (pass the previous result to hash data in pieces).
std::uint64_t fnv1a64(const void* data, std::size_t size,
                      std::uint64_t state = 0xcbf29ce484222325ull);

// Stable content hash of a mesh: FNV-1a 64 over, in this order, the vertex count V and the
// triangle count T as little-endian uint64, then the little-endian bytes of positions (V·3
// float32), normals (V·3 float32), albedo (V·3 float32) and triangles (T·3 uint32). Exactly the
// bytes the .shprt sections hold, so any reader can recompute it. The source path and
// source_vertex are not hashed (the same geometry loaded from two paths hashes the same).
std::uint64_t mesh_hash(const Mesh& mesh);

// "fnv1a64:" followed by 16 lower-case hex digits, the form stored in the file's metadata.
std::string format_mesh_hash(std::uint64_t hash);

}  // namespace shprt
