// Content hash of a mesh (FNV-1a 64: Fowler, Noll, Vo; public-domain reference at
// isthe.com/chongo/tech/comp/fnv).
#include "shprt/io/hash.hpp"

#include <fmt/format.h>

#include <bit>

namespace shprt {

static_assert(std::endian::native == std::endian::little, "mesh_hash hashes little-endian bytes");
static_assert(sizeof(Vec3f) == 12 && sizeof(std::array<std::uint32_t, 3>) == 12,
              "mesh arrays must be tightly packed");

std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t state) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
        state ^= p[i];
        state *= 0x100000001b3ull;
    }
    return state;
}

std::uint64_t mesh_hash(const Mesh& mesh) {
    const std::uint64_t counts[2] = {mesh.positions.size(), mesh.triangles.size()};
    std::uint64_t h = fnv1a64(counts, sizeof counts);
    h = fnv1a64(mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f), h);
    h = fnv1a64(mesh.normals.data(), mesh.normals.size() * sizeof(Vec3f), h);
    h = fnv1a64(mesh.albedo.data(), mesh.albedo.size() * sizeof(Vec3f), h);
    h = fnv1a64(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]), h);
    return h;
}

std::string format_mesh_hash(std::uint64_t hash) { return fmt::format("fnv1a64:{:016x}", hash); }

}  // namespace shprt
